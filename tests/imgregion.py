"""imgregion.py — what the annotation tests look for in a PNG frame (issue 20).

  imgregion.py text A.png BARE.png X0 Y0 X1 Y1
      pixels in the box (fractions of the width and height) that are text in A
      (near white, every channel >= 230) and not in BARE: prints the count.
  imgregion.py bar A.png X0 Y0 X1 Y1 [SLACK]
      the longest run along a row of the box whose lightness never falls (by
      more than SLACK of 255, default 1: rounding; more for a lossy movie) and
      rises by >= 100 of 255, the same in the three rows below (a colour bar
      from its low to its high colour):
      prints its length in pixels (0: none).
  imgregion.py globe BARE.png COAST.png
      a plan view of a global 5 x 4 degree grid (GrADS model.ctl: cells centred
      from 0E, 90S): the share of pixels that differ from the background inside
      the globe's box and outside it, the fewest line pixels (COAST - BARE)
      within 5 pixels of four coast points and the most within 3 of three
      open-sea points.
  imgregion.py diff A.png B.png
      the largest channel difference and the number of pixels that differ.
"""
import sys

import numpy as np
from PIL import Image


def load(path):
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.int32)


def box(img, args):
    h, w = img.shape[:2]
    x0, y0, x1, y1 = (float(a) for a in args)
    return img[int(y0 * h):int(y1 * h), int(x0 * w):int(x1 * w)]


def text(a, bare, args):
    ta, tb = box(a, args).min(axis=2) >= 230, box(bare, args).min(axis=2) >= 230
    return int((ta & ~tb).sum())


def bar(a, args, slack):
    img = box(a, args)
    light = img.sum(axis=2) / 3.0
    best = 0
    for y in range(len(light) - 3):
        row = light[y]
        start = 0
        for x in range(1, len(row) + 1):
            if x == len(row) or row[x] < row[x - 1] - slack:
                # a bar: the same colours in the three rows below
                same = np.abs(img[y + 1:y + 4, start:x] - img[y, start:x]).max() <= 2 * slack + 1
                if row[x - 1] - row[start] >= 100 and same:
                    best = max(best, x - start)
                start = x
    return best


def globe(bare, coast):
    h, w = bare.shape[:2]
    k = w / (1.02 * 360)  # pixels per degree: a plan view spans 1.02 of the box's width

    def px(lat, lon):  # the box: longitudes -2.5..357.5, latitudes -92..92
        return int(round(w / 2 + ((lon % 360) - 177.5) * k)), int(round(h / 2 - lat * k))

    x0, y0, x1, y1 = w / 2 - 180 * k, h / 2 - 92 * k, w / 2 + 180 * k, h / 2 + 92 * k
    data = np.abs(bare - bare[0, 0]).max(axis=2) > 8
    inside = data[int(y0) + 3:int(y1) - 3, int(x0) + 3:int(x1) - 3].mean()
    outside = np.concatenate([data[:max(int(y0) - 3, 0)].ravel(), data[int(y1) + 4:].ravel()]).mean()
    line = np.abs(coast - bare).max(axis=2) > 10

    def near(lat, lon, r):
        x, y = px(lat, lon)
        return int(line[y - r:y + r + 1, x - r:x + r + 1].sum())

    # the Cape of Good Hope, New York, Sydney, Cape Horn; the South Pacific,
    # the southern Indian Ocean, the North Atlantic
    coasts = [near(la, lo, 5) for la, lo in ((-34.36, 18.47), (40.7, -74.0), (-33.9, 151.2), (-55.98, -67.27))]
    seas = [near(la, lo, 3) for la, lo in ((-45, -120), (-45, 90), (30, -40))]
    return "%.3f %.4f %d %d" % (inside, outside, min(coasts), max(seas))


def main():
    what = sys.argv[1]
    if what == "text":
        print(text(load(sys.argv[2]), load(sys.argv[3]), sys.argv[4:8]))
    elif what == "bar":
        print(bar(load(sys.argv[2]), sys.argv[3:7], float(sys.argv[7]) if len(sys.argv) > 7 else 1))
    elif what == "globe":
        print(globe(load(sys.argv[2]), load(sys.argv[3])))
    else:
        a, b = load(sys.argv[2]), load(sys.argv[3])
        if a.shape != b.shape:
            print(999, a.shape[0] * a.shape[1])
        else:
            d = np.abs(a - b).max(axis=2)
            print(int(d.max()), int((d > 0).sum()))


main()
