#!/usr/bin/env python3
"""Batch throughput (docs/perf.md, "Batches"): COUNT maps of SIZE^2 baked by
`python3 -m leanfade.batch` on its local Dask cluster (2 worker processes, a fresh 8 GiB cache) against
`xargs -P2 leanfade bake` on the same maps with the same (default) settings; then the batch's
rerun of the unchanged manifest and with its outputs removed (served from the cache).

    PYTHONPATH=build/python python3 bench/batch_throughput.py --leanfade build/tools/leanfade/leanfade

Prints a table and writes OUT.json and OUT.csv (default out/bench/batch). The maps are 8-bit
height and normal maps made from seeded noise and waves (half each), written once and reused.
"""
import argparse
import csv
import json
import os
import platform
import shutil
import subprocess
import sys
import time

import numpy as np

import leanfade


def make_maps(folder, count, size):
    os.makedirs(folder, exist_ok=True)
    names = []
    y, x = np.mgrid[0:size, 0:size] / size
    for i in range(count):
        name = os.path.join(folder, f"map{i:04d}.png")
        names.append(name)
        if os.path.exists(name):
            continue
        rng = np.random.default_rng(i)
        h = 0.5 + 0.2 * np.sin(2 * np.pi * (i % 7 + 1) * x + i) * np.cos(2 * np.pi * 3 * y)
        h += 0.05 * rng.random((size, size))
        if i % 2:
            gy, gx = np.gradient(h * 50)
            n = np.stack([-gx, gy, np.ones_like(h)], axis=-1)
            n /= np.linalg.norm(n, axis=-1, keepdims=True)
            image = np.round((0.5 * n + 0.5) * 255).astype(np.uint8)
        else:
            image = np.round(np.clip(h, 0, 1) * 255).astype(np.uint8)
        leanfade.write_image(name, image)
    return names


def timed(command, **kwargs):
    start = time.monotonic()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, **kwargs)
    return time.monotonic() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--leanfade", default="build/tools/leanfade/leanfade")
    parser.add_argument("--count", type=int, default=200)
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--work", default="out/bench/batch-work", help="scratch folder")
    parser.add_argument("--out", default="out/bench/batch", help="OUT.json and OUT.csv")
    args = parser.parse_args()
    work = os.path.abspath(args.work)
    inputs = make_maps(os.path.join(work, "in"), args.count, args.size)
    for sub in ("xargs", "batch", "cache"):
        shutil.rmtree(os.path.join(work, sub), ignore_errors=True)
        os.makedirs(os.path.join(work, sub))

    # xargs -P WORKERS leanfade bake IN -o OUT, one process per map.
    listing = "".join(f"{name}\0{os.path.join(work, 'xargs', os.path.basename(name))}.ktx2\0"
                      for name in inputs)
    xargs = timed(["xargs", "-0", "-n", "2", "-P", str(args.workers), "sh", "-c",
                   f'exec "$0" bake "$1" -o "$2"', os.path.abspath(args.leanfade)],
                  input=listing.encode())

    manifest = os.path.join(work, "manifest.jsonl")
    with open(manifest, "w") as f:
        for name in inputs:
            f.write(json.dumps({"input": os.path.relpath(name, work),
                                "output": f"batch/{os.path.basename(name)}.ktx2"}) + "\n")
    # A cache large enough for the set (5.3 GB at 200 x 1024^2), so that the last rerun is
    # served from it whole (leanfade's default bound, 2 GiB, would keep the newest 40 %).
    batch = [sys.executable, "-m", "leanfade.batch", manifest, "--workers", str(args.workers),
             "--cache", os.path.join(work, "cache"), "--cache-gib", "8"]
    first = timed(batch)
    rerun = timed(batch)
    for name in os.listdir(os.path.join(work, "batch")):
        os.remove(os.path.join(work, "batch", name))
    from_cache = timed(batch)
    same = all(open(os.path.join(work, "xargs", os.path.basename(n) + ".ktx2"), "rb").read() ==
               open(os.path.join(work, "batch", os.path.basename(n) + ".ktx2"), "rb").read()
               for n in inputs)

    rows = [
        ("xargs -P%d leanfade bake" % args.workers, xargs, 1.0),
        ("leanfade.batch, local cluster, cold cache", first, first / xargs),
        ("leanfade.batch rerun, outputs there", rerun, rerun / xargs),
        ("leanfade.batch rerun, outputs removed", from_cache, from_cache / xargs),
    ]
    machine = f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores"
    print(f"{args.count} maps of {args.size}^2 (8-bit, half height, half normal), "
          f"{args.workers} workers, {machine}")
    print(f"{'run':46} {'seconds':>8} {'maps/s':>8} {'vs xargs':>9}")
    for name, seconds, ratio in rows:
        print(f"{name:46} {seconds:8.2f} {args.count / seconds:8.1f} {ratio:9.2f}")
    print("outputs byte-identical to the CLI's:", "yes" if same else "NO")
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    record = {"maps": args.count, "size": args.size, "workers": args.workers, "cores":
              os.cpu_count(), "identical_outputs": same,
              "runs": [{"run": n, "seconds": s, "ratio_to_xargs": r} for n, s, r in rows]}
    with open(args.out + ".json", "w") as f:
        json.dump(record, f, indent=2)
        f.write("\n")
    with open(args.out + ".csv", "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["run", "seconds", "ratio_to_xargs"])
        for name, seconds, ratio in rows:
            writer.writerow([name, f"{seconds:.3f}", f"{ratio:.3f}"])
    print(f"written to {args.out}.json and {args.out}.csv")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
