"""advect_track.py — does a cloud move through the frames between two
outputs, or cross-fade? Follows one species in a slab of levels through
the frames of two field streams of the same run (linear and advect, from
vsv-interp --time-res), frames F0..F1 (F0 and F1 model outputs):

  python3 bench/advect_track.py LINEAR.fs ADVECT.fs SPECIES K0 K1 F0 F1

Per frame and stream, of the slab's column totals (levels K0..K1-1): the
peak, the number of objects above half the larger of the two outputs'
peaks (8-connected; 2 means the two ghosts of a cross-fade), and the
mass-weighted centroid (cells) of the heaviest such object with its step
from the previous frame. A cloud that moves shows one object whose
centroid steps evenly; a cross-fade shows two objects mid-way and the
heaviest object's centroid jumping when the later ghost outweighs the
earlier one.
"""
import sys

import numpy as np
from scipy import ndimage

sys.path.insert(0, __file__.rsplit('/', 1)[0] if '/' in __file__ else '.')
import fieldstream  # noqa: E402


def track(path, sp, k0, k1, f0, f1):
    _, _, _, _, names, frames = fieldstream.read(path)
    v = names.index(sp)
    slab = [np.nan_to_num(frames[i][1][v, k0:k1]).sum(0) for i in range(f0, f1 + 1)]
    thr = 0.5 * max(slab[0].max(), slab[-1].max())
    out = []
    for f, s in zip(range(f0, f1 + 1), slab):
        lab, n = ndimage.label(s > thr, structure=np.ones((3, 3)))
        cx = cy = float('nan')
        if n:
            mass = ndimage.sum(s, lab, range(1, n + 1))
            cy, cx = ndimage.center_of_mass(s, lab, int(np.argmax(mass)) + 1)
        out.append((frames[f][0], float(s.max()), n, cx, cy))
    return out


def main():
    lin, adv, sp = sys.argv[1], sys.argv[2], sys.argv[3]
    k0, k1, f0, f1 = (int(x) for x in sys.argv[4:8])
    tl, ta = track(lin, sp, k0, k1, f0, f1), track(adv, sp, k0, k1, f0, f1)
    print('%s, column totals of levels %d..%d, frames %d..%d\n' % (sp, k0, k1 - 1, f0, f1))
    print('| frame | time | linear: peak | objects | centroid x, y (step) | advect: peak | objects | centroid x, y (step) |')
    print('|---|---|---|---|---|---|---|---|')
    import datetime
    steps = {'linear': [], 'advect': []}
    for i, (l, a) in enumerate(zip(tl, ta)):
        cells = []
        for name, r, prev in (('linear', l, tl[i - 1] if i else None), ('advect', a, ta[i - 1] if i else None)):
            st = float(np.hypot(r[3] - prev[3], r[4] - prev[4])) if prev else float('nan')
            if prev:
                steps[name].append(st)
            cells.append('%.3g | %d | %.1f, %.1f (%s)' % (r[1], r[2], r[3], r[4], '-' if st != st else '%.1f' % st))
        t = datetime.datetime.fromtimestamp(l[0], datetime.timezone.utc).strftime('%H:%M')
        print('| %d | %s | %s | %s |' % (f0 + i, t, cells[0], cells[1]))
    print()
    for name in ('linear', 'advect'):
        s = np.array(steps[name])
        s = s[np.isfinite(s)]
        if len(s):
            print('%s: centroid steps %.1f..%.1f cells (largest / mean %.2f); objects mid-way %d' % (
                name, s.min(), s.max(), s.max() / s.mean(), (tl if name == 'linear' else ta)[len(tl) // 2][2]))


if __name__ == '__main__':
    main()
