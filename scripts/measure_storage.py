#!/usr/bin/env python3
"""Storage precision of LEAN maps: PSNR of LEAN renders of 8, 16, 16f bakes against the 32f bake.

For each test map: `leanfade bake --bits B` for every storage, `leanfade render --techniques lean
--cells DIR` of the same scene (linear radiance in PFM), then the PSNR of every cell against the
32f bake's cell: 10 log10(1 / MSE), the radiance clamped to [0, 1] (the displayable range) and the
mean taken over every pixel and channel of the cells of all distances. Writes
docs/data/storage_psnr.csv and .json (docs/ktx2.md, "Choosing storage and sc").

Test maps: 8-bit RGB normal maps made from the built-in bump sets (`leanfade bake --format png`
gives the normals of a height field in lean1's rgb, kept at 8 bits here), the same maps
with one texel turned to a horizontal normal (1, 0.5, 0.5): z = 1/255 raised to 1/64, a slope of
64), and a few height maps baked straight from the built-ins.

Usage: scripts/measure_storage.py LEANFADE_EXE OUT_DIR [--quick]
"""
import json
import math
import os
import struct
import subprocess
import sys
import zlib

# (label, bake flags): every storage with the default sc (auto), and with sc = the maximum.
VARIANTS = [("8", ["--bits", "8"]), ("16", ["--bits", "16"]), ("16f", ["--bits", "16f"]),
            ("32f", ["--bits", "32f"]), ("8 sc=max", ["--bits", "8", "--sc", "max"]),
            ("16 sc=max", ["--bits", "16", "--sc", "max"]),
            ("32f sc=max", ["--bits", "32f", "--sc", "max"]), ("auto", ["--bits", "auto"])]
TRUTH = "32f"
DISTANCES = "1.6,4,12"
SIZE = "256x256"


