/* vsv_room.h — one decoded copy of the steps being played for every render
 * process of a display that forks one per wall (FreeVR), and the tick that
 * keeps every wall on the same step.
 *
 * Made before the fork, in one anonymous MAP_SHARED mapping, so every
 * process sees it at the same address: the pointers it holds (decoded
 * bricks) mean the same memory everywhere. Inside:
 *  - an arena for the pager's decoded bricks (vsv_room_slab, given as
 *    vsv_pager_opts.slab_alloc to the one pager, in the process that reads
 *    the input): bricks are decoded once, whatever the number of walls;
 *  - two slots, each a published tick: the step, its time, the species'
 *    volumes (brick pointers, ranges and keys, pinned in the pager by the
 *    publishing process) and the back end's own plain data (play state,
 *    placement, wand);
 *  - one record per window: its process, name, frame count and the last
 *    tick it has shown.
 *
 * The time lock: a window takes the newest tick when it starts a frame
 * (vsv_room_frame), which also says that the frame before it (the tick
 * taken then) is on the screen. The publisher moves on to a new tick only
 * when every window has shown the current one (vsv_room_can_publish):
 * every window draws every tick, a slow wall slows the ticks rather than
 * splitting the room, and the slot a new tick overwrites (the one before
 * the current) is read by no window any more, so its pins can go.
 *
 * One process-shared, robust mutex guards the header and the slots: a
 * process that dies holding it leaves it usable. Every call is cheap (no
 * decoding, no allocation after the first frame). */
#ifndef VSV_ROOM_H
#define VSV_ROOM_H

#include "vsv_pager.h"

#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

typedef struct vsv_room vsv_room;

typedef struct vsv_room_opts {
    size_t arena_bytes;    /* the decoded bricks' arena (virtual: pages cost
                              memory only once written) */
    int nspecies, nbricks; /* of the file */
    int windows;           /* most windows that join (at least 1) */
    size_t user_bytes;     /* the back end's data published with each tick */
} vsv_room_opts;

/* Maps the room (before any fork). 0, or VSV_EINVAL / VSV_ENOMEM with the
 * reason in err (caller buffer of cap bytes). Caller frees with
 * vsv_room_free in every process that goes on after using it. */
int vsv_room_create(const vsv_room_opts *o, vsv_room **out, char *err, size_t cap);
/* Unmaps it in this process (the publisher: after vsv_room_unpin and
 * vsv_pager_free). NULL is fine. */
void vsv_room_free(vsv_room *r);

/* The pager's slab allocator over the arena (vsv_pager_opts.slab_alloc,
 * slab_ctx = the room): bytes aligned to 2 MiB, or NULL once it is full. */
void *vsv_room_slab(void *room, size_t bytes);
/* Bytes of the arena handed out so far, and in all. */
size_t vsv_room_arena_used(const vsv_room *r);
size_t vsv_room_arena_size(const vsv_room *r);
/* The clock the room stamps windows and views with: CLOCK_MONOTONIC
 * seconds, the same in every process. */
double vsv_room_clock(void);

/* ------------------------------------------------------------- publisher */

/* 1 when the room has a tick and every window that joined has shown it, or
 * no tick was published yet. */
int vsv_room_can_publish(vsv_room *r);
/* Publishes the next tick, when vsv_room_can_publish: step (its time, and
 * damage: why it is not drawn, or NULL), and for each species s with
 * vols[s] non-NULL that volume (of pager pg, borrowed for the call: its
 * bricks are pinned again for the slot, so the caller may move on), and
 * user_bytes of user (copied). The slot it takes over is released. A
 * species showing the same step as in the tick shown keeps its load (its
 * vsv_volume.gen in the windows): renderers keep what they derived. 0 with
 * the new tick (1, 2, ...) in *tick (may be NULL); VSV_EAGAIN when a window
 * has not shown the current tick yet (nothing done); another VSV_E* code
 * with the reason in err (nothing published). */
int vsv_room_publish(vsv_room *r, vsv_pager *pg, int step, int64_t time, const char *damage,
                     const vsv_volume *const *vols, const void *user, int64_t *tick, char *err, size_t cap);
/* Releases every pin the room holds (before vsv_pager_free). */
void vsv_room_unpin(vsv_room *r);
/* The tick published last (0: none). */
int64_t vsv_room_tick(vsv_room *r);

/* A window as the publisher sees it: plain info. */
typedef struct vsv_room_window {
    pid_t pid; /* the process that draws it */
    char name[64];
    uint64_t frames; /* frames it has started */
    int64_t shown;   /* the newest tick it has shown (-1: none yet) */
    double last;     /* CLOCK_MONOTONIC seconds of its last frame start */
    double rate;     /* its frames per second, over about a second */
    double report;   /* what it said last with vsv_room_report */
} vsv_room_window;
/* Copies up to cap windows' records into w; returns how many joined. */
int vsv_room_windows(vsv_room *r, vsv_room_window *w, int cap);

/* ---------------------------------------------------------------- windows */

/* A window joins (from its render process): its index, or -1 when the room
 * is full. */
int vsv_room_join(vsv_room *r, const char *name);

/* What a window draws in one frame: the tick, step, time and damage, the
 * volumes per species (NULL: not drawn) and the back end's data. Owned by
 * the room in this process: the volumes and damage valid until a window of
 * this process takes a tick two ticks newer, the data until this window's
 * next vsv_room_frame. */
typedef struct vsv_room_view {
    int64_t tick;
    int step;
    int64_t time;
    const char *damage;            /* NULL, or why the step is not drawn */
    const vsv_volume *const *vols; /* nspecies entries */
    const void *user;              /* user_bytes */
    double when;                   /* vsv_room_clock() when it was taken */
} vsv_room_view;

/* Window w starts a frame: the frame before it is shown, and it takes the
 * newest tick into view. 0, or -1 when nothing was published yet (view
 * untouched) or w is not a window of this room. */
int vsv_room_frame(vsv_room *r, int w, vsv_room_view *view);

/* Window w says a number to the publisher (the back end's own meaning). */
void vsv_room_report(vsv_room *r, int w, double v);

/* ------------------------------------------------------------- failures */

/* A process cannot go on: msg says why and code (> 0) is the exit status
 * it asks for (the first failure is kept), for the process that ends the
 * run. */
void vsv_room_fail(vsv_room *r, int code, const char *msg);
/* The code of a process's failure, with its message into buf (cap bytes;
 * may be NULL); 0 when none failed. */
int vsv_room_failed(vsv_room *r, char *buf, size_t cap);

#endif
