#!/usr/bin/python3
"""imgcmp.py A.png B.png [BG_R,BG_G,BG_B]: compares two renders of the same
clouds. A pixel is "covered" when it differs from the background by more
than 8 of 255 in some channel. Prints: covered-by-both / covered-by-either
(percent) and the PSNR (dB) over the pixels either covers."""
import sys
import numpy as np
from PIL import Image

a = np.asarray(Image.open(sys.argv[1]).convert("RGB"), dtype=np.float64)
b = np.asarray(Image.open(sys.argv[2]).convert("RGB"), dtype=np.float64)
bg = [float(v) for v in sys.argv[3].split(",")] if len(sys.argv) > 3 else [0.02, 0.03, 0.06]
bg8 = np.array([round(255 * (c ** (1 / 2.2))) for c in bg], dtype=np.float64)
ca = np.abs(a - bg8).max(axis=2) > 8
cb = np.abs(b - bg8).max(axis=2) > 8
either = ca | cb
both = ca & cb
n = either.sum()
if n == 0:
    print("0.0 0.0")
    sys.exit(0)
mse = ((a - b) ** 2)[either].mean()
psnr = 99.0 if mse == 0 else 10 * np.log10(255.0 ** 2 / mse)
print("%.1f %.1f" % (100.0 * both.sum() / n, psnr))