def run(args):
    result = subprocess.run(args, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit("failed: " + " ".join(args) + "\n" + result.stderr)
    return result.stdout


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        width, height = (int(v) for v in f.readline().split())
        scale = float(f.readline())
        channels = 3 if kind == b"PF" else 1
        count = width * height * channels
        data = f.read(4 * count)
    endian = "<" if scale < 0 else ">"
    return struct.unpack(endian + "%df" % count, data)


def psnr(a_cells, b_cells):
    total, count = 0.0, 0
    for a, b in zip(a_cells, b_cells):
        for x, y in zip(a, b):
            d = min(max(x, 0.0), 1.0) - min(max(y, 0.0), 1.0)
            total += d * d
        count += len(a)
    mse = total / count
    return float("inf") if mse == 0.0 else 10.0 * math.log10(1.0 / mse)


def write_png_rgb8(path, width, height, rgb):
    """An 8-bit RGB PNG (filter 0 on every row)."""
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))
    rows = b"".join(b"\0" + bytes(rgb[3 * width * y:3 * width * (y + 1)]) for y in range(height))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height,
                                                                   8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def read_png_rgb8(path):
    """The 8-bit RGB of a non-interlaced 8/16-bit RGB(A) PNG (16-bit samples rounded)."""
    with open(path, "rb") as f:
        data = f.read()
    pos, idat = 8, b""
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    channels = {2: 3, 6: 4}[colour]
    bpp = channels * depth // 8
    stride = width * bpp
    raw = zlib.decompress(idat)
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = previous[i]
            c = previous[i - bpp] if i >= bpp else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                predictor = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + predictor) & 255
        rows.append(line)
        previous = line
    rgb = bytearray()
    for line in rows:
        for x in range(width):
            for c in range(3):
                if depth == 8:
                    rgb.append(line[x * bpp + c])
                else:
                    value = (line[x * bpp + 2 * c] << 8) | line[x * bpp + 2 * c + 1]
                    rgb.append((value * 255 + 32767) // 65535)
    return width, height, rgb


def make_normal_map(exe, work, builtin, size, outliers):
    """An 8-bit RGB normal map of a built-in height set, optionally with horizontal texels."""
    base = os.path.join(work, "%s_%d" % (builtin, size))
    if not os.path.exists(base + ".lean1.png"):
        run([exe, "bake", "--builtin", builtin, "--size", str(size), "--format", "png",
             "--bits", "16", "-o", base + ".png"])
    width, height, rgb = read_png_rgb8(base + ".lean1.png")
    for i in range(outliers):  # normals along +x at the horizon: z = 1/255, raised to 1/64
        x, y = (size // 3 + 17 * i) % size, (size // 2 + 29 * i) % size
        rgb[3 * (y * width + x):3 * (y * width + x) + 3] = bytes([255, 128, 128])
    name = os.path.join(work, "%s_%d%s_n.png" % (
        builtin, size, "_%d_horizontal" % outliers if outliers else ""))
    write_png_rgb8(name, width, height, rgb)
    return name


def measure(exe, work, label, bake_args, scene, strength_note):
    rows = []
    cells = {}
    for bits, flags in VARIANTS:
        tag = bits.replace(" ", "_").replace("=", "")
        ktx = os.path.join(work, "%s_%s.ktx2" % (label, tag))
        summary = run([exe, "bake"] + bake_args + flags + ["-o", ktx])
        folder = os.path.join(work, "%s_%s_cells" % (label, tag))
        run([exe, "render", "--scene", scene, "--techniques", "lean", "--distances", DISTANCES,
             "--size", SIZE, "--bumps", ktx, "--cells", folder, "-o",
             os.path.join(work, "%s_%s.png" % (label, tag))])
        names = sorted(n for n in os.listdir(folder) if n.endswith(".pfm"))
        cells[bits] = [read_pfm(os.path.join(folder, n)) for n in names]
        sc = None
        beyond = 0
        for line in summary.splitlines():
            if "sc = " in line:
                sc = float(line.split("sc = ")[1].split()[0].rstrip(","))
            if "have a slope component above sc" in line:
                beyond = int(line.split()[0])
        rows.append({"map": label, "storage": bits, "sc": sc, "texels_beyond_sc": beyond,
                     "note": strength_note})
    for row in rows:
        value = psnr(cells[row["storage"]], cells[TRUTH])
        row["psnr_db"] = None if math.isinf(value) else round(value, 2)
    return rows


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    exe, out_dir = sys.argv[1], sys.argv[2]
    quick = "--quick" in sys.argv
    work = os.path.join(out_dir, "work")
    os.makedirs(work, exist_ok=True)
    maps = []
    cases = [("bumps", 0), ("bumps", 1), ("bumps", 8), ("noise", 0), ("noise", 1),
             ("checker", 0), ("checker", 1), ("waves", 1)]
    if quick:
        cases = [("bumps", 0), ("bumps", 1)]
    for builtin, outliers in cases:
        path = make_normal_map(exe, work, builtin, 256, outliers)
        label = os.path.basename(path)[:-4]
        maps.append((label, [path], "sphere", "8-bit normal map"))
    if not quick:
        maps.append(("bumps_height", ["--builtin", "bumps", "--size", "256"], "sphere",
                     "height map"))
    rows = []
    for label, args, scene, note in maps:
        rows += measure(exe, work, label, args, scene, note)
        for r in rows[-len(VARIANTS):]:
            print("%-28s %-10s sc %-10s beyond %-4d PSNR %s" % (
                r["map"], r["storage"], r["sc"], r["texels_beyond_sc"], r["psnr_db"]), flush=True)
    os.makedirs(out_dir, exist_ok=True)
    with open(os.path.join(out_dir, "storage_psnr.json"), "w") as f:
        json.dump({"scene": "sphere", "technique": "lean", "distances": DISTANCES,
                   "cell_size": SIZE, "metric": "PSNR of linear radiance clamped to [0,1] "
                   "against the 32f bake (default sc), over all cells", "rows": rows}, f,
                  indent=2)
        f.write("\n")
    with open(os.path.join(out_dir, "storage_psnr.csv"), "w") as f:
        f.write("map,input,storage,sc,texels_beyond_sc,psnr_db_vs_32f\n")
        for r in rows:
            f.write("%s,%s,%s,%s,%d,%s\n" % (r["map"], r["note"], r["storage"], r["sc"],
                                            r["texels_beyond_sc"],
                                            "inf" if r["psnr_db"] is None else r["psnr_db"]))


if __name__ == "__main__":
    main()
