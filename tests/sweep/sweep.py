#!/usr/bin/python3
"""sweep.py — damaged inputs and signals through the tools, counted.

  /usr/bin/python3 tests/sweep/sweep.py [--kinds K,...] [--flips N] [--truncs N]
        [--model-flips N] [--model-truncs N] [--sigterm N] [--jobs N] [--seed S]

Kinds (default all): vsv (a .vsv converted from the real WRF run
../shared/data/wrf/wrf_cropped.nc, through vsv-info --check, vsv-extract and
vsv-render: every step as a sequence, or with --render-last the last step),
mm5, camx, wrf, cmaq, grads (through vsv-convert), sigterm.

Each damaged copy is one random single-byte change (a byte replaced by
another value) or a truncation at a random length. A run passes when the tool
 - ends by itself within the time limit (no hang) and not by a signal,
 - exits 0 or 1 (never 2 or more),
 - on exit 1 prints a message naming the damaged file,
 - for a damaged .vsv through vsv-info --check: exits 1 (every byte of a .vsv
   is covered by a checksum or must be zero padding, so nothing passes),
 - leaves in its output folder either nothing (exit 1) or only the complete
   output (exit 0; a .vsv output then passes vsv-info --check): no temporary,
   no partial file.
SIGTERM: vsv-convert (the real MM5 run), vsv-export (--vdb, --netcdf),
vsv-render --movie and a vsv-render PNG sequence are each sent SIGTERM N
times (--sigterm) at a random moment of their run; after it the output
folder must be empty (or hold only the complete output if the job had
finished), and the tool must have died of the signal (or exited 0 first).
Prints per kind and tool the runs and each failure class; exit 1 on any
failure. Run from the top of the tree after `make`; B (build dir) and SHARED
as for the tests. tests/cli_sweep.sh runs a small fixed subset in make test.
"""
import argparse
import concurrent.futures as cf
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

B = os.environ.get("B", "build")
SHARED = os.environ.get("SHARED", "../shared")
# the small real files: the repository's copies (tests/data), else ../shared's
D = "tests/data" if os.path.isdir("tests/data") else SHARED + "/data"
LIMIT = float(os.environ.get("SWEEP_TIMEOUT", "120"))
RENDER_ALL = True
SIG_INPUT = SHARED + "/data/mm5/run1/MMOUT_DOMAIN1"
ENV = dict(os.environ, LC_ALL="C")


class Tally:
    def __init__(self):
        self.done = 0
        self.lock = threading.Lock()
        self.runs = {}
        self.fails = {}
        self.examples = {}

    def item(self):
        """One damaged input finished: the counts so far every 200."""
        with self.lock:
            self.done += 1
            n = self.done
        if n % 200 == 0:
            with self.lock:
                runs, fails = sum(self.runs.values()), sum(self.fails.values())
            print("  ... %d inputs, %d runs, %d failed" % (n, runs, fails), flush=True)

    def add(self, key, fail=None, example=None):
        with self.lock:
            self.runs[key] = self.runs.get(key, 0) + 1
            if fail:
                k = (key, fail)
                self.fails[k] = self.fails.get(k, 0) + 1
                self.examples.setdefault(k, example)


T = Tally()


def run(cmd, cwd=None):
    """(exit code or -signal, stderr text, hung?)"""
    try:
        p = subprocess.run(cmd, cwd=cwd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, timeout=LIMIT, env=ENV)
        return p.returncode, p.stderr.decode(errors="replace"), False
    except subprocess.TimeoutExpired as e:
        return None, (e.stderr or b"").decode(errors="replace"), True


def damage(data, rng, trunc):
    if trunc:
        n = rng.randrange(0, len(data))
        return data[:n], "truncated at %d of %d" % (n, len(data))
    at = rng.randrange(len(data))
    b = data[at] ^ rng.randrange(1, 256)
    return data[:at] + bytes([b]) + data[at + 1:], "byte %d 0x%02x -> 0x%02x" % (at, data[at], b)


