/* vsv_room.c — see vsv_room.h. The mapping: the header (lock, tick,
 * windows), two slots, then the brick arena on a 2 MiB boundary. The
 * publisher's pins live in its own heap (pager volume shells per slot and
 * species); the slots hold copies of what a renderer reads of them. */
#include "vsv_room.h"

#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#define SLAB_ALIGN ((size_t)2 << 20)
#define MAX_WINDOWS 64

/* what a renderer needs of one species' volume at the slot's step */
typedef struct spec {
    int present;
    int nx, ny, nz, brick, bdim[3], nbricks, shift, step, species;
    uint64_t gen;
    float empty_value;
    int64_t time;
    int has_keys;
} spec;

typedef struct slot {
    int64_t tick;
    int step;
    int64_t time;
    int damaged;
    char damage[512];
} slot;

typedef struct win {
    pid_t pid;
    char name[64];
    uint64_t frames;
    int64_t taken; /* the tick its current frame draws (-1 none) */
    int64_t shown; /* the tick of its frame before (-1 none) */
    double last, rate, rate_t0;
    uint64_t rate_f0;
    double report;
} win;

typedef struct head {
    pthread_mutex_t mu;
    int64_t tick; /* the newest published; 0 none */
    int cur;      /* its slot */
    int nwin;
    win w[MAX_WINDOWS];
    size_t arena_used;
    int failed;
    char failure[1024];
} head;

struct vsv_room {
    unsigned char *map;
    size_t map_bytes;
    head *h;
    int ns, nb, maxwin;
    size_t user_bytes;
    size_t slot_bytes, off_spec, off_bricks, off_bmin, off_bmax, off_bkey, off_user;
    unsigned char *slots; /* two of slot_bytes */
    unsigned char *arena;
    size_t arena_bytes;
    /* the publisher's pins: [slot][species] */
    vsv_volume **pins;
    vsv_pager *pin_pager;
    /* the views in the process that draws: per species, two volumes (the
     * loads of the two live ticks), each with the publisher's gen behind it
     * and when it was taken last; per window its volume pointers and data */
    vsv_volume *local;  /* [species][2] */
    uint64_t *seen_gen; /* [species][2] */
    uint64_t *used;     /* [species][2] */
    uint64_t takes;
    const vsv_volume **vptr; /* [window][species] */
    unsigned char *user;     /* [window] user_bytes */
};

