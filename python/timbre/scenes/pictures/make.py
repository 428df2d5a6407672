#!/usr/bin/env python3
"""Makes the example scenes' pictures (standard library only): `sky.png`, an equirectangular
sky (+y the top row, +z the centre) labelled +Z, +X, -Z, -X at the horizon in the directions
they name, and `letter-f.png`, an F on four coloured quarters, to show which way a picture
lies. Values are linear, as timbre reads them. Run from anywhere: writes beside itself."""

import math
import os
import struct
import zlib

FONT = {  # 5 x 7, rows from the top
    "+": ["00000", "00100", "00100", "11111", "00100", "00100", "00000"],
    "-": ["00000", "00000", "00000", "11111", "00000", "00000", "00000"],
    "X": ["10001", "10001", "01010", "00100", "01010", "10001", "10001"],
    "Z": ["11111", "00001", "00010", "00100", "01000", "10000", "11111"],
    "F": ["11111", "10000", "10000", "11110", "10000", "10000", "10000"],
}


def write_png(path, width, height, pixel):
    rows = bytearray()
    for y in range(height):
        rows.append(0)
        for x in range(width):
            rows.extend(max(0, min(255, round(255 * c))) for c in pixel(x, y))
    chunk = lambda kind, data: (
        struct.pack(">I", len(data)) + kind + data
        + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    )
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(bytes(rows), 9)))
        f.write(chunk(b"IEND", b""))


def text_mask(text, scale):
    """The set of (column, row) texels of `text` drawn `scale` times the font's size."""
    mask = set()
    for k, ch in enumerate(text):
        for r, line in enumerate(FONT[ch]):
            for c, bit in enumerate(line):
                if bit == "1":
                    for dy in range(scale):
                        for dx in range(scale):
                            mask.add(((6 * k + c) * scale + dx, r * scale + dy))
    return mask


def sky(width=512, height=256):
    labels = []
    for text, u in [("+Z", 0.5), ("+X", 0.75), ("-Z", 0.0), ("-X", 0.25)]:
        mask = text_mask(text, 3)
        w = (6 * len(text) - 1) * 3
        labels.append((round(u * width) - w // 2, height // 2 - 30, mask))
    sun = (math.radians(30), math.radians(25))  # azimuth from +z towards +x, elevation

    def pixel(x, y):
        azimuth = (x + 0.5) / width * 2 * math.pi - math.pi
        elevation = math.pi / 2 - (y + 0.5) / height * math.pi
        for left, top, mask in labels:
            if ((x - left) % width, y - top) in mask:
                return (1.0, 1.0, 1.0)
        d = (math.cos(elevation) * math.sin(azimuth), math.sin(elevation),
             math.cos(elevation) * math.cos(azimuth))
        s = (math.cos(sun[1]) * math.sin(sun[0]), math.sin(sun[1]),
             math.cos(sun[1]) * math.cos(sun[0]))
        if sum(a * b for a, b in zip(d, s)) > math.cos(math.radians(4)):
            return (1.0, 0.95, 0.6)
        if elevation < 0:
            return (0.25, 0.35 + 0.1 * math.sin(8 * azimuth), 0.15)
        t = elevation / (math.pi / 2)
        return (0.55 - 0.4 * t, 0.7 - 0.35 * t, 1.0 - 0.1 * t)

    return width, height, pixel


def letter_f(size=64):
    mask = text_mask("F", 6)
    left, top = (size - 30) // 2, (size - 42) // 2
    quarters = [[(0.9, 0.1, 0.1), (0.1, 0.7, 0.1)], [(0.1, 0.2, 0.9), (0.9, 0.8, 0.1)]]

    def pixel(x, y):
        if (x - left, y - top) in mask:
            return (1.0, 1.0, 1.0)
        return quarters[2 * y // size][2 * x // size]

    return size, size, pixel


if __name__ == "__main__":
    here = os.path.dirname(os.path.abspath(__file__))
    write_png(os.path.join(here, "sky.png"), *sky())
    write_png(os.path.join(here, "letter-f.png"), *letter_f())