def check_outputs(outdir, rc, expect):
    """What the output folder holds wrongly: None or a reason."""
    left = sorted(os.listdir(outdir))
    if rc != 0:
        return ("files left after a failure", "left %s" % left[:3]) if left else None
    extra = [f for f in left if f not in expect]
    if extra:
        return "files left beside the output", "left %s" % extra[:3]
    for f in left:
        if f.endswith(".vsv"):
            r, err, hung = run([B + "/vsv-info", "--check", os.path.join(outdir, f)])
            if r != 0:
                return "exit 0, output fails vsv-info --check", err.strip()[:200]
    return None


def judge(key, cmd, path, outdir, expect, what, must_fail=False):
    rc, err, hung = run(cmd)
    ex = "%s (%s): %s" % (" ".join(cmd), what, err.strip()[-300:])
    if hung:
        T.add(key, "hang (> %g s)" % LIMIT, ex)
    elif rc < 0:
        T.add(key, "killed by signal %d" % -rc, ex)
    elif rc not in (0, 1):
        T.add(key, "exit %d" % rc, ex)
    elif rc == 1 and not any(p in err for p in (path if isinstance(path, tuple) else (path,))):
        T.add(key, "message does not name the file", ex)
    elif rc == 0 and must_fail:
        T.add(key, "damage not reported (exit 0)", ex)
    else:
        bad = check_outputs(outdir, rc, expect) if outdir else None
        T.add(key, bad and bad[0], bad and ex + " | " + bad[1])
    return rc


def vsv_sweep(work, n_flips, n_truncs, rng, jobs):
    src = os.path.join(work, "real.vsv")
    r, err, _ = run([B + "/vsv-convert", "-q", D + "/wrf/wrf_cropped.nc", "-o", src])
    if r != 0:
        sys.exit("sweep: cannot make the .vsv: " + err)
    data = open(src, "rb").read()
    print("vsv: %s, %d bytes (vsv-convert of %s/wrf/wrf_cropped.nc)" % (src, len(data), D), flush=True)

    def one(i):
        trunc = i >= n_flips
        bad, what = damage(data, random.Random(rng.random() + i), trunc)
        d = tempfile.mkdtemp(dir=work)
        path = os.path.join(d, "damaged.vsv")
        open(path, "wb").write(bad)
        out = os.path.join(d, "out")
        os.mkdir(out)
        kind = "vsv trunc" if trunc else "vsv flip"
        judge((kind, "vsv-info --check"), [B + "/vsv-info", "--check", path], path, None, (), what,
              must_fail=True)
        judge((kind, "vsv-extract"), [B + "/vsv-extract", path], path, None, (), what)
        if RENDER_ALL:
            rc = judge((kind, "vsv-render --times :"), [B + "/vsv-render", "-q", path, "--times", ":", "--size", "48x36",
                                                       "--threads", "1", "-o", os.path.join(out, "f%02d.png")], path,
                       out, ("f00.png", "f01.png", "f02.png", "f03.png"), what)
            if rc == 0 and len(os.listdir(out)) != 4:
                T.add((kind, "vsv-render sequence"), "exit 0 with %d of 4 frames" % len(os.listdir(out)), what)
        else:
            judge((kind, "vsv-render"), [B + "/vsv-render", "-q", path, "--size", "48x36", "--threads", "1",
                                         "-o", os.path.join(out, "f.png")], path, out, ("f.png",), what)
        shutil.rmtree(d)
        T.item()

    with cf.ThreadPoolExecutor(jobs) as ex:
        list(ex.map(one, range(n_flips + n_truncs)))