double vsv_room_clock(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static size_t align_up(size_t n, size_t a) { return (n + a - 1) / a * a; }

/* The lock; a holder that died leaves it consistent again (its writes are
 * plain values: the worst is one torn window record). */
static void lock(vsv_room *r)
{
    if (pthread_mutex_lock(&r->h->mu) == EOWNERDEAD)
        pthread_mutex_consistent(&r->h->mu);
}
static void unlock(vsv_room *r) { pthread_mutex_unlock(&r->h->mu); }

static unsigned char *slot_at(const vsv_room *r, int k) { return r->slots + (size_t)k * r->slot_bytes; }

int vsv_room_create(const vsv_room_opts *o, vsv_room **out, char *err, size_t cap)
{
    *out = NULL;
    if (o->nspecies < 0 || o->nbricks < 1 || o->windows < 1 || o->windows > MAX_WINDOWS) {
        snprintf(err, cap, "a room of %d windows, %d species, %d bricks: out of range (at most %d windows)", o->windows,
                 o->nspecies, o->nbricks, MAX_WINDOWS);
        return VSV_EINVAL;
    }
    vsv_room *r = calloc(1, sizeof *r);
    if (!r) {
        snprintf(err, cap, "out of memory");
        return VSV_ENOMEM;
    }
    r->ns = o->nspecies, r->nb = o->nbricks, r->maxwin = o->windows, r->user_bytes = o->user_bytes;
    const size_t ns = (size_t)(r->ns ? r->ns : 1), nb = (size_t)r->nb;
    r->off_spec = align_up(sizeof(slot), 64);
    r->off_bricks = align_up(r->off_spec + ns * sizeof(spec), 64);
    r->off_bmin = align_up(r->off_bricks + ns * nb * sizeof(float *), 64);
    r->off_bmax = align_up(r->off_bmin + ns * nb * sizeof(float), 64);
    r->off_bkey = align_up(r->off_bmax + ns * nb * sizeof(float), 64);
    r->off_user = align_up(r->off_bkey + ns * nb * sizeof(uint64_t), 64);
    r->slot_bytes = align_up(r->off_user + o->user_bytes, 64);
    const size_t before = align_up(align_up(sizeof(head), 64) + 2 * r->slot_bytes, SLAB_ALIGN);
    r->arena_bytes = align_up(o->arena_bytes, SLAB_ALIGN);
    /* one more slab's room so the arena can start on a 2 MiB boundary */
    r->map_bytes = before + r->arena_bytes + SLAB_ALIGN;
    void *m = mmap(NULL, r->map_bytes, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (m == MAP_FAILED) {
        snprintf(err, cap, "cannot map %zu bytes of shared memory for the walls: %s", r->map_bytes, strerror(errno));
        free(r);
        return VSV_ENOMEM;
    }
    r->map = m;
    r->h = m;
    r->slots = r->map + align_up(sizeof(head), 64);
    r->arena = (unsigned char *)align_up((size_t)(r->map + before), SLAB_ALIGN);
    pthread_mutexattr_t a;
    pthread_mutexattr_init(&a);
    pthread_mutexattr_setpshared(&a, PTHREAD_PROCESS_SHARED);
    pthread_mutexattr_setrobust(&a, PTHREAD_MUTEX_ROBUST);
    const int rc = pthread_mutex_init(&r->h->mu, &a);
    pthread_mutexattr_destroy(&a);
    r->pins = calloc(2 * ns, sizeof *r->pins);
    if (rc || !r->pins) {
        snprintf(err, cap, "cannot set up the walls' lock: %s", rc ? strerror(rc) : "out of memory");
        vsv_room_free(r);
        return VSV_ENOMEM;
    }
    *out = r;
    return 0;
}

void vsv_room_free(vsv_room *r)
{
    if (!r)
        return;
    if (r->pins)
        for (int i = 0; i < 2 * (r->ns ? r->ns : 1); i++)
            vsv_volume_free(r->pins[i]);
    free(r->pins);
    free(r->local);
    free(r->vptr);
    free(r->seen_gen);
    free(r->used);
    free(r->user);
    if (r->map)
        munmap(r->map, r->map_bytes);
    free(r);
}

void *vsv_room_slab(void *room, size_t bytes)
{
    vsv_room *r = room;
    bytes = align_up(bytes, SLAB_ALIGN);
    lock(r);
    void *p = NULL;
    if (r->h->arena_used <= r->arena_bytes && bytes <= r->arena_bytes - r->h->arena_used) {
        p = r->arena + r->h->arena_used;
        r->h->arena_used += bytes;
    }
    unlock(r);
    return p;
}

size_t vsv_room_arena_used(const vsv_room *r) { return r->h->arena_used; }
size_t vsv_room_arena_size(const vsv_room *r) { return r->arena_bytes; }

/* ------------------------------------------------------------- publisher */

/* Under the lock: whether every window has shown the newest tick (none
 * published yet: windows that joined wait for the first). */
static int all_shown(const vsv_room *r)
{
    if (!r->h->tick)
        return 1;
    for (int i = 0; i < r->h->nwin; i++)
        if (r->h->w[i].shown < r->h->tick)
            return 0;
    return 1;
}

int vsv_room_can_publish(vsv_room *r)
{
    lock(r);
    const int ok = all_shown(r);
    unlock(r);
    return ok;
}

int64_t vsv_room_tick(vsv_room *r)
{
    lock(r);
    const int64_t t = r->h->tick;
    unlock(r);
    return t;
}

int vsv_room_publish(vsv_room *r, vsv_pager *pg, int step, int64_t time, const char *damage,
                     const vsv_volume *const *vols, const void *user, int64_t *tick, char *err, size_t cap)
{
    lock(r);
    const int64_t next = r->h->tick + 1;
    const int k = r->h->tick ? 1 - r->h->cur : 0;
    const int ready = all_shown(r);
    unlock(r);
    if (!ready) /* (windows only ever move on: this stays true once seen) */
        return VSV_EAGAIN;
    /* the slot k is read by no window (every one has shown the current
     * tick, in the other slot): pin the new step's bricks there, which
     * releases those of the tick before */
    unsigned char *sl = slot_at(r, k);
    const spec *now = next > 1 ? (const spec *)(slot_at(r, 1 - k) + r->off_spec) : NULL;
    spec *sp = (spec *)(sl + r->off_spec);
    float **bricks = (float **)(sl + r->off_bricks);
    float *bmin = (float *)(sl + r->off_bmin), *bmax = (float *)(sl + r->off_bmax);
    uint64_t *bkey = (uint64_t *)(sl + r->off_bkey);
    const size_t nb = (size_t)r->nb;
    if (pg != r->pin_pager) { /* (a new pager: the shells are its) */
        for (int i = 0; i < 2 * r->ns; i++) {
            vsv_volume_free(r->pins[i]);
            r->pins[i] = NULL;
        }
        r->pin_pager = pg;
    }
    for (int s = 0; s < r->ns; s++) {
        vsv_volume **pin = &r->pins[k * r->ns + s];
        const vsv_volume *v = vols ? vols[s] : NULL;
        if (!v || v->step < 0) {
            if (*pin)
                vsv_pager_put(pg, *pin);
            memset(&sp[s], 0, sizeof sp[s]);
            continue;
        }
        if (!*pin && !(*pin = vsv_pager_volume_new(pg))) {
            snprintf(err, cap, "out of memory");
            return VSV_ENOMEM;
        }
        const int rc = vsv_pager_get(pg, v->step, s, 1, *pin);
        if (rc) {
            snprintf(err, cap, "%s", vsv_pager_error(pg));
            return rc;
        }
        const vsv_volume *p = *pin;
        if (p->nbricks != r->nb) {
            snprintf(err, cap, "a volume of %d bricks in a room of %d", p->nbricks, r->nb);
            return VSV_EINVAL;
        }
        /* the same step of the same species as the tick shown: the same
         * values (and the same cached bricks), so the same load for the
         * renderers, which then keep what they derived from it */
        const uint64_t gen = now && now[s].present && now[s].step == p->step ? now[s].gen : p->gen;
        sp[s] = (spec){1,          p->nx,          p->ny,   p->nz,      p->brick, {p->bdim[0], p->bdim[1], p->bdim[2]},
                       p->nbricks, p->shift,       p->step, p->species, gen,      p->empty_value,
                       p->time,    p->bkey != NULL};
        memcpy(bricks + s * nb, p->bricks, nb * sizeof *bricks);
        memcpy(bmin + s * nb, p->bmin, nb * sizeof *bmin);
        memcpy(bmax + s * nb, p->bmax, nb * sizeof *bmax);
        if (p->bkey)
            memcpy(bkey + s * nb, p->bkey, nb * sizeof *bkey);
    }
    slot *h = (slot *)sl;
    h->tick = next;
    h->step = step;
    h->time = time;
    h->damaged = damage != NULL;
    snprintf(h->damage, sizeof h->damage, "%s", damage ? damage : "");
    if (r->user_bytes)
        memcpy(sl + r->off_user, user, r->user_bytes);
    lock(r); /* the mutex orders the slot's writes before the windows' reads */
    r->h->tick = next;
    r->h->cur = k;
    unlock(r);
    if (tick)
        *tick = next;
    return 0;
}

void vsv_room_unpin(vsv_room *r)
{
    for (int i = 0; i < 2 * r->ns; i++) {
        vsv_volume_free(r->pins[i]);
        r->pins[i] = NULL;
    }
    r->pin_pager = NULL;
}

int vsv_room_windows(vsv_room *r, vsv_room_window *w, int cap)
{
    lock(r);
    const int n = r->h->nwin;
    for (int i = 0; i < n && i < cap; i++) {
        const win *x = &r->h->w[i];
        w[i].pid = x->pid;
        snprintf(w[i].name, sizeof w[i].name, "%s", x->name);
        w[i].frames = x->frames;
        w[i].shown = x->shown;
        w[i].last = x->last;
        w[i].rate = x->rate;
        w[i].report = x->report;
    }
    unlock(r);
    return n;
}

/* ---------------------------------------------------------------- windows */

int vsv_room_join(vsv_room *r, const char *name)
{
    lock(r);
    int i = -1;
    if (r->h->nwin < r->maxwin) {
        i = r->h->nwin++;
        win *x = &r->h->w[i];
        memset(x, 0, sizeof *x);
        x->pid = getpid();
        snprintf(x->name, sizeof x->name, "%s", name ? name : "");
        x->taken = x->shown = -1;
        x->rate_t0 = x->last = vsv_room_clock();
    }
    unlock(r);
    return i;
}

/* The views in this process, built once. */
static int local_alloc(vsv_room *r)
{
    if (r->local)
        return 0;
    const size_t ns = (size_t)(r->ns ? r->ns : 1);
    r->local = calloc(2 * ns, sizeof *r->local);
    r->seen_gen = calloc(2 * ns, sizeof *r->seen_gen);
    r->used = calloc(2 * ns, sizeof *r->used);
    r->vptr = calloc(ns * (size_t)r->maxwin, sizeof *r->vptr);
    r->user = calloc((size_t)r->maxwin, r->user_bytes ? r->user_bytes : 1);
    if (!r->local || !r->seen_gen || !r->used || !r->vptr || !r->user) {
        free(r->local), free(r->seen_gen), free(r->used), free(r->vptr), free(r->user);
        r->local = NULL, r->seen_gen = NULL, r->used = NULL, r->vptr = NULL, r->user = NULL;
        return -1;
    }
    return 0;
}

/* The volume of this process that shows species s of a slot: the one
 * already made for the publisher's load gen (a renderer keys what it
 * derives on a volume and its gen: the same load keeps the same volume),
 * else the one used least recently (of a tick no window draws any more:
 * at most two ticks are live, and every window has taken the newer before
 * a third appears). */
static vsv_volume *local_for(vsv_room *r, int s, uint64_t gen)
{
    const size_t a = 2 * (size_t)s;
    size_t k = r->seen_gen[a] == gen && r->local[a].gen           ? a
               : r->seen_gen[a + 1] == gen && r->local[a + 1].gen ? a + 1
               : r->used[a] <= r->used[a + 1]                     ? a
                                                                  : a + 1;
    if (r->seen_gen[k] != gen || !r->local[k].gen) { /* a new load: a gen unique in this process */
        r->seen_gen[k] = gen;
        r->local[k].gen = vsv_volume_new_gen();
    }
    r->used[k] = ++r->takes;
    return &r->local[k];
}

int vsv_room_frame(vsv_room *r, int w, vsv_room_view *view)
{
    if (local_alloc(r))
        return -1;
    lock(r);
    if (w < 0 || w >= r->h->nwin || r->h->w[w].pid != getpid() || !r->h->tick) {
        unlock(r);
        return -1;
    }
    win *x = &r->h->w[w];
    const double t = vsv_room_clock();
    x->shown = x->taken; /* the frame before is on the screen */
    x->taken = r->h->tick;
    x->frames++;
    x->last = t;
    if (t - x->rate_t0 >= 1) { /* frames a second over about one second */
        x->rate = (double)(x->frames - x->rate_f0) / (t - x->rate_t0);
        x->rate_t0 = t, x->rate_f0 = x->frames;
    }
    const unsigned char *sl = slot_at(r, r->h->cur);
    unlock(r);
    /* the slot stays as it is while this window draws from it: it is
     * rewritten only after every window has shown a later tick */
    const slot *h = (const slot *)sl;
    const spec *sp = (const spec *)(sl + r->off_spec);
    const size_t nb = (size_t)r->nb;
    const size_t at = (size_t)w * (size_t)r->ns;
    for (int s = 0; s < r->ns; s++) {
        if (!sp[s].present) {
            r->vptr[at + s] = NULL;
            continue;
        }
        /* (a volume shared with another window of this process showing the
         * same load: pointing it at this slot's arrays changes nothing it
         * reads, the values are the same) */
        vsv_volume *v = local_for(r, s, sp[s].gen);
        v->nx = sp[s].nx, v->ny = sp[s].ny, v->nz = sp[s].nz, v->brick = sp[s].brick;
        memcpy(v->bdim, sp[s].bdim, sizeof v->bdim);
        v->nbricks = sp[s].nbricks, v->shift = sp[s].shift, v->step = sp[s].step, v->species = sp[s].species;
        v->empty_value = sp[s].empty_value, v->time = sp[s].time;
        v->bricks = (float **)(sl + r->off_bricks) + s * nb;
        v->bmin = (float *)(sl + r->off_bmin) + s * nb;
        v->bmax = (float *)(sl + r->off_bmax) + s * nb;
        v->bkey = sp[s].has_keys ? (uint64_t *)(sl + r->off_bkey) + s * nb : NULL;
        v->release_ = NULL;
        r->vptr[at + s] = v;
    }
    unsigned char *user = r->user + (size_t)w * r->user_bytes;
    if (r->user_bytes)
        memcpy(user, sl + r->off_user, r->user_bytes);
    view->tick = h->tick;
    view->step = h->step;
    view->time = h->time;
    view->damage = h->damaged ? h->damage : NULL;
    view->vols = r->vptr + at;
    view->user = user;
    view->when = t;
    return 0;
}

void vsv_room_report(vsv_room *r, int w, double v)
{
    lock(r);
    if (w >= 0 && w < r->h->nwin && r->h->w[w].pid == getpid())
        r->h->w[w].report = v;
    unlock(r);
}

void vsv_room_fail(vsv_room *r, int code, const char *msg)
{
    lock(r);
    if (!r->h->failed) {
        r->h->failed = code > 0 ? code : 1;
        snprintf(r->h->failure, sizeof r->h->failure, "%s", msg);
    }
    unlock(r);
}

int vsv_room_failed(vsv_room *r, char *buf, size_t cap)
{
    lock(r);
    const int f = r->h->failed;
    if (f && buf)
        snprintf(buf, cap, "%s", r->h->failure);
    unlock(r);
    return f;
}
