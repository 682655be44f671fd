#!/usr/bin/env python3
"""LEAN map file sizes of every storage, with and without Zstandard, on the corpus maps.

For each installed map of bake_off.py's CORPUS: `leanfade bake` with --bits 8, 16, 16f and auto,
each with --supercompression zstd (the default) and none, and the file's bytes; the ratio is
against the former default file (--bits auto --supercompression none). With
docs/data/corpus/storage_psnr (the renders' PSNR of each storage against 32f) this is the study
of a compact layout in docs/ktx2.md, "Supercompression". Writes OUT/storage_sizes.{csv,json,md}.

Usage: scripts/storage_sizes.py [--leanfade build/tools/leanfade/leanfade] [--out out/storage_sizes]
"""
import argparse
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bake_off import CORPUS, write_rows  # noqa: E402

STORAGES = ["8", "16", "16f", "auto"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--leanfade", default="build/tools/leanfade/leanfade")
    parser.add_argument("--out", default="out/storage_sizes")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for tag, package, path, flags in CORPUS:
            if not os.path.exists(path):
                continue
            bake_flags = flags
            sizes = {}
            for bits in STORAGES:
                for scheme in ("zstd", "none"):
                    out = os.path.join(folder, f"{tag}.{bits}.{scheme}.ktx2")
                    summary = subprocess.run(
                        [args.leanfade, "bake", path, "--bits", bits, "--supercompression", scheme,
                         "-o", out] + bake_flags, check=True, capture_output=True, text=True).stdout
                    sizes[(bits, scheme)] = os.path.getsize(out)
                    os.remove(out)
            base = sizes[("auto", "none")]
            for (bits, scheme), size in sizes.items():
                rows.append({"map": tag, "package": package, "bits": bits,
                             "supercompression": scheme, "bytes": size,
                             "ratio": round(size / base, 4)})
            print(tag, " ".join(f"{b}/{s}={v}" for (b, s), v in sizes.items()), file=sys.stderr)
    write_rows(rows, os.path.join(args.out, "storage_sizes"))
    lines = ["| map | " + " | ".join(f"`--bits {b}` zstd" for b in STORAGES) + " | `auto` none (bytes) |",
             "|---|" + "---|" * (len(STORAGES) + 1)]
    for tag in dict.fromkeys(r["map"] for r in rows):
        mine = {(r["bits"], r["supercompression"]): r for r in rows if r["map"] == tag}
        cells = [f"{mine[(b, 'zstd')]['ratio']:.3f}" for b in STORAGES]
        lines.append(f"| {tag} | " + " | ".join(cells) + f" | {mine[('auto', 'none')]['bytes']:,} |")
    with open(os.path.join(args.out, "storage_sizes.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
