/* vsv_pager.h — the brick pager: decoded bricks of a .vsv in a cache
 * bounded by a byte budget, pinned while a renderer reads them, decoded ahead
 * of the playhead on worker threads in the direction of play.
 *
 * The unit of caching is one brick of one species in one state: a brick
 * that a step leaves UNCHANGED is the same cache entry for every step that
 * shares it, and a brick that is all code 0 (EMPTY, or no data) takes no
 * memory.
 *
 * Decoding: the pager keeps, per species and brick, the decoder state (the
 * brick's quantised codes at the last step decoded), so playing forward
 * costs one payload per changed brick per step. Playing backward, the
 * state steps back by undoing a delta (vsv_decoder_brick_retreat), also one
 * payload per changed brick per step; only entering a keyframe group from
 * above walks from the group's keyframe to its top step, serving the steps
 * of the group that the prefetch window holds on the way and keeping the
 * states it passes below them as checkpoints (codes, while they fit), which
 * the next steps backward then copy instead of decoding. Each decode takes
 * the cheapest way in payloads. A seek costs at most K
 * payloads per brick (K = the file's keyframe interval).
 *
 * Budget: everything the pager allocates — decoded bricks, decoder state,
 * the tables of defining steps (stats.fixed_bytes) — counts against the
 * budget, and what is evicted returns to the pager's buffer pools. The
 * bytes held stay within the budget except for bricks that are pinned (held
 * in a volume) or being decoded (stats.pinned_bytes): a budget smaller than
 * one time step degrades to decoding on demand, never to a deadlock.
 * Prefetch decodes only what fits beside the current step (ahead =
 * min(ahead option, budget / step size - 2) of the steps listed by
 * vsv_pager_playhead); playing backward the budget
 * first sets aside K - 2 checkpoints of half a step each). Eviction takes
 * the least recently used brick outside the prefetch window, then
 * checkpoints, then idle decoder tracks, then bricks inside the window.
 *
 * Failures keep their kind. A damaged chunk index or brick payload fails
 * the vsv_pager_get that needs it (VSV_ECORRUPT, with VSV_ECODEC and the
 * like folded into it, or VSV_ETRUNC for a file cut while read) with a
 * message naming the file, step, species, brick and offset
 * (vsv_pager_error); other steps and species keep playing, and the brick
 * stays damaged: a worker's failure is recorded in the cache, a get without
 * wait reports it, a get with wait tries once more. A transfer that fails
 * (a byte source: a dropped connection, a stalled server) is not damage:
 * the get says VSV_EIO with the source's message, and what it left is
 * tried again a second later (VSV_PAGER_RETRY), by the workers or the next
 * get that needs it. Out of memory is VSV_ENOMEM from the get. Nothing
 * fails silently and nothing is retried in a loop.
 *
 * Transfers: no call holds the pager's lock while it waits for a server, so
 * a get without wait, vsv_pager_ready, vsv_pager_playhead and the rest
 * return at once while a worker waits on a stalled one: the workers fetch
 * what the window needs (chunk indexes, payloads); a get without wait of a
 * step whose chunk index is not fetched yet is VSV_EAGAIN. A program
 * quitting ends the transfers under way with vsv_file_interrupt before
 * vsv_pager_free, which joins the workers.
 *
 * Thread safety: every call may be made from any thread (one mutex; see
 * vsv_pager_internal.h for the lock discipline), except that a volume is
 * used by one thread at a time; the vsv_file must outlive the pager. The
 * pager reads the file only through the reader's calls (chunk index, brick
 * kinds, octree, decoder), never its bytes, so any byte source behind the
 * vsv_file serves it. */
#ifndef VSV_PAGER_H
#define VSV_PAGER_H

#include "vsv_format.h"

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

VSV_API_BEGIN

typedef struct vsv_pager vsv_pager;

#define VSV_PAGER_AHEAD 16 /* steps decoded ahead by default */

typedef struct vsv_pager_opts {
    size_t budget;     /* bytes of decoded bricks; 0 = a quarter of physical memory */
    int threads;       /* decode-ahead workers; 0 = one per CPU beyond the first (at least 1); < 0 none */
    int ahead;         /* most steps decoded ahead of the playhead; 0 = VSV_PAGER_AHEAD */
    int from_keyframe; /* 1: keep no decoder state, decode every brick from its
                          last absolute state (the earlier path; benchmarks
                          compare against it) */
    /* Where decoded bricks live: NULL = the heap. Otherwise the pager takes
     * the memory of its decoded bricks (and of the backward-play checkpoints
     * that share their buffers; never the per-brick decoder state) in slabs
     * of `bytes` (2 MiB, 2 MiB aligned) from slab_alloc(slab_ctx, bytes),
     * which returns NULL when it has no more (the get that needed it fails
     * with VSV_ENOMEM), and never gives a slab back: the caller owns that
     * memory and frees it after vsv_pager_free. Memory shared between
     * processes (viewer/vsv_room.h) makes the bricks of vsv_pager_get
     * readable by every process that maps it at the same address. Called
     * under the pager's lock, from any of its threads. */
    void *(*slab_alloc)(void *slab_ctx, size_t bytes);
    void *slab_ctx;
} vsv_pager_opts;

