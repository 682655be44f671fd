#!/usr/bin/env python3
"""The shape of each corpus map's slope distribution against LEAN's Gaussian (docs/results.md §9,
"Why the natural maps miss").

Every map of the real-map corpus (scripts/bake_off.py CORPUS) is baked to a 32-bit float LEAN
map (`leanfade bake --bits 32f --plateau-epsilon 0`), and the slopes B of its finest level are
read back from the KTX2 file (layer lean2, rg = B / sc with sc = 1). Per map:

- E|B|^2: the mean squared slope;
- centre / Gaussian: the density of the slopes within r = 0.05 of their mean, over the density
  of LEAN's Gaussian (the same mean and covariance) at the mean: what the far plane near its
  mirror direction sees, where every pixel's footprint holds the whole map;
- kurtosis k = E|B - mu|^4 / ((tr S)^2 + 2 tr S^2): 1 for a Gaussian of any covariance S, over the
  whole map and as the median over 64 x 64 texel blocks (a footprint at middle distance);
- t peak: the centre / Gaussian ratio that a Student-t of the same covariance and kurtosis has,
  nu / (nu - 2) with nu = (4k - 2) / (k - 1) (at most nu = 4.2, the heaviest tail whose kurtosis
  exists): the reach of a lobe fitted from one more linear moment, E|B|^4;
- with --eval, LEAN's energy on the plane near its mirror direction (s = 1024, 1.5 and 16 radii)
  against the truth shaded with the bump normal's Blinn-Phong and against the truth shaded with
  LEAN's own lobe per sample (`eval --reference-model lean`): their ratio is LEAN's model
  mismatch, LEAN against its own truth its filtering error.

Usage: scripts/slope_shape.py [--leanfade build/tools/leanfade/leanfade] [--out out/slope_shape]
                              [--only TAG,...] [--eval]
Writes slope_shape.{csv,json,md} in --out. Pure Python 3 (no NumPy): about 20 s a map.
"""
import argparse
import csv
import json
import math
import os
import struct
import subprocess
import sys
from array import array

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bake_off import CORPUS  # noqa: E402

RADIUS = 0.05   # slope units: the centre's disc
BLOCK = 64      # texels: the blocks of the middle-distance kurtosis
MAX_NU = 4.2


def bake_flags(eval_flags):
    """The bake's flags of a corpus map's eval flags (--directx, --from, --strength)."""
    return list(eval_flags)


