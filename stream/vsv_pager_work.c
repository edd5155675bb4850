/* vsv_pager_work.c — the pager's decoding: the defining step of each
 * brick, decode jobs (a brick carried forward from its track's state
 * through the steps asked for, outside the lock) and the worker threads. */
#include "vsv_pager_internal.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void vsv_pager_set_err(vsv_pager *p, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(p->err, sizeof p->err, fmt, ap);
    va_end(ap);
}

/* The defining step of every brick of (step, s) (under the lock): the last
 * step at or before `step` whose payload set the brick (walking back over
 * UNCHANGED, from the row of step-1 when it is cached), -1 where the brick
 * is empty. NULL on a damaged chunk, or one not fetched yet (error set,
 * *rc its code). Borrowed until the next call: the rows are a
 * direct-mapped cache of fixed size. */
const int *vsv_pager_defs(vsv_pager *p, int step, int s, int *rc)
{
    const int ns = p->info.nspecies, nb = p->info.nbricks;
    const size_t key = (size_t)step * ns + s;
    defrow *r = &p->rows[key & (size_t)(p->nrows - 1)];
    if (r->step == step && r->s == s)
        return r->def;
    const defrow *q = step > 0 ? &p->rows[(key - ns) & (size_t)(p->nrows - 1)] : NULL;
    const int *prev = q && q->step == step - 1 && q->s == s ? q->def : NULL;
    r->step = -1;                          /* until it is complete */
    int k = vsv_pager_kind(p, step, s, 0); /* (the chunk there, checked: the octree too) */
    const unsigned char *oct = k < 0 ? NULL : vsv_file_octree(p->f, step, s, NULL);
    if (!oct) {
        if (k >= 0)
            vsv_pager_set_err(p, "%s", vsv_file_error(p->f));
        if (rc)
            *rc = k < 0 ? k : VSV_ECORRUPT;
        return NULL;
    }
    for (int b = 0; b < nb; b++) {
        unsigned mn, mx;
        vsv_octree_node(oct, (size_t)b, &mn, &mx);
        int t = step;
        k = b ? vsv_pager_kind(p, step, s, b) : k;
        if (k == VSV_BRICK_UNCHANGED && prev) {
            r->def[b] = prev[b];
            continue;
        }
        while (k == VSV_BRICK_UNCHANGED && t > 0)
            k = vsv_pager_kind(p, --t, s, b);
        if (k < 0) {
            if (rc)
                *rc = k;
            return NULL;
        }
        r->def[b] = mx == 0 || k == VSV_BRICK_EMPTY ? -1 : t;
    }
    r->step = step;
    r->s = s;
    return r->def;
}

/* Takes the track of (s, b) for job j when the pager keeps decoder state
 * (under the lock; the caller made sure it is not busy): it holds codes
 * (allocated within the budget when it had none) or the job decodes into
 * scratch. */
static void take_track(vsv_pager *p, job *j)
{
    j->track = -1;
    j->codes = NULL;
    if (!p->incremental)
        return;
    const int i = j->s * p->info.nbricks + j->b;
    track *T = &p->tracks[i];
    if (T->listed) {
        vsv_lru_unlink(&p->tlru, p->tracks, sizeof *p->tracks, i);
        T->listed = 0;
    }
    if (!T->codes && vsv_cache_make_room(p, p->codes_bytes, 0) && (T->codes = vsv_slab_get(p, 1))) {
        T->step = -1;
        p->bytes += p->codes_bytes;
        p->track_bytes += p->codes_bytes;
        if (p->bytes > p->peak)
            p->peak = p->bytes;
    }
    if (!T->codes)
        return;
    T->busy = 1;
    p->pinned += p->codes_bytes;
    j->track = i;
    j->codes = T->codes;
}

/* Adds output step v (claimed) to j, keeping the steps ascending. */
static int add_output(vsv_pager *p, job *j, int v)
{
    const int e = vsv_cache_claim(p, j->s, j->b, v);
    if (e < 0)
        return -1;
    int i = j->n++;
    for (; i > 0 && j->step[i - 1] > v; i--) {
        j->step[i] = j->step[i - 1];
        j->ent[i] = j->ent[i - 1];
        j->out[i] = j->out[i - 1];
    }
    j->step[i] = v;
    j->ent[i] = e;
    j->out[i] = p->ent[e].data;
    return 0;
}

