/* vsv_sched.c — the pager's prefetch scheduler: the window of steps ahead
 * of the playhead in the direction of play, and the next brick a worker
 * decodes. */
#include "vsv_pager_internal.h"

#include <stdlib.h>

/* The step d frames ahead of the playhead, or -1 past an end. */
int vsv_sched_ahead(const vsv_pager *p, int d)
{
    const int n = p->info.nsteps;
    long t = p->head + (long)d * p->stride * (p->dir ? p->dir : 1);
    if (p->dir == 0 && d > 1)
        return -1; /* paused: the step on screen and its neighbours */
    if (p->dir == 0 && d == 1)
        t = p->head + 1;
    if (t < 0 || t >= n) {
        if (!p->loop)
            return -1;
        t = ((t % n) + n) % n;
    }
    return (int)t;
}

/* Marks every cached brick the prefetch window needs (under the lock, once
 * per playhead change) and sizes the window: as many steps as fit beside the
 * current one. 0 on a damaged chunk. */
int vsv_sched_mark_window(vsv_pager *p)
{
    if (p->marked_gen == p->gen)
        return 1;
    p->marked_gen = p->gen;
    p->mark++;
    p->scan_d = p->scan_s = p->scan_b = 0;
    size_t unit = 0;
    for (int s = 0; s < p->info.nspecies; s++) {
        const int *def = vsv_sched_wanted(p, s) ? vsv_pager_defs(p, p->head, s) : NULL;
        for (int b = 0; def && b < p->info.nbricks; b++)
            unit += def[b] >= 0 ? p->brick_bytes : 0;
    }
    if (unit > p->step_bytes)
        p->step_bytes = unit;
    const long fit = (long)(p->budget / (p->step_bytes ? p->step_bytes : p->brick_bytes)) - 2;
    int depth = (int)(fit < 0 ? 0 : fit > p->ahead ? p->ahead : fit);
    if (p->dir == 0 && depth > 1)
        depth = 1;
    p->depth = depth;
    for (int d = 0; d <= depth; d++) {
        const int t = vsv_sched_ahead(p, d);
        if (t < 0)
            break;
        for (int s = 0; s < p->info.nspecies; s++) {
            const int *def = vsv_sched_wanted(p, s) ? vsv_pager_defs(p, t, s) : NULL;
            if (vsv_sched_wanted(p, s) && !def)
                return 0;
            for (int b = 0; def && b < p->info.nbricks; b++) {
                const int e = def[b] >= 0 ? vsv_cache_lookup(p, s, b, def[b]) : -1;
                if (e >= 0)
                    p->ent[e].mark = p->mark;
            }
        }
    }
    return 1;
}

/* The next brick to decode ahead (under the lock): claims it (LOADING) and
 * returns the entry, or -1 when there is nothing to do within the budget. */
int vsv_sched_next(vsv_pager *p, int *s_out, int *b_out, int *step_out)
{
    if (!vsv_sched_mark_window(p))
        return -1;
    /* finish the step under way first, even if the playhead has moved past
     * it: when decoding cannot keep up, complete steps are what the player
     * can show (the newest complete one), half-decoded ones are not */
    if (p->focus >= 0 && p->focus_dir == p->dir && p->depth > 0) {
        for (int s = 0; s < p->info.nspecies; s++) {
            const int *def = vsv_sched_wanted(p, s) ? vsv_pager_defs(p, p->focus, s) : NULL;
            for (int b = 0; def && b < p->info.nbricks; b++) {
                if (def[b] < 0 || vsv_cache_lookup(p, s, b, def[b]) >= 0)
                    continue;
                if (!vsv_cache_make_room(p, p->brick_bytes, 0))
                    goto scan;
                const int ne = vsv_cache_claim(p, s, b, def[b]);
                if (ne >= 0)
                    *s_out = s, *b_out = b, *step_out = def[b];
                return ne;
            }
        }
        p->focus = -1; /* complete */
    }
scan:
    /* resume where the last scan of this window stopped: what lies before
     * it was decoded or claimed (an eviction changes the window's mark) */
    for (int d = p->scan_d; d <= p->depth; d++) {
        const int t = vsv_sched_ahead(p, d);
        if (t < 0)
            break;
        for (int s = d == p->scan_d ? p->scan_s : 0; s < p->info.nspecies; s++) {
            if (!vsv_sched_wanted(p, s))
                continue;
            const int *def = vsv_pager_defs(p, t, s);
            if (!def)
                return -1;
            for (int b = d == p->scan_d && s == p->scan_s ? p->scan_b : 0; b < p->info.nbricks; b++) {
                if (def[b] < 0 || vsv_cache_lookup(p, s, b, def[b]) >= 0)
                    continue;
                p->scan_d = d, p->scan_s = s, p->scan_b = b;
                if (!vsv_cache_make_room(p, p->brick_bytes, 0))
                    return -1;
                p->focus = t;
                p->focus_dir = p->dir;
                const int ne = vsv_cache_claim(p, s, b, def[b]);
                if (ne >= 0)
                    *s_out = s, *b_out = b, *step_out = def[b];
                return ne;
            }
        }
    }
    p->scan_d = p->depth + 1;
    return -1;
}
