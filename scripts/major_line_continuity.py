#!/usr/bin/env python3
"""Major lines' continuity in pictures strata drew with its default major-line colour.

Usage: major_line_continuity.py PICTURE.png...

Each major (blue) line crossing the middle row (steep ones) or the middle column
(shallow ones) is followed row by row (column by column) to the picture's edge; a
gap is two or more steps in a row with no blue pixel within 2 px of where the line is
predicted, not counting steps next to a fault trace (red). Prints, per picture and
family, the lines followed with their start, steps, steps missed and gaps. Lines of
the other family crossing the start row are left out (most of their steps miss)."""
import sys

import numpy as np
from PIL import Image

def runs(mask_line):
    xs = np.flatnonzero(mask_line)
    if xs.size == 0:
        return []
    groups = np.split(xs, np.flatnonzero(np.diff(xs) > 1) + 1)
    return [g.mean() for g in groups if g.size <= 6]

def follow(blue, fault, start_row):
    h, w = blue.shape
    out = []
    for x0 in runs(blue[start_row]):
        ahead = [x for x in runs(blue[start_row + 3]) if abs(x - x0) <= 5]
        if not ahead:
            continue
        slope0 = (min(ahead, key=lambda x: abs(x - x0)) - x0) / 3
        steps, missing, gaps, run = 0, 0, 0, 0
        for direction in (1, -1):
            x, slope, y = x0, slope0 * direction, start_row
            history = [(y, x)]
            while True:
                y += direction
                if not (0 <= y < h):
                    break
                px = x + slope * direction
                if not (2 <= px < w - 2):
                    break
                lo, hi = int(round(px)) - 2, int(round(px)) + 3
                hits = np.flatnonzero(blue[y, lo:hi])
                steps += 1
                if hits.size:
                    nx = lo + hits.mean()
                    history.append((y, nx))
                    if len(history) > 8:
                        (ya, xa), (yb, xb) = history[-8], history[-1]
                        slope = (xb - xa) / (yb - ya) * direction
                    x = nx
                    if run >= 2:
                        gaps += 1
                    run = 0
                elif fault[y, lo - 2:hi + 2].any():
                    x = px
                else:
                    x = px
                    missing += 1
                    run += 1
        out.append((round(x0), steps, missing, gaps))
    return out

for path in sys.argv[1:]:
    im = np.asarray(Image.open(path).convert('RGB')).astype(int)
    r, g, b = im[..., 0], im[..., 1], im[..., 2]
    blue = (b - (r + g) / 2 > 0) & (b > 40)
    fault = (r - b > 80) & (r > 150)
    for name, mask, faults in (("steep", blue, fault), ("shallow", blue.T, fault.T)):
        found = follow(mask, faults, mask.shape[0] // 2)
        kept = [f for f in found if f[2] < 0.3 * f[1]]
        print(f"{path} {name}: {len(kept)} lines followed (of {len(found)} crossings); (start, steps, missing, gaps) {kept}")