MODEL = {
    # kind: (files to damage, the file given to vsv-convert, extra args)
    "mm5": (["tests/corpus/mm5/tiny.mm5"], 0, []),
    "camx": ([D + "/camx/test.uamiv"], 0, []),
    "wrf": ([D + "/wrf/wrf_cropped.nc"], 0, []),
    "cmaq": (["tests/corpus/netcdf/ioapi-cmaq.nc"], 0, []),
    "grads": ([D + "/grads/model.ctl", D + "/grads/model.dat"], 0, ["--vars", "T,Q"]),
}


def model_sweep(kind, work, n_flips, n_truncs, rng, jobs):
    files, main, extra = MODEL[kind]
    datas = [open(f, "rb").read() for f in files]
    print("%s: %s (%s bytes)" % (kind, " + ".join(files), " + ".join(str(len(x)) for x in datas)), flush=True)

    def one(i):
        trunc = i >= n_flips
        r = random.Random(rng.random() + i)
        which = r.randrange(len(files)) if len(files) > 1 else 0
        d = tempfile.mkdtemp(dir=work)
        for k, f in enumerate(files):
            dst = os.path.join(d, os.path.basename(f))
            if k == which:
                bad, what = damage(datas[k], r, trunc)
                what = os.path.basename(f) + " " + what
                open(dst, "wb").write(bad)
            else:
                shutil.copy(f, dst)
        path = os.path.join(d, os.path.basename(files[main]))
        out = os.path.join(d, "out")
        os.mkdir(out)
        key = (kind + (" trunc" if trunc else " flip"), "vsv-convert")
        judge(key, [B + "/vsv-convert", "-q", "--threads", "1"] + extra + [path, "-o", os.path.join(out, "o.vsv")],
              (path, os.path.basename(files[which])), out, ("o.vsv",), what)
        shutil.rmtree(d)
        T.item()

    with cf.ThreadPoolExecutor(jobs) as ex:
        list(ex.map(one, range(n_flips + n_truncs)))


def orphans_gone(folder):
    """Waits (up to the time limit) until no process's command line names folder."""
    end = time.time() + LIMIT
    key = folder.encode()
    while time.time() < end:
        alive = False
        for pid in os.listdir("/proc"):
            if pid.isdigit():
                try:
                    with open("/proc/%s/cmdline" % pid, "rb") as fp:
                        alive = key in fp.read()
                except OSError:
                    continue
                if alive:
                    break
        if not alive:
            return
        time.sleep(0.05)


def sigterm_sweep(work, n, rng):
    """SIGTERM at a random moment; nothing may be left but a complete output."""
    small = os.path.join(work, "sig.vsv")
    run([B + "/vsv-convert", "-q", D + "/wrf/wrf_cropped.nc", "-o", small])
    jobs = [
        ("vsv-convert", lambda o: [B + "/vsv-convert", "-q", SIG_INPUT, "-o", o + "/o.vsv"],
         ("o.vsv",)),
        ("vsv-export --vdb", lambda o: [B + "/vsv-export", "-q", small, "--vdb", o + "/o_%02d.vdb"],
         ("o_00.vdb", "o_01.vdb", "o_02.vdb", "o_03.vdb")),
        ("vsv-export --netcdf", lambda o: [B + "/vsv-export", "-q", small, "--netcdf", o + "/o.nc"], ("o.nc",)),
        ("vsv-render --movie", lambda o: [B + "/vsv-render", "-q", small, "--size", "320x240", "--movie",
                                          o + "/o.mp4"], ("o.mp4",)),
        ("vsv-render -o %02d", lambda o: [B + "/vsv-render", "-q", small, "--times", ":", "--size", "320x240",
                                          "-o", o + "/f%02d.png"], ("f00.png", "f01.png", "f02.png", "f03.png")),
    ]
    # each job's full duration, to place the signals inside it
    dur = {}
    for name, cmd, _ in jobs:
        o = tempfile.mkdtemp(dir=work)
        t0 = time.time()
        r, err, _ = run(cmd(o))
        dur[name] = time.time() - t0
        shutil.rmtree(o)
        print("sigterm: %s runs %.2f s (exit %s)" % (name, dur[name], r), flush=True)
    for i in range(n * len(jobs)):  # n tries of each job, interleaved
        name, cmd, expect = jobs[i % len(jobs)]
        o = tempfile.mkdtemp(dir=work)
        when = rng.uniform(0, dur[name] * 1.05)
        p = subprocess.Popen(cmd(o), stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                             env=ENV)
        time.sleep(when)
        p.send_signal(signal.SIGTERM)
        try:
            _, err = p.communicate(timeout=LIMIT)
            rc = p.returncode
        except subprocess.TimeoutExpired:
            p.kill()
            p.communicate()
            T.add(("sigterm", name), "hang after SIGTERM", "at %.2f s" % when)
            shutil.rmtree(o)
            continue
        # a helper it started (ffmpeg, vsv-nc-writer) may outlive it: wait
        # for every process naming the folder, then look
        orphans_gone(o)
        left = sorted(os.listdir(o))
        ex = "SIGTERM at %.2f s: exit %s, left %s" % (when, rc, left[:4])
        if rc == 0 or left == sorted(expect):
            # exit 0, or killed after its outputs were renamed into place
            # (a sequence holds the signal until all are): complete
            T.add(("sigterm", name), None if sorted(expect) == left else "finished but output incomplete", ex)
        elif rc not in (-signal.SIGTERM, 128 + signal.SIGTERM, 1):
            T.add(("sigterm", name), "exit %s" % rc, ex)
        else:
            T.add(("sigterm", name), "left files" if left else None, ex)
        shutil.rmtree(o)


