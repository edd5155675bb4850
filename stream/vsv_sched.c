/* vsv_sched.c — the pager's prefetch scheduler: the window of steps ahead
 * of the playhead in the direction of play, and the next brick a worker
 * decodes. */
#include "vsv_pager_internal.h"

#include <stdlib.h>

/* The step d frames ahead of the playhead (0: the one on screen), or -1
 * past the list of steps ahead. */
int vsv_sched_ahead(const vsv_pager *p, int d) { return d == 0 ? p->head : d <= p->nnext ? p->next[d - 1] : -1; }

/* Marks every cached brick the prefetch window needs (under the lock, once
 * per playhead change) and sizes the window: as many steps as fit beside the
 * current one. A step of the window whose chunk is damaged is passed over:
 * the get that needs it says why, other steps play. */
void vsv_sched_mark_window(vsv_pager *p)
{
    if (p->marked_gen == p->gen)
        return;
    p->marked_gen = p->gen;
    vsv_cache_new_window(p);
    p->mark++;
    p->scan_d = p->scan_s = p->scan_b = 0;
    size_t unit = 0;
    for (int s = 0; s < p->info.nspecies; s++) {
        const int *def = vsv_sched_wanted(p, s) ? vsv_pager_defs(p, p->head, s, NULL) : NULL;
        for (int b = 0; def && b < p->info.nbricks; b++)
            unit += def[b] >= 0 ? p->brick_bytes : 0;
    }
    if (unit > p->step_bytes)
        p->step_bytes = unit;
    /* playing backward, checkpoints of a keyframe group's states (codes:
     * half a step's floats each) save a payload a brick each, where a step
     * of the window only decodes earlier: they come first */
    const size_t ck =
        p->incremental && p->dir < 0 && p->info.keyframe > 2 ? (size_t)(p->info.keyframe - 2) * (p->step_bytes / 2) : 0;
    const size_t unit_bytes = p->step_bytes ? p->step_bytes : p->brick_bytes;
    const size_t room = p->budget > ck ? p->budget - ck : 0;
    long fit = (long)(room / unit_bytes) - 2;
    const long fit_all = (long)(p->budget / unit_bytes) - 2;
    if (fit < 1 && fit_all >= 1) /* but a step ahead when it fits: a player shows it without waiting */
        fit = 1;
    int depth = (int)(fit < 0 ? 0 : fit > p->ahead ? p->ahead : fit);
    if (p->dir == 0 && depth > 1)
        depth = 1;
    p->depth = depth;
    for (int d = 0; d <= depth; d++) {
        const int t = vsv_sched_ahead(p, d);
        if (t < 0)
            break;
        for (int s = 0; s < p->info.nspecies; s++) {
            const int *def = vsv_sched_wanted(p, s) ? vsv_pager_defs(p, t, s, NULL) : NULL;
            for (int b = 0; def && b < p->info.nbricks; b++) {
                const int e = def[b] >= 0 ? vsv_cache_lookup(p, s, b, def[b]) : -1;
                if (e >= 0)
                    vsv_cache_mark(p, e);
            }
        }
    }
}

/* Whether brick b of species s waits for its track (a job is using it). */
static int track_busy(const vsv_pager *p, int s, int b)
{
    return p->incremental && p->tracks[(size_t)s * p->info.nbricks + b].busy;
}

/* Whether brick b of species s at defining step v is in the cache (under
 * the lock): decoded, being decoded, damaged, or left by a failed transfer
 * a moment ago; one left so earlier is dropped, to be made again. */
static int cached(vsv_pager *p, int s, int b, int v, int due)
{
    const int e = vsv_cache_lookup(p, s, b, v);
    if (e >= 0 && due && p->ent[e].state == STALLED && !p->ent[e].pins) {
        vsv_cache_drop(p, e);
        return 0;
    }
    return e >= 0;
}

/* The next decode job ahead of the playhead (under the lock): 1 with j
 * made (its entries claimed, LOADING), 0 when there is nothing to do
 * within the budget. A brick whose track is busy is left for later: the
 * job using the track carries it to a nearer state. */
int vsv_sched_next(vsv_pager *p, job *j)
{
    vsv_sched_mark_window(p);
    const int due = vsv_pager_due(p);
    /* finish the step under way first, even if the playhead has moved past
     * it: when decoding cannot keep up, complete steps are what the player
     * can show (the newest complete one), half-decoded ones are not */
    if (p->focus >= 0 && p->focus_dir == p->dir && p->depth > 0) {
        int blocked = 0;
        for (int s = 0; s < p->info.nspecies; s++) {
            const int *def = vsv_sched_wanted(p, s) ? vsv_pager_defs(p, p->focus, s, NULL) : NULL;
            for (int b = 0; def && b < p->info.nbricks; b++) {
                if (def[b] < 0 || cached(p, s, b, def[b], due))
                    continue;
                if (track_busy(p, s, b)) {
                    blocked = 1;
                    continue;
                }
                if (!vsv_cache_make_room(p, p->brick_bytes, 0))
                    goto scan;
                const int rc = vsv_pager_job_make(p, j, s, b, def[b]);
                return rc ? rc : 1;
            }
        }
        if (!blocked)
            p->focus = -1; /* complete */
    }
scan:;
    /* resume where the last scan of this window stopped: what lies before
     * it was decoded or claimed (an eviction changes the window's mark) */
    int held = 0; /* the resume point stays at a brick left for its busy track */
    for (int d = p->scan_d; d <= p->depth; d++) {
        const int t = vsv_sched_ahead(p, d);
        if (t < 0)
            break;
        for (int s = d == p->scan_d ? p->scan_s : 0; s < p->info.nspecies; s++) {
            if (!vsv_sched_wanted(p, s))
                continue;
            const int *def = vsv_pager_defs(p, t, s, NULL);
            if (!def)
                continue; /* a damaged chunk (the get that needs it says why), or one to fetch */
            for (int b = d == p->scan_d && s == p->scan_s ? p->scan_b : 0; b < p->info.nbricks; b++) {
                if (def[b] < 0 || cached(p, s, b, def[b], due))
                    continue;
                if (!held)
                    p->scan_d = d, p->scan_s = s, p->scan_b = b;
                if (track_busy(p, s, b)) {
                    held = 1;
                    continue;
                }
                if (!vsv_cache_make_room(p, p->brick_bytes, 0))
                    return 0;
                p->focus = t;
                p->focus_dir = p->dir;
                const int rc = vsv_pager_job_make(p, j, s, b, def[b]);
                return rc ? rc : 1;
            }
        }
    }
    if (!held)
        p->scan_d = p->depth + 1;
    return !held && vsv_pager_job_prewalk(p, j);
}
