#!/usr/bin/python3
"""bench_peers.py — the raycaster beside its peers on a suite of volumes, at
matched settings, interleaved, with the ratio printed per volume.

Usage (bench/bench_vtk.sh runs it under Xvfb; `make bench` runs that):
  bench_peers.py [--build B] [--shared DIR] [--rounds N] [--size S]
                 [--sets NAME,NAME...] [--work DIR]

The suite: the real MM5 run at 3 h (Q dense; CLW and SNOW sparse), a WRF
file (Hurricane Katrina's QCLOUD), and gen-plume's sparse plume and its
plume with a haze floor (../shared/tools/gen-plume, compiled and run here).

Every volume goes through bench_rc_peer (Vesuvius), which decodes it and
writes the decoded floats, the geometry, the transfer function's table, the
sample step, the termination threshold and 8 views orbiting 30 degrees up;
every other peer renders that. A peer is a program speaking
bench_rc_peer.c's protocol on its standard input ("time THREADS SIZE",
"image THREADS SIZE VIEW OUT", "quit"); to add one, add it to PEERS below.

Per volume: PSNR of each peer's 8 images against Vesuvius's (8-bit RGB over
black; >= 35 dB for the comparison to count), then ROUNDS rounds, each
rendering the 8 views on 1 and then 2 threads with every peer in turn (the
order alternating from round to round), so the machine's changing load
falls on all alike. A round's time is the mean frame time over the 8
views; printed: the median and range over rounds, and the ratio of medians
(peer / Vesuvius: > 1 means Vesuvius is faster) with the range of the
per-round ratios."""
import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def peers(build):
    """name, argv(dir) — the first is Vesuvius, which prepares each volume."""
    return [
        ("VTK vtkFixedPointVolumeRayCastMapper", lambda d: ["/usr/bin/python3", HERE + "/bench_vtk_peer.py", d]),
    ]