def report(t0):
    """The table so far; the number of failed runs."""
    print("\n%-12s %-22s %7s %7s" % ("damage", "tool", "runs", "failed"))
    total = failed = 0
    for key in sorted(T.runs):
        nf = sum(v for (k, _), v in T.fails.items() if k == key)
        total += T.runs[key]
        failed += nf
        print("%-12s %-22s %7d %7d" % (key[0], key[1], T.runs[key], nf))
    for (key, why), v in sorted(T.fails.items()):
        print("FAIL %s / %s: %s x%d, e.g. %s" % (key[0], key[1], why, v, T.examples[(key, why)]))
    print("%d runs, %d failed (%.0f s)" % (total, failed, time.time() - t0), flush=True)
    return failed


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--kinds", default="vsv,mm5,camx,wrf,cmaq,grads,sigterm")
    ap.add_argument("--flips", type=int, default=2000)
    ap.add_argument("--truncs", type=int, default=200)
    ap.add_argument("--model-flips", type=int, default=500)
    ap.add_argument("--model-truncs", type=int, default=100)
    ap.add_argument("--sigterm", type=int, default=100, help="SIGTERM tries of each tool")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--seed", type=int, default=18)
    ap.add_argument("--sigterm-input", help="the model file vsv-convert reads in the SIGTERM runs "
                    "(default: the real MM5 run's MMOUT_DOMAIN1, 94 MB)")
    ap.add_argument("--render-last", action="store_true",
                    help="vsv-render the last step to one image (default: every step, a %%02d sequence)")
    a = ap.parse_args()
    global RENDER_ALL, SIG_INPUT
    RENDER_ALL = not a.render_last
    if a.sigterm_input:
        SIG_INPUT = a.sigterm_input
    rng = random.Random(a.seed)
    work = tempfile.mkdtemp(prefix="vsv-sweep.")
    t0 = time.time()
    try:
        for k in a.kinds.split(","):
            t1 = time.time()
            if k == "vsv":
                vsv_sweep(work, a.flips, a.truncs, rng, a.jobs)
            elif k == "sigterm":
                sigterm_sweep(work, a.sigterm, rng)
            else:
                model_sweep(k, work, a.model_flips, a.model_truncs, rng, a.jobs)
            print("  (%s: %.0f s)" % (k, time.time() - t1), flush=True)
            report(t0)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    failed = sum(T.fails.values())
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