/* Payloads (ABS, DELTA, ABS3, DELTA3) of brick b of species s over steps
 * [a, z]; *absolute: whether one of (a, z] is an absolute state (EMPTY,
 * ABS, ABS3), and then the count stops there (the callers want no more).
 * A negative error for a damaged chunk index, or one not fetched yet. */
static long payloads_in(vsv_pager *p, int s, int b, int a, int z, int *absolute)
{
    long n = 0;
    *absolute = 0;
    for (int t = a; t <= z && !*absolute; t++) {
        const int k = vsv_pager_kind(p, t, s, b);
        if (k < 0)
            return k;
        n += k >= VSV_BRICK_ABS;
        if (t > a)
            *absolute |= vsv_brick_absolute(k);
    }
    return n;
}

/* Claims checkpoints for the states of brick (j->s, j->b) at the defining
 * steps from `top` down to j->from that a walk forward from j->from passes
 * (nearest first, two to an entry, while they fit without evicting
 * anything but bricks outside the window); they land in j->ck_* in
 * ascending order. */
static void keep_states(vsv_pager *p, job *j, int top)
{
    const int s = j->s, b = j->b, ns = p->info.nspecies;
    int e = -1; /* the entry whose second half is free */
    for (int v = top; v >= j->from && j->nck < p->job_cap; v--) {
        if (vsv_pager_kind(p, v, s, b) < VSV_BRICK_ABS || vsv_cache_lookup(p, s, b, v) >= 0 ||
            vsv_cache_lookup(p, s + ns, b, v) >= 0)
            continue;
        uint16_t *buf;
        if (e >= 0) { /* the second half of the last one */
            p->ent[e].lo = v;
            p->ent[e].halves |= 2;
            buf = (uint16_t *)p->ent[e].data + p->codes_bytes / sizeof(uint16_t);
        } else {
            if (!vsv_cache_room_ck(p) || (e = vsv_cache_claim(p, s + ns, b, v)) < 0)
                break;
            p->ent[e].lo = -1;
            p->ent[e].halves = 1;
            buf = p->ent[e].data;
        }
        j->ck_step[j->nck] = v; /* descending here: reversed below */
        j->ck_ent[j->nck] = e;
        j->ck_buf[j->nck++] = buf;
        if (p->ent[e].halves == 3)
            e = -1;
    }
    for (int i = 0, k = j->nck - 1; i < k; i++, k--) {
        const int ts = j->ck_step[i], te = j->ck_ent[i];
        uint16_t *tb = j->ck_buf[i];
        j->ck_step[i] = j->ck_step[k], j->ck_ent[i] = j->ck_ent[k], j->ck_buf[i] = j->ck_buf[k];
        j->ck_step[k] = ts, j->ck_ent[k] = te, j->ck_buf[k] = tb;
    }
}

/* Makes the job that decodes brick b of species s at defining step `step`
 * (under the lock; its entry is absent, its track not busy, room made for
 * it): claims the entry and the track, and chooses the cheapest way there
 * in payloads: a copy of a checkpoint of that state; forward from the
 * track's state when it lies between the brick's last absolute state and
 * `step`; backward from the track's state when it lies after `step` with
 * no absolute state between (each delta undone: playing backward a step
 * costs one payload, as forward); else forward from the last absolute
 * state. Playing backward, a walk forward also fills checkpoints of the
 * states it passes, as far as the budget allows. 0, or an error (the job's outputs then failed and released; the
 * error set). */
