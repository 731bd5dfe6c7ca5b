#!/usr/bin/env python3
"""Mean absolute difference of two PNG images (8-bit RGB or RGBA, not interlaced), in 8-bit sRGB
steps over the RGB channels; with a third image (the scene without the medium), only over the pixels
where the reference differs from it (the medium's own pixels). Standard library only.

    png_error.py IMAGE REFERENCE [BACKGROUND]   ->  "png_error mean_error=X pixels=N"
"""

import struct
import sys
import zlib


def read_png(path):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"{path}: not a PNG")
    pos, idat, width = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos : pos + 8])
        body = data[pos + 8 : pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or colour not in (2, 6) or interlace:
                sys.exit(f"{path}: only 8-bit RGB/RGBA, not interlaced")
            bpp = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw, stride = zlib.decompress(idat), width * bpp
    rows, prev = [], bytearray(stride)
    for y in range(height):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1 : (y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return width, height, bpp, rows


def main():
    imgs = [read_png(p) for p in sys.argv[1:4]]
    (w, h, bpp, a), (_, _, bppr, r) = imgs[0], imgs[1]
    bg = imgs[2] if len(imgs) > 2 else None
    total, count = 0, 0
    for y in range(h):
        for x in range(w):
            pr = r[y][x * bppr : x * bppr + 3]
            if bg and pr == bg[3][y][x * bg[2] : x * bg[2] + 3]:
                continue
            pa = a[y][x * bpp : x * bpp + 3]
            total += sum(abs(pa[c] - pr[c]) for c in range(3))
            count += 1
    print(f"png_error mean_error={total / max(1, 3 * count):.3f} pixels={count}")


if __name__ == "__main__":
    main()
