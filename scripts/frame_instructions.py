#!/usr/bin/env python3
"""Instructions per pixel of each technique's frame on Mesa's llvmpipe, counted by callgrind.

A frame time on a shared CPU machine moves with the load; the instructions a frame executes do
not. For each technique this runs `leanfade bench` (the sphere filling a 256 x 192 frame, no
floor, no near/mid/far views) under `valgrind --tool=callgrind` with `LP_NUM_THREADS=0`, so that
llvmpipe rasterises in the calling thread, and counts only the benchmark's view loop. It runs
with 2 and with 6 timed frames and divides the difference by 4 frames and the frame's pixels,
which removes everything counted once (upload, the coverage probe). Program compilation is
counted in whichever run finds Mesa's shader cache without the program: the 2-frame run is made
before and after the 6-frame one and the smaller count kept, so that neither kept run compiles.

Writes OUT.csv and OUT.json (technique, instructions per pixel, ratio to the first technique)
and prints the table. Takes about a minute per technique.

Usage: scripts/frame_instructions.py [--leanfade build/tools/leanfade/leanfade]
                                     [--techniques lean,two-lobe] [--out out/frame_instructions]
                                     [-- extra bench flags, e.g. --geometric-aa off]
"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys

WIDTH, HEIGHT = 256, 192


def bench(leanfade, technique, frames, warmup, extra):
    """Instructions callgrind counts in `leanfade bench`'s view loop."""
    command = ["valgrind", "--tool=callgrind", "--collect-atstart=no",
               "--toggle-collect=*run_view*", "--callgrind-out-file=/dev/null"]
    command += [leanfade, "bench", "--scenes", "sphere", "--techniques", technique, "--size",
                f"{WIDTH}x{HEIGHT}", "--distances", "none", "--no-floor", "--frames", str(frames),
                "--warmup", str(warmup), "--timing", "cpu"] + extra
    env = dict(os.environ, EGL_PLATFORM="surfaceless", LP_NUM_THREADS="0")
    result = subprocess.run(command, env=env, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"frame_instructions.py: {' '.join(command)} failed:\n{result.stderr[-2000:]}")
    match = re.search(r"Collected : (\d+)", result.stderr)
    if not match:
        sys.exit("frame_instructions.py: callgrind printed no count")
    return int(match.group(1))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--leanfade", default="build/tools/leanfade/leanfade")
    parser.add_argument("--techniques", default="lean,two-lobe")
    parser.add_argument("--out", default="out/frame_instructions")
    parser.add_argument("extra", nargs="*", help="further `leanfade bench` flags (after --)")
    args = parser.parse_args()
    rows = []
    for technique in args.techniques.split(","):
        # The 2-frame count twice, the least kept: a run that compiled a program is the larger.
        two = bench(args.leanfade, technique, 2, 1, args.extra)
        six = bench(args.leanfade, technique, 6, 1, args.extra)
        two = min(two, bench(args.leanfade, technique, 2, 1, args.extra))
        per_pixel = (six - two) / 4 / (WIDTH * HEIGHT)
        rows.append({"technique": technique, "instructions_per_pixel": round(per_pixel, 1)})
        print(f"{technique}: {per_pixel:.0f} instructions per pixel", file=sys.stderr, flush=True)
    for row in rows:
        row["ratio"] = round(row["instructions_per_pixel"] / rows[0]["instructions_per_pixel"], 3)
    os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)
    with open(args.out + ".json", "w") as f:
        json.dump({"bench_flags": args.extra, "frame": f"{WIDTH}x{HEIGHT}", "rows": rows}, f,
                  indent=1)
    with open(args.out + ".csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)
    print(f"| technique | instructions per pixel | / {rows[0]['technique']} |")
    print("|---|---|---|")
    for row in rows:
        print(f"| {row['technique']} | {row['instructions_per_pixel']:.0f} | {row['ratio']:.3f} |")


if __name__ == "__main__":
    main()