int vsv_pager_job_make(vsv_pager *p, job *j, int s, int b, int step)
{
    j->s = s;
    j->b = b;
    j->n = 0;
    j->track = -1;
    j->payloads = 0;
    j->rev = 0;
    j->copy = -1;
    j->nck = 0;
    if (add_output(p, j, step)) {
        vsv_pager_set_err(p, "out of memory: a brick of step %d", step);
        return VSV_ENOMEM;
    }
    const int ns = p->info.nspecies;
    if (p->incremental) { /* a checkpoint of this very state: a copy, no payload */
        int c = vsv_cache_lookup(p, s + ns, b, step), half = 0;
        if (c < 0 || p->ent[c].state != READY || p->ent[c].pins || !(p->ent[c].halves & 1)) {
            /* or in the second half of the one keyed by the next defining step */
            int u = step + 1, k = VSV_BRICK_UNCHANGED;
            while (u < p->info.nsteps && (k = vsv_pager_kind(p, u, s, b)) == VSV_BRICK_UNCHANGED)
                u++;
            c = u < p->info.nsteps && vsv_brick_delta(k) ? vsv_cache_lookup(p, s + ns, b, u) : -1;
            half = 1;
            if (c >= 0 &&
                (p->ent[c].state != READY || p->ent[c].pins || p->ent[c].lo != step || !(p->ent[c].halves & 2)))
                c = -1;
        }
        if (c >= 0) {
            vsv_cache_pin(p, c); /* before take_track, which may evict */
            j->copy = c;
            j->copy_half = half;
            j->copy_codes = (const uint16_t *)p->ent[c].data + (half ? p->codes_bytes / sizeof(uint16_t) : 0);
        }
    }
    take_track(p, j);
    if (j->copy >= 0) {
        j->from = step + 1;
        j->fresh = 0;
        return 0;
    }
    const int have = j->track >= 0 ? p->tracks[j->track].step : -1;
    int rc = 0, a = step; /* the brick's last absolute state at or before step */
    for (;; a--) {
        const int k = vsv_pager_kind(p, a, s, b);
        if (vsv_brick_absolute(k))
            break;
        if (k < 0 || a == 0) { /* keyframes hold absolute states: a == 0 is damage */
            rc = k < 0 ? k : VSV_ECORRUPT;
            if (!(k < 0))
                vsv_pager_set_err(p, "%s", vsv_file_error(p->f));
            break;
        }
    }
    long fresh = 0, inc = -1, rev = -1;
    int absolute = 0;
    if (!rc)
        fresh = payloads_in(p, s, b, a, step, &absolute);
    if (!rc && fresh >= 0 && have >= a && have <= step)
        inc = payloads_in(p, s, b, have, step, &absolute) - (vsv_pager_kind(p, have, s, b) >= VSV_BRICK_ABS);
    if (!rc && fresh >= 0 && have > step) {
        /* undoing steps have..step+1 (their payloads) reaches step */
        rev = payloads_in(p, s, b, step, have, &absolute) - (vsv_pager_kind(p, step, s, b) >= VSV_BRICK_ABS);
        if (absolute)
            rev = -1;
    }
    if (!rc && fresh < 0)
        rc = (int)fresh;
    if (!rc) {
        if (inc >= 0 && (rev < 0 || inc <= rev) && inc <= fresh) {
            j->from = have + 1;
            j->fresh = 0;
            j->payloads = (int)inc;
        } else if (rev >= 0 && rev <= fresh) {
            j->from = have;
            j->fresh = 0;
            j->rev = 1;
            j->payloads = (int)rev;
        } else {
            j->from = a;
            j->fresh = 1;
            j->payloads = (int)fresh;
        }
    }
    if (!rc && p->incremental && p->dir < 0 && vsv_sched_wanted(p, s)) {
        /* a walk forward: keep the states it passes as checkpoints
         * (nearest first, while they fit without evicting anything but
         * bricks outside the window), so the steps after this one
         * backward cost a copy each. Checkpoints rather than more float
         * outputs: half the memory, and the job claims one brick only,
         * so another thread can serve the next steps as soon as it ends */
        if (!j->rev)
            keep_states(p, j, j->step[0] - 1);
    }
    if (rc)
        vsv_pager_job_finish(p, j, rc, 0, 0, p->err);
    return rc;
}

/* Playing backward with nothing left to do in the window: the walk into
 * the keyframe group of the step just past it, done ahead (under the
 * lock). For the first brick of that step that no checkpoint or cache
 * entry holds and that its track cannot reach by undoing deltas, j walks
 * from the brick's last absolute state in scratch codes, keeping the
 * states from the step down as checkpoints: when the window gets there,
 * a copy serves it instead of a walk of up to K payloads in one frame.
 * 1 with j made, 0 when there is none or no room. */
