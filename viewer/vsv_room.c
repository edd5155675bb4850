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
    int64_t taken;  /* the tick its current frame draws (-1 none) */
    int64_t shown;  /* the tick of its frame before (-1 none) */
    double last, rate, rate_t0;
    uint64_t rate_f0;
    double report;
} win;

typedef struct head {
    pthread_mutex_t mu;
    int64_t tick;   /* the newest published; 0 none */
    int cur;        /* its slot */
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
    /* a window's view in this process */
    vsv_volume *local;    /* ns volumes */
    const vsv_volume **vptr;
    uint64_t *seen_gen;   /* per species: the publisher's gen behind local[s].gen */
    void *user;           /* user_bytes */
};

static double now_s(void)
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
        snprintf(err, cap, "a room of %d windows, %d species, %d bricks: out of range (at most %d windows)",
                 o->windows, o->nspecies, o->nbricks, MAX_WINDOWS);
        return -1;
    }
    vsv_room *r = calloc(1, sizeof *r);
    if (!r) {
        snprintf(err, cap, "out of memory");
        return -1;
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
        return -1;
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
        return -1;
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

/* ------------------------------------------------------------- publisher */

/* Under the lock: whether every window has shown the newest tick. */
static int all_shown(const vsv_room *r)
{
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

int64_t vsv_room_publish(vsv_room *r, vsv_pager *pg, int step, int64_t time, const char *damage,
                         const vsv_volume *const *vols, const void *user, char *err, size_t cap)
{
    lock(r);
    const int64_t tick = r->h->tick + 1;
    const int k = r->h->tick ? 1 - r->h->cur : 0;
    const int ready = all_shown(r);
    unlock(r);
    if (!ready) /* (windows only ever move on: this stays true once seen) */
        return 0;
    /* the slot k is read by no window (every one has shown the current
     * tick, in the other slot): pin the new step's bricks there, which
     * releases those of the tick before */
    unsigned char *sl = slot_at(r, k);
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
            return -1;
        }
        const int rc = vsv_pager_get(pg, v->step, s, 1, *pin);
        if (rc) {
            snprintf(err, cap, "%s", vsv_pager_error(pg));
            return -1;
        }
        const vsv_volume *p = *pin;
        if (p->nbricks != r->nb) {
            snprintf(err, cap, "a volume of %d bricks in a room of %d", p->nbricks, r->nb);
            return -1;
        }
        sp[s] = (spec){1,           p->nx,      p->ny, p->nz, p->brick, {p->bdim[0], p->bdim[1], p->bdim[2]},
                       p->nbricks, p->shift,    p->step, p->species, p->gen, p->empty_value, p->time, p->bkey != NULL};
        memcpy(bricks + s * nb, p->bricks, nb * sizeof *bricks);
        memcpy(bmin + s * nb, p->bmin, nb * sizeof *bmin);
        memcpy(bmax + s * nb, p->bmax, nb * sizeof *bmax);
        if (p->bkey)
            memcpy(bkey + s * nb, p->bkey, nb * sizeof *bkey);
    }
    slot *h = (slot *)sl;
    h->tick = tick;
    h->step = step;
    h->time = time;
    h->damaged = damage != NULL;
    snprintf(h->damage, sizeof h->damage, "%s", damage ? damage : "");
    if (r->user_bytes)
        memcpy(sl + r->off_user, user, r->user_bytes);
    lock(r); /* the mutex orders the slot's writes before the windows' reads */
    r->h->tick = tick;
    r->h->cur = k;
    unlock(r);
    return tick;
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
        x->rate_t0 = x->last = now_s();
    }
    unlock(r);
    return i;
}

/* This process's view: its volumes, built once. */
static int local_alloc(vsv_room *r)
{
    if (r->local)
        return 0;
    const size_t ns = (size_t)(r->ns ? r->ns : 1);
    r->local = calloc(ns, sizeof *r->local);
    r->vptr = calloc(ns, sizeof *r->vptr);
    r->seen_gen = calloc(ns, sizeof *r->seen_gen);
    r->user = calloc(1, r->user_bytes ? r->user_bytes : 1);
    if (!r->local || !r->vptr || !r->seen_gen || !r->user) {
        free(r->local), free(r->vptr), free(r->seen_gen), free(r->user);
        r->local = NULL, r->vptr = NULL, r->seen_gen = NULL, r->user = NULL;
        return -1;
    }
    return 0;
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
    const double t = now_s();
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
    for (int s = 0; s < r->ns; s++) {
        vsv_volume *v = &r->local[s];
        if (!sp[s].present) {
            r->vptr[s] = NULL;
            continue;
        }
        if (sp[s].gen != r->seen_gen[s] || !v->gen) { /* a new load: a gen unique in this process */
            r->seen_gen[s] = sp[s].gen;
            v->gen = vsv_volume_new_gen();
        }
        v->nx = sp[s].nx, v->ny = sp[s].ny, v->nz = sp[s].nz, v->brick = sp[s].brick;
        memcpy(v->bdim, sp[s].bdim, sizeof v->bdim);
        v->nbricks = sp[s].nbricks, v->shift = sp[s].shift, v->step = sp[s].step, v->species = sp[s].species;
        v->empty_value = sp[s].empty_value, v->time = sp[s].time;
        v->bricks = (float **)(sl + r->off_bricks) + s * nb;
        v->bmin = (float *)(sl + r->off_bmin) + s * nb;
        v->bmax = (float *)(sl + r->off_bmax) + s * nb;
        v->bkey = sp[s].has_keys ? (uint64_t *)(sl + r->off_bkey) + s * nb : NULL;
        v->release_ = NULL;
        r->vptr[s] = v;
    }
    if (r->user_bytes)
        memcpy(r->user, sl + r->off_user, r->user_bytes);
    view->tick = h->tick;
    view->step = h->step;
    view->time = h->time;
    view->damage = h->damaged ? h->damage : NULL;
    view->vols = r->vptr;
    view->user = r->user;
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

void vsv_room_fail(vsv_room *r, const char *msg)
{
    lock(r);
    if (!r->h->failed) {
        r->h->failed = 1;
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
