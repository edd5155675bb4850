#!/usr/bin/python3
"""freevr_trace.py - what a vsv-play-freevr --trace file shows (lines:
window frame tick step time seconds cpu pid; see vsv-play-freevr(1)).

  freevr_trace.py check TRACE [WINDOWS]   the time lock, exit 0 when it holds:
      - every window draws every tick from the first it drew to the last one
        drawn (none skipped), and every tick has one step on every window;
      - a tick is first drawn only after every window has shown the tick
        before (started a frame after its first frame of it): the walls
        never split;
      - with WINDOWS, that many windows drew.
    It prints the ticks, steps, and each window's frames a second.
  freevr_trace.py rates TRACE             per window: frames, frames a second,
      ticks a second (new pictures: with the time lock every window draws the
      room's ticks at the slowest window's pace, and a faster window redraws
      the picture it keeps in between), and CPU milliseconds a frame and a
      tick (its process's CPU time over its frames or ticks; a process that
      draws several windows is divided among them)."""
import sys


def load(path):
    rows = []
    for line in open(path):
        if line.startswith('#') or not line.strip():
            continue
        f = line.split()
        rows.append({'win': f[0], 'frame': int(f[1]), 'tick': int(f[2]), 'step': int(f[3]), 'time': f[4],
                     't': float(f[5]), 'cpu': float(f[6]), 'pid': int(f[7])})
    return rows


def rates(rows):
    out = {}
    wins = sorted(set(r['win'] for r in rows))
    per_pid = {}
    for r in rows:
        per_pid.setdefault(r['pid'], set()).add(r['win'])
    for w in wins:
        mine = [r for r in rows if r['win'] == w]
        mine.sort(key=lambda r: r['t'])
        n = len(mine)
        span = mine[-1]['t'] - mine[0]['t'] if n > 1 else 0
        cpu = (mine[-1]['cpu'] - mine[0]['cpu']) / max(1, len(per_pid[mine[0]['pid']]))
        ticks = mine[-1]['tick'] - mine[0]['tick']
        out[w] = (n, (n - 1) / span if span > 0 else 0, 1000 * cpu / (n - 1) if n > 1 else 0,
                  ticks / span if span > 0 else 0, 1000 * cpu / ticks if ticks > 0 else 0)
    return out


def check(rows, want):
    bad = []
    wins = sorted(set(r['win'] for r in rows))
    if want is not None and len(wins) != want:
        bad.append('%d windows drew, not %d' % (len(wins), want))
    step = {}
    for r in rows:
        if step.setdefault(r['tick'], r['step']) != r['step']:
            bad.append('tick %d shows step %d and step %d' % (r['tick'], step[r['tick']], r['step']))
    first = {}   # (window, tick) -> time of its first frame of that tick
    after = {}   # (window, tick) -> time of its first frame after that one
    last = max(r['tick'] for r in rows)
    for w in wins:
        mine = sorted((r for r in rows if r['win'] == w), key=lambda r: r['t'])
        seen = []
        for i, r in enumerate(mine):
            if (w, r['tick']) not in first:
                first[(w, r['tick'])] = r['t']
                seen.append(r['tick'])
                if i + 1 < len(mine):
                    after[(w, r['tick'])] = mine[i + 1]['t']
        for a, b in zip(seen, seen[1:]):
            if b != a + 1:
                bad.append('%s: tick %d then %d (ticks skipped)' % (w, a, b))
        if seen and seen[-1] < last - 1:
            bad.append('%s: stops at tick %d of %d' % (w, seen[-1], last))
    split = 0
    for k in range(2, last + 1):
        starts = [first[(w, k)] for w in wins if (w, k) in first]
        if not starts:
            continue
        for w in wins:
            shown = after.get((w, k - 1))
            if shown is not None and shown > min(starts) + 1e-6:
                split += 1
                if split <= 5:
                    bad.append('tick %d drawn at %.4f s before %s had shown tick %d (at %.4f s)'
                               % (k, min(starts), w, k - 1, shown))
    steps = sorted(set(step.values()))
    print('%d frames, %d windows, ticks 1..%d, %d steps (%s)' % (len(rows), len(wins), last, len(steps),
                                                               ' '.join(map(str, steps[:20]))))
    for w, (n, fps, cpu, tps, cput) in sorted(rates(rows).items()):
        print('  %-10s %5d frames  %6.1f frames/s  %7.1f ms CPU a frame  %6.2f ticks/s  %7.1f ms CPU a tick'
              % (w, n, fps, cpu, tps, cput))
    for b in bad:
        print('FAULT ' + b)
    return 1 if bad else 0


def main():
    if len(sys.argv) < 3 or sys.argv[1] not in ('check', 'rates'):
        print(__doc__, file=sys.stderr)
        return 2
    rows = load(sys.argv[2])
    if not rows:
        print('no frames in ' + sys.argv[2])
        return 1
    if sys.argv[1] == 'check':
        return check(rows, int(sys.argv[3]) if len(sys.argv) > 3 else None)
    for w, (n, fps, cpu, tps, cput) in sorted(rates(rows).items()):
        print('%s %d %.2f %.2f %.2f %.2f' % (w, n, fps, cpu, tps, cput))
    return 0


sys.exit(main())
