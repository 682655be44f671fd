#!/usr/bin/env bash
# Installs the Debian 12 packages leanfade needs, only those missing, and the web example's npm
# packages from its lockfile (examples/web: three.js at the pinned version). Idempotent.
# Uses sudo only when not root. Set LEANFADE_EXTRA_PACKAGES to add more.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake ninja-build pkg-config git
  libglm-dev libpng-dev libtinyexr-dev libstb-dev libcli11-dev nlohmann-json3-dev
  libtinyobjloader-dev libssl-dev libzstd-dev libepoxy-dev libegl-dev libegl-mesa0 libgl1-mesa-dri libgbm1
  libglfw3-dev libimgui-dev glslang-tools xvfb xauth libglx-mesa0 gnuplot-nox
  libgtest-dev libgmock-dev libbenchmark-dev
  libsquish-dev libastcenc-dev
  libopenimageio-dev libtinygltf-dev spirv-cross libspirv-cross-c-shared-dev glslang-dev
  spirv-tools mesa-vulkan-drivers libvulkan-dev vulkan-validationlayers
  chromium
  pybind11-dev python3-dev python3-numpy python3-distributed
)
# Node.js and npm for the WebGL2 example's server and its three.js, unless the machine already
# has them (another Node.js installation conflicts with Debian's packages).
command -v node >/dev/null 2>&1 || packages+=(nodejs)
command -v npm >/dev/null 2>&1 || packages+=(npm)
# shellcheck disable=SC2206
packages+=(${LEANFADE_EXTRA_PACKAGES:-})

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
if ((${#missing[@]} > 0)); then
  echo "install-deps: installing ${missing[*]}"
  sudo_cmd=()
  if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# The web example's packages, exactly as its lockfile pins them, when missing or another version.
web=examples/web
wanted=$(node -p "require('./$web/package-lock.json').packages['node_modules/three'].version")
have=$(node -p "try { require('./$web/node_modules/three/package.json').version } catch { '' }")
if [[ "$have" != "$wanted" ]]; then
  echo "install-deps: npm ci in $web (three $wanted)"
  (cd "$web" && npm ci --no-audit --no-fund --loglevel=error)
fi

# The Node.js scripts' packages (tools/node: naga-wasm for WGSL, ktx2-encoder and ktx-parse for
# Basis Universal; wgsl_reflect for the tests), as their lockfile pins them.
node_tools=tools/node
for package in naga-wasm ktx2-encoder ktx-parse wgsl_reflect; do
  wanted=$(node -p "require('./$node_tools/package-lock.json').packages['node_modules/$package'].version")
  have=$(node -p "try { require('./$node_tools/node_modules/$package/package.json').version } catch { '' }")
  if [[ "$have" != "$wanted" ]]; then
    echo "install-deps: npm ci in $node_tools ($package $wanted)"
    (cd "$node_tools" && npm ci --no-audit --no-fund --loglevel=error)
    break
  fi
done
