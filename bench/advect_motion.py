"""advect_motion.py — how far do the model's patterns move, against how far
its air moves? And how well could any motion field do?

  vsv-extract --add-winds MMOUT > s.fs
  python3 bench/advect_motion.py s.fs HOLD

Frames HOLD-1 and HOLD+1 of the stream (which carries wind.u and wind.v):
1. Block matching, per species and every third level: blocks of 24 x 24
   columns (half overlapping) whose later field changed; the whole-cell
   shift (up to 10 cells each way) of the earlier field that best matches
   the later one (least squares), kept where it removes at least 30 % of
   the mismatch; beside it the block's mean wind times the interval
   (cells; map factors ignored). alpha = (shift . wind) / |wind|^2 is how
   much of the wind's displacement the pattern followed, weighted by the
   block's content.
2. A free motion field (radar-style advection correction, no wind at all):
   per level, 16 x 16 blocks with the best shift (as above, up to 8 cells,
   kept where it removes 10 % of the mismatch), bilinear between block
   centres, and frame HOLD rebuilt as the mean of the earlier frame moved
   half the shift forward and the later moved half back. Its RMSE against
   the held-out frame, beside linear interpolation's, bounds what a
   translation-only motion can gain on these fields.
"""
import sys

import numpy as np
from scipy import ndimage

sys.path.insert(0, __file__.rsplit('/', 1)[0] if '/' in __file__ else '.')
import fieldstream  # noqa: E402


def best_shift(pa, pb, j0, i0, size, r, margin):
    """Best (sx, sy) moving pa onto pb for the block at (j0, i0) in the
    padded arrays (padding r + margin), and the mismatch ratio to no shift."""
    win = pb[j0 + r:j0 + r + size + 2 * margin, i0 + r:i0 + r + size + 2 * margin]
    e0, best = None, (np.inf, 0, 0)
    for sy in range(-r, r + 1):
        for sx in range(-r, r + 1):
            a = pa[j0 + r - sy:j0 + r - sy + size + 2 * margin, i0 + r - sx:i0 + r - sx + size + 2 * margin]
            e = float(((a - win) ** 2).sum())
            if sx == 0 and sy == 0:
                e0 = e
            if e < best[0] or (e == best[0] and sx * sx + sy * sy < best[1] ** 2 + best[2] ** 2):
                best = (e, sx, sy)
    return best[1], best[2], (best[0] / e0 if e0 > 0 else 1.0)


def main():
    path, hold = sys.argv[1], int(sys.argv[2])
    nx, ny, nz, spacing, names, frames = fieldstream.read(path)
    iu, iv = names.index('wind.u'), names.index('wind.v')
    (ta, A), (_, H), (tb, B) = frames[hold - 1], frames[hold], frames[hold + 1]
    dt = tb - ta
    species = [i for i, n in enumerate(names) if not n.startswith('wind.')]
    z = np.nan_to_num
    print('%s: %d x %d x %d, frames %d and %d (%d s apart), held out %d\n' % (path, nx, ny, nz, hold - 1, hold + 1, dt, hold))
    print('| species | blocks with content | matched (>= 30 % less mismatch) | mean shift (cells) | '
          'mean wind displacement (cells) | alpha, content-weighted | alpha, median |')
    print('|---|---|---|---|---|---|---|')
    R, S = 10, 24
    for v in species:
        rows = []
        for k in range(0, nz, 3):
            a, b = z(A[v, k]), z(B[v, k])
            pa, pb = np.pad(a, R + S), np.pad(b, R + S)
            u = z((A[iu, k] + B[iu, k]) / 2) * dt / spacing[0]
            w = z((A[iv, k] + B[iv, k]) / 2) * dt / spacing[1]
            for j0 in range(0, ny - S + 1, S // 2):
                for i0 in range(0, nx - S + 1, S // 2):
                    blk = b[j0:j0 + S, i0:i0 + S]
                    if not (blk.std() > 0):
                        continue
                    sx, sy, ratio = best_shift(pa, pb, j0 + S, i0 + S, S, R, 0)
                    rows.append((sx, sy, ratio, u[j0:j0 + S, i0:i0 + S].mean(), w[j0:j0 + S, i0:i0 + S].mean(),
                                 float((blk ** 2).sum())))
        if not rows:
            continue
        r = np.array(rows)
        g = r[r[:, 2] <= 0.7]
        if len(g):
            wind2 = np.maximum(g[:, 3] ** 2 + g[:, 4] ** 2, 1e-6)
            al = (g[:, 0] * g[:, 3] + g[:, 1] * g[:, 4]) / wind2
            print('| %s | %d | %d | %.1f | %.1f | %.2f | %.2f |' % (
                names[v], len(r), len(g), np.hypot(g[:, 0], g[:, 1]).mean(), np.hypot(g[:, 3], g[:, 4]).mean(),
                (al * g[:, 5]).sum() / g[:, 5].sum(), np.median(al)))
        else:
            print('| %s | %d | 0 | - | - | - | - |' % (names[v], len(r)))
    print('\n| species | RMSE linear | RMSE free motion field | free/linear |')
    print('|---|---|---|---|')
    R, S, M = 8, 16, 8
    yy, xx = np.mgrid[0:ny, 0:nx]
    for v in species:
        a3, b3, h3 = z(A[v]), z(B[v]), H[v]
        ok = np.isfinite(h3) & np.isfinite(A[v]) & np.isfinite(B[v])
        rec = np.empty_like(a3)
        nby, nbx = (ny + S - 1) // S, (nx + S - 1) // S
        for k in range(nz):
            a, b = a3[k], b3[k]
            pad = ((R + M, R + M + S), (R + M, R + M + S))
            pa, pb = np.pad(a, pad), np.pad(b, pad)
            dx, dy = np.zeros((nby, nbx)), np.zeros((nby, nbx))
            for by in range(nby):
                for bx in range(nbx):
                    j0, i0 = by * S, bx * S
                    if pb[j0 + R:j0 + R + S + 2 * M, i0 + R:i0 + R + S + 2 * M].std() == 0 and \
                            pa[j0 + R:j0 + R + S + 2 * M, i0 + R:i0 + R + S + 2 * M].std() == 0:
                        continue
                    sx, sy, ratio = best_shift(pa, pb, j0, i0, S, R, M)
                    if ratio < 0.9:
                        dx[by, bx], dy[by, bx] = sx, sy
            cy, cx = (yy + 0.5) / S - 0.5, (xx + 0.5) / S - 0.5
            fx = ndimage.map_coordinates(dx, [cy, cx], order=1, mode='nearest')
            fy = ndimage.map_coordinates(dy, [cy, cx], order=1, mode='nearest')
            a2 = ndimage.map_coordinates(a, [yy - 0.5 * fy, xx - 0.5 * fx], order=1, mode='nearest')
            b2 = ndimage.map_coordinates(b, [yy + 0.5 * fy, xx + 0.5 * fx], order=1, mode='nearest')
            rec[k] = 0.5 * (a2 + b2)
        lin = 0.5 * (a3 + b3)
        el = np.sqrt(((lin - h3)[ok] ** 2).mean())
        ef = np.sqrt(((rec - h3)[ok] ** 2).mean())
        print('| %s | %.3g | %.3g | %.2f |' % (names[v], el, ef, ef / el if el > 0 else 1.0))


if __name__ == '__main__':
    main()
