#!/usr/bin/env python3
"""Compares sgfx-cluster's composite with the single-process reference, pixel by pixel.

    composite_compare.py COMPOSITE REFERENCE [--tolerance T] [--allow-fraction F]

Pixels the composite leaves transparent (alpha 0: bezels and gaps between channels) are left out.
Over the others, counts the pixels whose largest RGB difference exceeds T (8-bit steps, default 1).
Such a pixel is a triangle-edge pixel when the composite's colour lies within T of the range of the
reference's 3x3 neighbourhood in every channel: a surface edge that the channel's own projection
put on the other side of the pixel's centre (the same scene, its coverage shifted by under a pixel).
The rest (`over_tolerance`) are mostly the same kind where a third surface shows through (a
nearly horizontal edge whose coverage moved over a run of pixels). Exit status 1 when the pixels
over T, of both kinds, are more than F of the compared pixels (default 0: none allowed), or when
the sizes differ or nothing was compared.
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "bench"))
from png_error import read_png  # noqa: E402  (the standard-library PNG reader next door)


def on_edge(c, rpx, bpp, x, y, w, h, tolerance):
    near = [
        rpx[j][i * bpp : i * bpp + 3]
        for j in range(max(0, y - 1), min(h, y + 2))
        for i in range(max(0, x - 1), min(w, x + 2))
    ]
    return all(min(p[k] for p in near) - tolerance <= c[k] <= max(p[k] for p in near) + tolerance for k in range(3))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("composite")
    ap.add_argument("reference")
    ap.add_argument("--tolerance", type=int, default=1)
    ap.add_argument("--allow-fraction", type=float, default=0.0)
    a = ap.parse_args()
    cw, ch, cbpp, cpx = read_png(a.composite)
    rw, rh, rbpp, rpx = read_png(a.reference)
    if (cw, ch) != (rw, rh):
        print(f"composite_compare: sizes differ: {cw}x{ch} and {rw}x{rh}")
        return 1
    compared = over = edges = 0
    worst, worst_at = 0, None
    for y in range(ch):
        for x in range(cw):
            c = cpx[y][x * cbpp : x * cbpp + cbpp]
            if cbpp == 4 and c[3] == 0:
                continue
            r = rpx[y][x * rbpp : x * rbpp + rbpp]
            d = max(abs(c[i] - r[i]) for i in range(3))
            compared += 1
            if d > a.tolerance:
                if on_edge(c, rpx, rbpp, x, y, rw, rh, a.tolerance):
                    edges += 1
                else:
                    over += 1
            if d > worst:
                worst, worst_at = d, (x, y)
    print(
        f"composite_compare pixels={compared} over_tolerance={over} edge_pixels={edges} "
        f"max_diff={worst} at={worst_at}"
    )
    if compared == 0:
        print("composite_compare: nothing compared")
        return 1
    return 0 if over + edges <= a.allow_fraction * compared else 1


if __name__ == "__main__":
    sys.exit(main())