class Peer:
    def __init__(self, name, argv):
        self.name = name
        self.p = subprocess.Popen(argv, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        line = self.p.stdout.readline().strip()
        if line != "ready":
            raise SystemExit("bench_peers: %s did not start (%r)" % (name, line))

    def ask(self, cmd):
        self.p.stdin.write(cmd + "\n")
        self.p.stdin.flush()
        line = self.p.stdout.readline()
        if not line:
            raise SystemExit("bench_peers: %s stopped at %r" % (self.name, cmd))
        return line.strip()

    def times(self, threads, size):
        """per frame: the peer's renderer time (and wall time, when it has one)"""
        parts = self.ask("time %d %d" % (threads, size)).split("|")
        own = [float(t) for t in parts[0].split()]
        wall = [float(t) for t in parts[1].split()] if len(parts) > 1 else own
        return own, wall

    def image(self, threads, size, view, path):
        if self.ask("image %d %d %d %s" % (threads, size, view, path)) != "ok":
            raise SystemExit("bench_peers: %s: no image" % self.name)
        return np.fromfile(path, np.uint8).reshape(size, size, 3).astype(np.float64)

    def close(self):
        try:
            self.p.stdin.write("quit\n")
            self.p.stdin.close()
        except BrokenPipeError:
            pass
        self.p.wait()


def psnr(a, b):
    mse = ((a - b) ** 2).mean()
    return math.inf if mse == 0 else 10 * math.log10(255.0 ** 2 / mse)


def datasets(args, work):
    mm5 = os.path.join(args.shared, "data/mm5/run1/MMOUT_DOMAIN1")
    wrf = os.path.join(args.shared, "data/wrf/katrina_ci_test_file.nc")
    conv = os.path.join(args.build, "vsv-convert")
    sets = []
    if os.path.exists(mm5):
        out = os.path.join(work, "mm5.vsv")
        subprocess.run([conv, "-q", "--vertical", "even", mm5, "-o", out], check=True)
        for sp, what in [("Q", "MM5 Q (vapour, dense)"), ("CLW", "MM5 CLW (cloud water, sparse)"),
                         ("SNOW", "MM5 SNOW (sparse)")]:
            sets.append((sp.lower(), what, [out, "3", sp]))
    if os.path.exists(wrf):
        out = os.path.join(work, "wrf.vsv")
        subprocess.run([conv, "-q", "--vertical", "even", wrf, "-o", out], check=True)
        sets.append(("wrf", "WRF Katrina QCLOUD", [out, "3", "QCLOUD"]))
    gen = os.path.join(args.shared, "tools/gen-plume/gen_volume.c")
    if os.path.exists(gen):
        exe = os.path.join(work, "gen_volume")
        subprocess.run(["cc", "-O2", "-I", os.path.dirname(gen), gen, "-o", exe, "-lm"], check=True)
        subprocess.run([exe, work], check=True, stdout=subprocess.DEVNULL)
        # 1 km cells, 100 m levels: a 256 x 256 km domain 6.4 km deep
        geo = ["256", "256", "64", "1000", "1000", "100"]
        sets.append(("plume", "gen-plume plume (sparse)", ["--f32", os.path.join(work, "plume_t0.f32")] + geo + ["plume"]))
        sets.append(("haze", "gen-plume plume with haze (never empty)",
                     ["--f32", os.path.join(work, "plume_haze.f32")] + geo + ["haze"]))
    return [s for s in sets if not args.sets or s[0] in args.sets.split(",")]


def occupancy(d):
    """share of cells whose value is above the transfer function's transparent floor"""
    with open(os.path.join(d, "scene.txt")) as f:
        sc = dict((w[0], w[1:]) for w in (line.split() for line in f) if w and w[0] in ("dims", "lo", "lut"))
    lut_first = None
    with open(os.path.join(d, "scene.txt")) as f:
        lines = f.read().split("\n")
    i = next(k for k, line in enumerate(lines) if line.startswith("lut "))
    for line in lines[i + 1:i + 1 + int(sc["lut"][0])]:
        v, a = float(line.split()[0]), float(line.split()[4])
        if a > 0:
            break
        lut_first = v
    vol = np.fromfile(os.path.join(d, "volume.f32"), np.float32)
    floor = lut_first if lut_first is not None else float(sc["lo"][0])
    return 100.0 * np.count_nonzero(vol > floor) / vol.size, "x".join(sc["dims"])


def loadavg():
    try:
        return os.getloadavg()[0]
    except OSError:
        return float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.environ.get("B", "build"))
    ap.add_argument("--shared", default=os.environ.get("SHARED", "../shared"))
    ap.add_argument("--rounds", type=int, default=int(os.environ.get("ROUNDS", "5")))
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--sets", default=os.environ.get("SETS", ""))
    ap.add_argument("--work", default="")
    args = ap.parse_args()
    work = args.work or tempfile.mkdtemp(prefix="vsv-bench-peers.")
    os.makedirs(work, exist_ok=True)
    rc_peer = os.path.join(args.build, "bench/bench_rc_peer")
    try:
        sets = datasets(args, work)
        if not sets:
            raise SystemExit("bench_peers: no data (needs %s/data or its tools/gen-plume)" % args.shared)
        print("Raycasters on the same volumes: %dx%d, 8 views orbiting 30 deg up, perspective 35 deg; %d rounds, "
              "interleaved; %d cores; load average %.1f at the start" % (args.size, args.size, args.rounds,
                                                                         os.cpu_count(), loadavg()))
        print("Matched: the decoded volume (VTK reads it with SetFileLowerLeft(1)), the camera, the image size, "
              "the sample step (half the smallest cell edge), early termination (transmittance < 255/32767, VTK's), "
              "opacity per unit length (VTK's scalar opacity o(v) = 1 - exp(-3 a(v)) at unit distance min(dx, dy), "
              "a(v): the opacity curve; bench_vtk_peer.py derives it), no shading, no terrain.")
        print("Times: Vesuvius vsv_render(); VTK the mapper's own TimeToDraw (ray casting and drawing its image; "
              "its Render() wall time beside it). Ratio = peer time / Vesuvius time (> 1: Vesuvius faster).\n")
        print("| data | cells | non-empty | peer | PSNR dB (worst view) | threads | Vesuvius ms median (range) "
              "| peer ms median (range) | peer Render() wall ms | ratio median (range) |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        summary = []
        for key, what, src in sets:
            d = os.path.join(work, key)
            os.makedirs(d, exist_ok=True)
            ours = Peer("Vesuvius", [rc_peer, d] + src)
            occ, dims = occupancy(d)
            others = [Peer(name, argv(d)) for name, argv in peers(args.build)]
            quality = []
            for p in others:
                worst, diff2 = math.inf, []
                for v in range(8):
                    a = ours.image(1, args.size, v, os.path.join(d, "ours%d.rgb" % v))
                    b = p.image(1, args.size, v, os.path.join(d, "peer%d.rgb" % v))
                    worst = min(worst, psnr(a, b))
                    diff2.append(((a - b) ** 2).mean())
                m = float(np.mean(diff2))
                quality.append((10 * math.log10(255.0 ** 2 / m) if m else math.inf, worst))
            for th in (1, 2):
                ours_t, peer_t, peer_w = [], [[] for _ in others], [[] for _ in others]
                for r in range(args.rounds):
                    order = [None] + list(range(len(others)))
                    if r % 2:
                        order.reverse()
                    for i in order:
                        if i is None:
                            own, _ = ours.times(th, args.size)
                            ours_t.append(np.mean(own))
                        else:
                            own, wall = others[i].times(th, args.size)
                            peer_t[i].append(np.mean(own))
                            peer_w[i].append(np.mean(wall))
                for i, p in enumerate(others):
                    ratios = [b / a for a, b in zip(ours_t, peer_t[i])]
                    ratio = np.median(peer_t[i]) / np.median(ours_t)
                    summary.append((ratio, what, th, p.name))
                    q = quality[i]
                    print("| %s | %s | %.1f %% | %s | %.1f (%.1f)%s | %d | %.1f (%.1f-%.1f) | %.1f (%.1f-%.1f) | %.1f | "
                          "**%.2f** (%.2f-%.2f) |" % (
                              what, dims, occ, p.name.split()[0], q[0], q[1], "" if q[0] >= 35 else " below 35: does not count", th, 1e3 * np.median(ours_t),
                              1e3 * min(ours_t), 1e3 * max(ours_t), 1e3 * np.median(peer_t[i]), 1e3 * min(peer_t[i]),
                              1e3 * max(peer_t[i]), 1e3 * np.median(peer_w[i]), ratio, min(ratios), max(ratios)))
                    sys.stdout.flush()
            for p in others + [ours]:
                p.close()
        print("\nload average %.1f at the end" % loadavg())
        summary.sort()
        lo, hi = summary[0], summary[-1]
        print("worst: %.2fx (%s, %d thread%s, %s); best: %.2fx (%s, %d thread%s, %s)" % (
            lo[0], lo[1], lo[2], "s" if lo[2] > 1 else "", lo[3].split()[0],
            hi[0], hi[1], hi[2], "s" if hi[2] > 1 else "", hi[3].split()[0]))
        low = [s for s in summary if s[0] < 3]
        print("ratio >= 3 on every volume and thread count: %s" % ("yes" if not low else "no (%d of %d below)" % (
            len(low), len(summary))))
    finally:
        if not args.work:
            shutil.rmtree(work, ignore_errors=True)


main()