def read_lean2_level0(path):
    """(width, height, B as two arrays of floats) of a 32f KTX2 LEAN map's finest level."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:12] != b"\xabKTX 20\xbb\r\n\x1a\n":
        raise SystemExit(f"{path}: not a KTX2 file")
    vk_format, type_size, width, height, depth, layers, faces, levels, scheme = struct.unpack_from(
        "<9I", data, 12)
    if vk_format != 109 or scheme != 0:  # VK_FORMAT_R32G32B32A32_SFLOAT, no supercompression
        raise SystemExit(f"{path}: expected an uncompressed RGBA32F map (vkFormat {vk_format})")
    offset, length, _ = struct.unpack_from("<3Q", data, 80)
    texels = width * height
    lean2 = array("f")
    lean2.frombytes(data[offset + texels * 16: offset + texels * 32])
    if sys.byteorder != "little":
        lean2.byteswap()
    return width, height, lean2[0::4], lean2[1::4]


def kurtosis(n, s_x, s_y, s_xx, s_yy, s_xy, s_r2x, s_r2y, s_r4):
    """k of the slopes with the sums given (n texels): 1 for a Gaussian; nan when flat."""
    mx, my = s_x / n, s_y / n
    mxx, myy, mxy = s_xx / n, s_yy / n, s_xy / n
    sxx, syy, sxy = mxx - mx * mx, myy - my * my, mxy - mx * my
    trace = sxx + syy
    denominator = trace * trace + 2.0 * (sxx * sxx + syy * syy + 2.0 * sxy * sxy)
    if denominator <= 1e-20:
        return float("nan")
    mm = mx * mx + my * my
    central4 = (s_r4 / n - 4.0 * (s_r2x * mx + s_r2y * my) / n
                + 4.0 * (mx * mx * mxx + my * my * myy + 2.0 * mx * my * mxy)
                + 2.0 * (mxx + myy) * mm - 3.0 * mm * mm)
    return central4 / denominator


def t_peak(k):
    """nu / (nu - 2) of the Student-t whose kurtosis is k (nu at least MAX_NU); 1 for k <= 1."""
    if not k > 1.0:
        return 1.0
    nu = max((4.0 * k - 2.0) / (k - 1.0), MAX_NU)
    return nu / (nu - 2.0)


def shape(width, height, bx, by):
    """The statistics of one map's slopes (module docstring)."""
    n = width * height
    sums = [0.0] * 8
    blocks_x, blocks_y = width // BLOCK, height // BLOCK
    block_sums = [[0.0] * 8 for _ in range(blocks_x * blocks_y)]
    for row in range(height):
        block_row = row // BLOCK
        base = row * width
        for column in range(width):
            x = bx[base + column]
            y = by[base + column]
            r2 = x * x + y * y
            values = (x, y, x * x, y * y, x * y, r2 * x, r2 * y, r2 * r2)
            if block_row < blocks_y and column // BLOCK < blocks_x:
                b = block_sums[block_row * blocks_x + column // BLOCK]
                for i in range(8):
                    b[i] += values[i]
            for i in range(8):
                sums[i] += values[i]
    k_map = kurtosis(n, *sums)
    k_blocks = sorted(k for k in (kurtosis(BLOCK * BLOCK, *b) for b in block_sums)
                      if not math.isnan(k))
    k_block = k_blocks[len(k_blocks) // 2] if k_blocks else float("nan")
    mx, my = sums[0] / n, sums[1] / n
    sxx, syy, sxy = sums[2] / n - mx * mx, sums[3] / n - my * my, sums[4] / n - mx * my
    det = sxx * syy - sxy * sxy
    inside = sum(1 for i in range(n) if (bx[i] - mx) ** 2 + (by[i] - my) ** 2 < RADIUS * RADIUS)
    centre = inside / n / (math.pi * RADIUS * RADIUS)
    gaussian = 1.0 / (2.0 * math.pi * math.sqrt(det)) if det > 0 else float("inf")
    return {
        "mean_squared_slope": (sums[2] + sums[3]) / n,
        "centre_over_gaussian": centre / gaussian,
        "kurtosis": k_map,
        "kurtosis_64_median": k_block,
        "t_peak": t_peak(k_map),
    }


def lean_energy(leanfade, path, flags, model, folder):
    """LEAN's energy_total at 1.5 and 16 radii, s = 1024, plane near its mirror direction."""
    out = os.path.join(folder, f"eval_{model}")
    subprocess.run([leanfade, "eval", "--scene", "plane", "--view-dir", "0,0.3,1", "--light-dir",
                    "0,0.35,-1", "--distances", "1.5,16", "--shininess", "1024", "--frames", "2",
                    "--techniques", "lean", "--reference-model", model, "--bumps", path,
                    "--out", out] + flags, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "results.csv"), newline="") as f:
        return {float(r["distance"]): float(r["energy_total"]) for r in csv.DictReader(f)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--leanfade", default="build/tools/leanfade/leanfade")
    parser.add_argument("--out", default="out/slope_shape")
    parser.add_argument("--only", default="")
    parser.add_argument("--eval", action="store_true")
    args = parser.parse_args()
    only = set(filter(None, args.only.split(",")))
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for tag, package, path, flags in CORPUS:
        if (only and tag not in only) or not os.path.exists(path):
            continue
        folder = os.path.join(args.out, tag)
        os.makedirs(folder, exist_ok=True)
        ktx2 = os.path.join(folder, "map.ktx2")
        # Uncompressed levels: this script reads the file's bytes itself.
        subprocess.run([args.leanfade, "bake", path, "--bits", "32f", "--plateau-epsilon", "0",
                        "--supercompression", "none", "-o", ktx2] + bake_flags(flags), check=True, stdout=subprocess.DEVNULL)
        row = {"map": tag, "package": package}
        row.update(shape(*read_lean2_level0(ktx2)))
        if args.eval:
            baseline = lean_energy(args.leanfade, path, flags, "baseline", folder)
            own = lean_energy(args.leanfade, path, flags, "lean", folder)
            for d in (1.5, 16.0):
                row[f"lean_vs_truth_{d:g}"] = baseline[d]
                row[f"lean_vs_own_truth_{d:g}"] = own[d]
                row[f"model_mismatch_{d:g}"] = baseline[d] / own[d]
        rows.append(row)
        print(f"{tag}: " + ", ".join(f"{k} {v:.3g}" for k, v in row.items()
                                      if isinstance(v, float)), flush=True)
    if not rows:
        raise SystemExit("slope_shape: no corpus map installed (docs/results.md §9)")
    keys = list(rows[0].keys())
    with open(os.path.join(args.out, "slope_shape.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=keys)
        writer.writeheader()
        writer.writerows(rows)
    with open(os.path.join(args.out, "slope_shape.json"), "w") as f:
        json.dump(rows, f, indent=1)
    with open(os.path.join(args.out, "slope_shape.md"), "w") as f:
        f.write("| " + " | ".join(keys) + " |\n|" + "---|" * len(keys) + "\n")
        for row in rows:
            f.write("| " + " | ".join(v if isinstance(v, str) else f"{v:.3g}"
                                      for v in row.values()) + " |\n")
    print(f"slope_shape: {len(rows)} maps, {args.out}/slope_shape.{{csv,json,md}}")


if __name__ == "__main__":
    main()
