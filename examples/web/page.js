// What the example pages share: their query (?data=URL&map=NAME&size=N&capture=CELLS) and
// fetching a file as bytes.
export function pageParams(defaultSize = 256, largest = 1024) {
  const params = new URLSearchParams(location.search);
  return {
    params,
    dataUrl: params.get('data') ?? 'data',
    mapName: params.get('map') ?? 'bumps',
    size: Math.min(largest, Math.max(16, Number(params.get('size') ?? defaultSize))),
    capture: params.get('capture'),
  };
}

export async function fetchBytes(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: ${response.status} ${response.statusText}`);
  return response.arrayBuffer();
}
