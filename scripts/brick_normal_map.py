#!/usr/bin/env python3
"""Writes a synthetic 8-bit RGB brick normal map (flat brick faces, bevelled mortar, 8-texel
noise; OpenGL convention) as a PNG: the input of the plateau layer's bake-cost measurement in
docs/perf.md. Needs NumPy (Debian: python3-numpy).

    scripts/brick_normal_map.py OUT.png [SIZE]   # SIZE texels per side, default 2048
"""
import struct
import sys
import zlib

import numpy as np


def brick_normals(n: int, seed: int = 1) -> np.ndarray:
    y, x = np.mgrid[0:n, 0:n].astype(np.float32)
    brick_w, brick_h = 128, 64
    row = (y // brick_h).astype(int)
    xo = (x + (row % 2) * brick_w / 2) % brick_w
    yo = y % brick_h
    edge = np.minimum(np.minimum(xo, brick_w - xo), np.minimum(yo, brick_h - yo))
    height = np.clip(edge / 6.0, 0.0, 1.0)  # 6-texel bevel, flat faces at 1
    noise = np.random.default_rng(seed).normal(0.0, 1.0, (n // 8, n // 8)).astype(np.float32)
    height = height + 0.02 * np.kron(noise, np.ones((8, 8), np.float32))
    gx = (np.roll(height, -1, 1) - np.roll(height, 1, 1)) * 2.0  # strength 4, central differences
    gy = (np.roll(height, -1, 0) - np.roll(height, 1, 0)) * 2.0
    nz = 1.0 / np.sqrt(1.0 + gx * gx + gy * gy)
    rgb = np.stack([-gx * nz, -gy * nz, nz], -1) * 0.5 + 0.5
    return np.clip(np.round(rgb * 255.0), 0, 255).astype(np.uint8)


def write_png(path: str, rgb: np.ndarray) -> None:
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[i].tobytes() for i in range(h))

    def chunk(kind: bytes, data: bytes) -> bytes:
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    size = int(sys.argv[2]) if len(sys.argv) == 3 else 2048
    if not 16 <= size <= 16384 or size % 128:
        sys.exit("SIZE must be a multiple of 128 in [128, 16384]")
    write_png(sys.argv[1], brick_normals(size))
