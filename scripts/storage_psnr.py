#!/usr/bin/env python3
"""PSNR of the default storage against the 32f bake, on renders of every corpus map.

For each map of bake_off.py's CORPUS that is installed: `leanfade bake` it with each --bits value
asked for (default: auto, the default storage) and with --bits 32f, render the sphere with LEAN and two-lobe at 1.5 and 16
radii from each (`leanfade render --cells DIR --cell-format pfm`), and compare the cells: PSNR in dB
over the linear colours clamped to [0, 1], as the tests' storage checks measure it. Writes
OUT/storage_psnr.{csv,json,md} (docs/results.md §9).

Usage: scripts/storage_psnr.py [--leanfade build/tools/leanfade/leanfade] [--out out/storage_psnr]
                               [--bits 16,16f,auto] [--maps TAG,...]
The table has the lowest PSNR over the cells of each map for each --bits value (with auto, the
storage it chose).
"""
import argparse
import math
import os
import struct
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bake_off import CORPUS, write_rows  # noqa: E402


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        channels = 3 if kind == b"PF" else 1
        data = f.read(width * height * channels * 4)
    values = struct.unpack(("<" if scale < 0 else ">") + "f" * (width * height * channels), data)
    return values


def cells(leanfade, lean_map, folder, flags):
    subprocess.run([leanfade, "render", "--scene", "sphere", "--techniques", "lean,two-lobe",
                    "--distances", "1.5,16", "--size", "192x192", "--bumps", lean_map,
                    "--cells", folder, "--cell-format", "pfm", "-o", folder + ".png"] + flags,
                   check=True, stdout=subprocess.DEVNULL,
                   env=dict(os.environ, EGL_PLATFORM="surfaceless"))
    return {name: read_pfm(os.path.join(folder, name))
            for name in sorted(os.listdir(folder)) if name.endswith(".pfm")}


def psnr(a, b):
    total = 0.0
    for x, y in zip(a, b):
        d = min(max(x, 0.0), 1.0) - min(max(y, 0.0), 1.0)
        total += d * d
    return float("inf") if total == 0.0 else 10.0 * math.log10(len(a) / total)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--leanfade", default="build/tools/leanfade/leanfade")
    parser.add_argument("--out", default="out/storage_psnr")
    parser.add_argument("--bits", default="auto",
                        help="comma-separated --bits values compared with 32f (e.g. 16,16f,auto)")
    parser.add_argument("--maps", default="", help="comma-separated corpus tags (default: all)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    requested = [b for b in args.bits.split(",") if b]
    wanted = set(t for t in args.maps.split(",") if t)
    rows = []
    for tag, package, path, flags in CORPUS:
        if not os.path.exists(path) or (wanted and tag not in wanted):
            continue
        bake_flags = [f for f in flags if f != "--directx"]
        if "--directx" in flags:
            bake_flags.append("--directx")
        storages = {}
        for bits in ["32f"] + requested:
            lean_map = os.path.join(args.out, f"{tag}_{bits}.ktx2")
            baked = subprocess.run([args.leanfade, "bake", path, "--bits", bits, "-o", lean_map] +
                                   bake_flags, check=True, capture_output=True, text=True).stdout
            storage = baked.split("storage ")[1].split()[0] if "storage " in baked else "?"
            storages[bits] = (storage, cells(args.leanfade, lean_map,
                                             os.path.join(args.out, f"{tag}_{bits}"), []))
        _, float_cells = storages["32f"]
        for bits in requested:
            storage, bits_cells = storages[bits]
            for name in bits_cells:
                rows.append({"map": tag, "package": package, "bits": bits, "storage": storage,
                             "cell": name[:-4],
                             "psnr_db": round(psnr(bits_cells[name], float_cells[name]), 2)})
        print(tag, " ".join(f"{b}:{min(r['psnr_db'] for r in rows if r['map'] == tag and r['bits'] == b)}"
                            for b in requested), file=sys.stderr)
    write_rows(rows, os.path.join(args.out, "storage_psnr"))
    with open(os.path.join(args.out, "storage_psnr.md"), "w") as f:
        f.write("| map | package | " + " | ".join(f"`--bits {b}`" for b in requested) +
                " |\n|---|---|" + "---|" * len(requested) + "\n")
        for tag in dict.fromkeys(r["map"] for r in rows):
            cells_text = []
            for bits in requested:
                mine = [r for r in rows if r["map"] == tag and r["bits"] == bits]
                low = min(mine, key=lambda r: r["psnr_db"])
                chosen = f" ({mine[0]['storage']})" if bits == "auto" else ""
                cells_text.append(f"{low['psnr_db']:.1f}{chosen}")
            package = next(r["package"] for r in rows if r["map"] == tag)
            f.write(f"| {tag} | {package} | " + " | ".join(cells_text) + " |\n")
    print(os.path.join(args.out, "storage_psnr.md"))


if __name__ == "__main__":
    main()