int vsv_pager_job_prewalk(vsv_pager *p, job *j)
{
    if (!p->incremental || p->dir >= 0)
        return 0;
    const int w = vsv_sched_ahead(p, p->depth + 1), ns = p->info.nspecies, nb = p->info.nbricks;
    if (w < 0)
        return 0;
    for (int s = 0; s < ns; s++) {
        const int *def = vsv_sched_wanted(p, s) ? vsv_pager_defs(p, w, s, NULL) : NULL;
        for (int b = 0; def && b < nb; b++) {
            const int v = def[b];
            if (v < 0 || vsv_cache_lookup(p, s, b, v) >= 0 || vsv_cache_lookup(p, s + ns, b, v) >= 0)
                continue;
            const track *T = &p->tracks[(size_t)s * nb + b];
            if (T->busy)
                continue;
            int absolute = 0;
            if (T->codes && T->step > v && payloads_in(p, s, b, v, T->step, &absolute) >= 0 && !absolute)
                continue; /* undoing from the track is as cheap */
            int a = v, k;
            while (vsv_brick_delta(k = vsv_pager_kind(p, a, s, b)) || k == VSV_BRICK_UNCHANGED)
                if (--a < 0)
                    break;
            if (a < 0 || k < 0 || k == VSV_BRICK_EMPTY)
                continue; /* damage, reported by the get that needs it; or nothing to walk */
            *j = (job){.s = s,
                       .b = b,
                       .n = 0,
                       .step = j->step,
                       .ent = j->ent,
                       .out = j->out,
                       .track = -1,
                       .from = a,
                       .fresh = 1,
                       .copy = -1,
                       .ck_step = j->ck_step,
                       .ck_ent = j->ck_ent,
                       .ck_buf = j->ck_buf};
            keep_states(p, j, v);
            if (!j->nck)
                return 0; /* no room */
            const long n = payloads_in(p, s, b, a, j->ck_step[j->nck - 1], &absolute);
            j->payloads = n > 0 ? (int)n : 0;
            return 1;
        }
    }
    return 0;
}

/* Runs job j with decoder d (outside the lock: it owns the job's buffers
 * and track; the payloads' transfers happen here); scratch holds the codes
 * when the job has no track. 0, or the decoder's error (VSV_EIO for a
 * transfer that failed, a damage code) with its text in msg. */
int vsv_pager_job_run(vsv_pager *p, vsv_decoder *d, job *j, uint16_t *scratch, char *msg, size_t cap)
{
    const int n = p->info.brick;
    const size_t cells = (size_t)n * n * n;
    uint16_t *codes = j->codes ? j->codes : scratch;
    int org[3], ext[3];
    vsv_file_brick_box(p->f, j->b, org, ext);
    const int partial = ext[0] < n || ext[1] < n || ext[2] < n;
    if (j->fresh && partial) /* cells outside the grid: code 0, as vsv_decoder_brick_codes */
        memset(codes, 0, cells * sizeof *codes);
    if (j->copy >= 0) /* whole bricks: cells outside the grid are 0 in a checkpoint too */
        memcpy(codes, j->copy_codes, cells * sizeof *codes);
    int t = j->rev ? j->from : j->from - 1, c = 0;
    for (int o = 0; o < j->n; o++) {
        const int i = j->rev ? j->n - 1 - o : o; /* undoing: the outputs from the highest down */
        while (t < j->step[i]) {
            const int rc = vsv_decoder_brick_advance(d, ++t, j->s, j->b, codes);
            if (rc) {
                snprintf(msg, cap, "%s", vsv_decoder_error(d));
                return rc;
            }
            if (c < j->nck && j->ck_step[c] == t)
                memcpy(j->ck_buf[c++], codes, cells * sizeof *codes);
        }
        while (t > j->step[i]) {
            const int rc = vsv_decoder_brick_retreat(d, t--, j->s, j->b, codes);
            if (rc) {
                snprintf(msg, cap, "%s", vsv_decoder_error(d));
                return rc;
            }
        }
        vsv_file_dequantise_brick(p->f, j->s, j->b, codes, j->out[i]); /* outside the grid: the empty value */
    }
    while (c < j->nck) { /* a walk that only keeps states (vsv_pager_job_prewalk) */
        const int rc = vsv_decoder_brick_advance(d, ++t, j->s, j->b, codes);
        if (rc) {
            snprintf(msg, cap, "%s", vsv_decoder_error(d));
            return rc;
        }
        if (j->ck_step[c] == t)
            memcpy(j->ck_buf[c++], codes, cells * sizeof *codes);
    }
    return 0;
}

