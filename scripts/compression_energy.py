#!/usr/bin/env python3
"""What block compression of the roughness MIPs does to a render's specular energy.

For real maps of the corpus (scripts/bake_off.py's CORPUS), the roughness chain that
`bake --roughness-out` writes at the base roughness of Blinn-Phong exponent s (r0 = (2/s)^(1/4)),
uncompressed and decoded from `--compress bc` (BC4) and `--compress astc` (ASTC 4x4), is given to
`leanfade eval --techniques roughness --roughness-mips` (the engine's roughness MIPs technique), and
its energy against the supersampled truth is compared across the three. Writes OUT/results.{csv,json,md}.

  scripts/compression_energy.py [--maps brick01,ground010] [--out out/compression_energy]
"""
import argparse
import csv
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bake_off import CORPUS, CORPUS_VIEWS  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--leanfade", default="build/tools/leanfade/leanfade")
    parser.add_argument("--tool", default="build/bench/leanfade_compression_error")
    parser.add_argument("--out", default="out/compression_energy")
    parser.add_argument("--maps", default="brick01,ground010")
    parser.add_argument("--views", default="plane,teapot")
    parser.add_argument("--shininess", type=float, default=1024.0)
    args = parser.parse_args()
    tags = args.maps.split(",")
    views = [v for v in CORPUS_VIEWS if v[0] in args.views.split(",")]
    r0 = (2.0 / args.shininess) ** 0.25
    levels = os.path.join(args.out, "levels")
    rows = []
    for tag, _, path, flags in CORPUS:
        if tag not in tags or not os.path.exists(path):
            continue
        kind = "--height" if "height" in flags else "--normal"
        subprocess.run([args.tool, "--out", os.path.join(args.out, "texels"), "--levels-out", levels,
                        "--roughness", f"{r0:.6f}", kind, path], check=True, stdout=subprocess.DEVNULL)
        stem = os.path.splitext(os.path.basename(path))[0]
        for view, view_flags in views:
            for compression in ("none", "bc", "astc"):
                folder = os.path.join(args.out, f"{tag}_{view}_{compression}")
                command = [args.leanfade, "eval"] + view_flags + [
                    "--bumps", path, "--techniques", "roughness", "--shininess", f"{args.shininess:g}",
                    "--roughness-mips", os.path.join(levels, f"{stem}.{compression}_0.png"),
                    "--out", folder] + flags
                print(" ".join(command), file=sys.stderr, flush=True)
                subprocess.run(command, check=True, stdout=subprocess.DEVNULL,
                               env=dict(os.environ, EGL_PLATFORM="surfaceless"))
                with open(os.path.join(folder, "results.json")) as f:
                    for case in json.load(f)["cases"]:
                        rows.append({"map": tag, "view": view, "compression": compression,
                                     "distance": case["distance"],
                                     "energy_total": case.get("energy_total"),
                                     "reference_energy_error": case.get("reference_energy_error")})
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(rows, f, indent=1)
    with open(os.path.join(args.out, "results.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)
    # One line per (map, view, distance): energy_total of none, bc, astc and the ratios.
    table = {}
    for r in rows:
        table.setdefault((r["map"], r["view"], r["distance"]), {})[r["compression"]] = r["energy_total"]
    lines = ["| map | view | distance | none | bc | astc | bc / none | astc / none |",
             "|---|---|---|---|---|---|---|---|"]
    for (tag, view, distance), e in table.items():
        n, b, a = e.get("none"), e.get("bc"), e.get("astc")
        ratio = lambda x: f"{x / n:.3f}" if x is not None and n else "-"  # noqa: E731
        fmt = lambda x: f"{x:.3f}" if x is not None else "-"  # noqa: E731
        lines.append(f"| {tag} | {view} | {distance:g} | {fmt(n)} | {fmt(b)} | {fmt(a)} | "
                     f"{ratio(b)} | {ratio(a)} |")
    with open(os.path.join(args.out, "results.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