void vsv_pager_opts_init(vsv_pager_opts *o);

typedef struct vsv_pager_stats {
    uint64_t hits, misses;      /* brick lookups by vsv_pager_get: found decoded / not */
    uint64_t bricks_decoded;    /* by workers and by callers */
    uint64_t bytes_decoded;     /* decoded float bytes produced */
    uint64_t payloads_decoded;  /* brick payloads (absolute or delta) decompressed and applied */
    double decode_seconds;      /* summed over threads */
    uint64_t stalls;            /* gets that could not be served without waiting */
    uint64_t evictions;         /* bricks dropped to stay within the budget */
    int prefetch_depth;         /* steps ahead the workers aim for now */
    size_t budget;              /* the budget in force */
    size_t bytes;               /* decoded bytes held now (cached + pinned + decoding) */
    size_t pinned_bytes;        /* of which pinned or being decoded */
    size_t peak_bytes;          /* most bytes held at once */
    size_t track_bytes;         /* of bytes: decoder state (codes per species and brick, and checkpoints) */
    size_t fixed_bytes;         /* of bytes: the pager's fixed tables */
    uint64_t transfer_failures; /* transfers that failed (a byte source), each tried again later */
} vsv_pager_stats;

/* Starts the pager over f (which must outlive it). */
int vsv_pager_open(vsv_file *f, const vsv_pager_opts *o, vsv_pager **out);
/* Stops the workers and frees every brick. Volumes of the pager still out
 * lose their bricks (step -1) and stay to be freed with vsv_volume_free. */
void vsv_pager_free(vsv_pager *p);
/* The last error's message (names the file, step, species, brick): a copy
 * taken under the lock, borrowed until this thread's next call. */
const char *vsv_pager_error(const vsv_pager *p);

/* Where playback is: the step on screen, the direction (+1, -1, 0 paused),
 * the steps the next shown frames will show (next[0 .. n-1], nearest first,
 * each once: vsv_clock_ahead predicts them; the first `ahead` + 1 are read),
 * and which species are wanted (nspecies flags; NULL = all). Workers decode
 * the listed steps in order, as many as the budget holds beside the one on
 * screen, so a step the display will skip costs no floats. next NULL: the
 * steps after `step` one by one in the direction of play, to the end
 * (paused: the next one). Cheap; call it every frame. */
void vsv_pager_playhead(vsv_pager *p, int step, int dir, const int *next, int n, const unsigned char *species);

/* A volume shell to receive pinned bricks (no brick storage of its own);
 * NULL when out of memory. Caller frees with vsv_volume_free (which unpins
 * what it holds), before or after the pager. */
vsv_volume *vsv_pager_volume_new(vsv_pager *p);

/* Fills v (a volume of vsv_pager_volume_new(p), else VSV_EINVAL) with
 * species s at step, every brick pinned until vsv_pager_put.
 * wait: fetch and decode what is missing on this thread (and wait for bricks
 * and chunk indexes other threads are fetching or decoding); otherwise
 * VSV_EAGAIN when any brick is not decoded yet (nothing stays pinned then;
 * counted as a stall), never waiting for a transfer. Errors (nothing stays
 * pinned; vsv_pager_error says why): VSV_ECORRUPT or VSV_ETRUNC, damage;
 * VSV_EIO, a transfer that failed (not damage: tried again later);
 * VSV_ENOMEM. A v that holds bricks is released first. */
int vsv_pager_get(vsv_pager *p, int step, int s, int wait, vsv_volume *v);
/* Unpins v's bricks (v->step becomes -1); a volume not of p is left alone. */
void vsv_pager_put(vsv_pager *p, vsv_volume *v);
/* 1 when every wanted species of step is decoded (species as in playhead);
 * -1 when one is known to fail (its chunk index or a brick failed its
 * checks, or a transfer for it failed: vsv_pager_get of it says why); else
 * 0. Never waits for a transfer. */
int vsv_pager_ready(vsv_pager *p, int step, const unsigned char *species);
/* As vsv_pager_ready, but while the answer is 0 waits up to `seconds`
 * (at most 10) for the workers to decode what is missing: for a step the
 * playhead lists (a step nobody decodes just costs the wait). */
int vsv_pager_wait_ready(vsv_pager *p, int step, const unsigned char *species, double seconds);

void vsv_pager_stats_get(vsv_pager *p, vsv_pager_stats *st);
/* Counts a stall the caller saw (a step it wanted was not decoded in time). */
void vsv_pager_stall(vsv_pager *p);

VSV_API_END

#ifdef __cplusplus
}
#endif

#endif