/* Marks j's outputs as rc says and releases them and its track (under the
 * lock): 0 decoded; damage FAILED and VSV_EIO STALLED, each keeping rc and
 * msg (in its brick buffer, unused then); else (a chunk index not fetched
 * yet, out of memory) dropped, to be made again. With keep_last the last
 * output (the step the caller asked for: outputs ascend and the others
 * precede it) stays pinned for the caller when decoded. */
void vsv_pager_job_finish(vsv_pager *p, job *j, int rc, double secs, int keep_last, const char *msg)
{
    const int ok = !rc, state = ok ? READY : rc == VSV_EIO ? STALLED : vsv_pager_damage(rc) ? FAILED : -1;
    if (state == STALLED)
        vsv_pager_stalled(p, msg);
    const size_t room = p->brick_bytes < 512 ? p->brick_bytes : 512;
    for (int i = 0; i < j->n; i++) {
        const int e = j->ent[i];
        if (state < 0) {
            vsv_cache_drop(p, e);
            continue;
        }
        p->ent[e].state = state;
        p->ent[e].why = rc;
        if (ok) {
            p->st.bricks_decoded++;
            p->st.bytes_decoded += p->brick_bytes;
        } else {
            snprintf(p->ent[e].data, room, "%s", msg);
        }
        if (!(ok && keep_last && i == j->n - 1))
            vsv_cache_unpin(p, e);
    }
    if (ok)
        p->st.payloads_decoded += (uint64_t)j->payloads;
    /* the walk's checkpoints, lowest first (evicted first: needed last);
     * each once, at the state it is keyed by */
    for (int i = 0; i < j->nck; i++) {
        const int e = j->ck_ent[i];
        if (p->ent[e].step != j->ck_step[i])
            continue;
        p->ent[e].state = ok ? READY : FAILED;
        vsv_cache_unpin(p, e);
        if (!ok)
            vsv_cache_drop(p, e);
    }
    j->nck = 0;
    if (j->copy >= 0) { /* consumed: the track (or the output) holds that state now */
        entry *E = &p->ent[j->copy];
        E->halves &= ~(1 << j->copy_half);
        vsv_cache_unpin(p, j->copy);
        if (!E->halves)
            vsv_cache_drop(p, j->copy);
        j->copy = -1;
    }
    if (j->track >= 0) {
        track *T = &p->tracks[j->track];
        T->busy = 0;
        T->step = !ok ? -1 : j->rev ? j->step[0] : j->step[j->n - 1];
        p->pinned -= p->codes_bytes;
        vsv_lru_push(&p->tlru, p->tracks, sizeof *p->tracks, j->track);
        T->listed = 1;
        j->track = -1;
        if (p->idle) { /* a worker may have skipped this brick for its busy track */
            p->kick++;
            pthread_cond_broadcast(&p->work);
        }
    }
    p->st.decode_seconds += secs;
    pthread_cond_broadcast(&p->ready);
}

void *vsv_pager_worker(void *arg)
{
    wslot *ws = arg;
    vsv_pager *p = ws->p;
    const int w = ws->index;
    free(ws);
    vsv_decoder *d = p->dec[w];
    job *j = &p->jobs[w];
    char msg[512];
    pthread_mutex_lock(&p->mu);
    while (!p->quit) {
        if (vsv_pager_fetch_missing(p)) /* a chunk index the window needs */
            continue;
        const int got = vsv_sched_next(p, j);
        if (got < 0 && got != VSV_EAGAIN && got != VSV_ENOMEM)
            continue; /* a job that failed at once: its bricks marked, look again */
        if (got <= 0) {
            if (p->missing >= 0)
                continue;
            const int gen = p->gen, kick = p->kick;
            p->idle++;
            while (!p->quit && gen == p->gen && kick == p->kick)
                pthread_cond_wait(&p->work, &p->mu);
            p->idle--;
            continue;
        }
        pthread_mutex_unlock(&p->mu);
        const double t0 = vsv_pager_now();
        const int rc = vsv_pager_job_run(p, d, j, p->scratch[w], msg, sizeof msg);
        const double t1 = vsv_pager_now();
        pthread_mutex_lock(&p->mu);
        if (rc)
            vsv_pager_set_err(p, "%s", msg);
        vsv_pager_job_finish(p, j, rc, t1 - t0, 0, msg);
        vsv_cache_make_room(p, 0, 1);
    }
    pthread_mutex_unlock(&p->mu);
    return NULL;
}
