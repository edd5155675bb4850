/* test_pager_io.c — the pager over a byte source whose transfers fail and
 * stall on the test's word (issue 33): a transfer that fails is VSV_EIO,
 * never damage, and is tried again a second later, the step then right; a
 * damaged brick or chunk index stays damaged (a get without wait says so);
 * while a worker waits on a stalled source, the calls a player makes every
 * frame (playhead, ready, get without wait, stats) return at once (the
 * pager's lock was held across the transfer: vsv-play froze); an
 * interruption ends the wait, so the pager is freed at once. Every wait
 * here is on a condition the test sets, bounded: no sleep races a check
 * (the one sleep outlasts the pager's fixed 1 s before a retry). */
#include "vsv_format.h"
#include "vsv_pager.h"
#include "vsv_synth.h"
#include "vsv_testlib.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static synth SY = {40, 30, 12, 14, 4, 9};
static vsv_decoder *REF; /* the local file's decoder */

/* The source: the file's bytes, each made resident when first asked for;
 * past the opening, its needs fail or wait as the test says. */
typedef struct src {
    vsv_byte_source pub;
    const unsigned char *real; /* what the server holds (damaged too, if so) */
    unsigned char *bytes, *asked;
    size_t size;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    int opened;     /* the modes below apply */
    int fail;       /* the next `fail` needs fail: a dropped connection */
    int block;      /* needs wait until it is 0 */
    int blocked;    /* needs waiting now */
    int release_rc; /* what a need released returns */
    int stopped;    /* interrupted */
} src;

static int s_need(vsv_byte_source *b, uint64_t off, uint64_t n, uint64_t ahead, char *msg, size_t cap)
{
    (void)ahead;
    src *s = (src *)b;
    int rc = 0;
    pthread_mutex_lock(&s->mu);
    if (s->opened && s->block && !s->stopped) {
        s->blocked++;
        pthread_cond_broadcast(&s->cv);
        while (s->block && !s->stopped)
            pthread_cond_wait(&s->cv, &s->mu);
        s->blocked--;
        if (!s->stopped && (rc = s->release_rc))
            snprintf(msg, cap, "test://x: the server stalled: headers, then no data for 30 s (bytes %llu-%llu)",
                     (unsigned long long)off, (unsigned long long)(off + n - 1));
    }
    if (!rc && s->stopped) {
        snprintf(msg, cap, "test://x: interrupted (the program is closing)");
        rc = VSV_EIO;
    }
    if (!rc && s->opened && s->fail > 0) {
        s->fail--;
        snprintf(msg, cap, "test://x: connection dropped (bytes %llu-%llu)", (unsigned long long)off,
                 (unsigned long long)(off + n - 1));
        rc = VSV_EIO;
    }
    for (uint64_t i = off; !rc && i < off + n && i < s->size; i++)
        if (!s->asked[i]) {
            s->asked[i] = 1;
            s->bytes[i] = s->real[i];
        }
    pthread_mutex_unlock(&s->mu);
    return rc;
}

static void s_interrupt(vsv_byte_source *b)
{
    src *s = (src *)b;
    pthread_mutex_lock(&s->mu);
    s->stopped = 1;
    pthread_cond_broadcast(&s->cv);
    pthread_mutex_unlock(&s->mu);
}

static void s_close(vsv_byte_source *b) { (void)b; }

static void s_init(src *s, const unsigned char *real, size_t size)
{
    memset(s, 0, sizeof *s);
    s->real = real;
    s->size = size;
    s->bytes = malloc(size);
    s->asked = calloc(size, 1);
    memset(s->bytes, 0xA5, size);
    pthread_mutex_init(&s->mu, NULL);
    pthread_cond_init(&s->cv, NULL);
    s->pub.base = s->bytes;
    s->pub.size = size;
    s->pub.need = s_need;
    s->pub.close = s_close;
    s->pub.interrupt = s_interrupt;
}

static void s_free(src *s)
{
    free(s->bytes);
    free(s->asked);
    pthread_mutex_destroy(&s->mu);
    pthread_cond_destroy(&s->cv);
}

/* s's fields under its lock */
static void s_set(src *s, int *field, int value)
{
    pthread_mutex_lock(&s->mu);
    *field = value;
    pthread_cond_broadcast(&s->cv);
    pthread_mutex_unlock(&s->mu);
}

/* Waits (10 s at most) until a need waits on s: 1, else 0. */
static int s_wait_blocked(src *s)
{
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += 10;
    pthread_mutex_lock(&s->mu);
    int rc = 0;
    while (!s->blocked && !rc)
        rc = pthread_cond_timedwait(&s->cv, &s->mu, &until);
    const int got = s->blocked > 0;
    pthread_mutex_unlock(&s->mu);
    return got;
}

/* v holds (step, s) as the local file decodes it. */
static int same(const vsv_volume *v, int step, int s)
{
    static float ref[40 * 30 * 12];
    if (v->step != step || v->species != s || vsv_decoder_volume(REF, step, s, ref))
        return 0;
    for (int k = 0; k < SY.nz; k++)
        for (int j = 0; j < SY.ny; j++)
            for (int i = 0; i < SY.nx; i++) {
                const float a = vsv_volume_at(v, i, j, k), b = ref[((size_t)k * SY.ny + j) * SY.nx + i];
                if (memcmp(&a, &b, sizeof a))
                    return 0;
            }
    return 1;
}

/* The file over a source s (opened: its modes apply from now on) and a
 * pager with `threads` workers; 0 or -1. */
static int open_all(src *s, vsv_file **f, int threads, vsv_pager **p)
{
    *p = NULL;
    if (!CHECK(vsv_file_open_source(&s->pub, "test://x", f) == 0, "the file opens over the test's source", "%s",
               *f ? vsv_file_error(*f) : ""))
        return -1;
    s_set(s, &s->opened, 1);
    vsv_pager_opts o;
    vsv_pager_opts_init(&o);
    o.budget = 64 << 20;
    o.threads = threads;
    return CHECK(vsv_pager_open(*f, &o, p) == 0, "the pager opens", " ") ? 0 : -1;
}

/* A transfer that fails, once for a chunk index and once for a payload. */
static void test_transient(const unsigned char *real, size_t size)
{
    src S;
    s_init(&S, real, size);
    vsv_file *f = NULL;
    vsv_pager *p = NULL;
    if (!open_all(&S, &f, -1, &p)) {
        vsv_volume *v = vsv_pager_volume_new(p);
        s_set(&S, &S.fail, 1);
        int rc = vsv_pager_get(p, 5, 0, 1, v);
        CHECK(rc == VSV_EIO && strstr(vsv_pager_error(p), "test://x: connection dropped"),
              "a chunk index whose transfer fails: VSV_EIO with the source's message, not damage", "rc %d: %s", rc,
              vsv_pager_error(p));
        rc = vsv_pager_get(p, 5, 0, 0, v);
        CHECK(rc == VSV_EIO, "... and a get without wait says so too", "rc %d: %s", rc, vsv_pager_error(p));
        usleep(1100 * 1000); /* past the pager's 1 s before a retry */
        rc = vsv_pager_get(p, 5, 0, 1, v);
        CHECK(rc == 0 && same(v, 5, 0), "... a second later it is fetched again and the step is right", "rc %d: %s", rc,
              vsv_pager_error(p));
        rc = vsv_pager_get(p, 6, 0, 1, v);
        s_set(&S, &S.fail, 1);
        rc = rc ? rc : vsv_pager_get(p, 6, 1, 1, v);
        CHECK(rc == VSV_EIO && strstr(vsv_pager_error(p), "connection dropped"),
              "a payload whose transfer fails: VSV_EIO with the source's message", "rc %d: %s", rc, vsv_pager_error(p));
        const unsigned char sp1[3] = {0, 1, 0};
        rc = vsv_pager_get(p, 6, 1, 0, v);
        CHECK(rc == VSV_EIO && vsv_pager_ready(p, 6, sp1) == -1,
              "... a get without wait says VSV_EIO (not damaged), ready -1", "rc %d: %s", rc, vsv_pager_error(p));
        usleep(1100 * 1000);
        rc = vsv_pager_get(p, 6, 1, 1, v);
        CHECK(rc == 0 && same(v, 6, 1), "... a second later it is fetched again and the step is right", "rc %d: %s", rc,
              vsv_pager_error(p));
        vsv_pager_stats st;
        vsv_pager_stats_get(p, &st);
        CHECK(st.transfer_failures == 2, "the stats count the 2 failed transfers", "%llu",
              (unsigned long long)st.transfer_failures);
        vsv_volume_free(v);
    }
    vsv_pager_free(p);
    vsv_file_free(f);
    s_free(&S);
}

/* What the server holds is damaged: step 7's first payload and step 9's
 * chunk index (SPEC.md §5: a chunk's offset in the table of contents,
 * payloads from align(32 + index_bytes, 64) on). */
static void test_damage(const unsigned char *real, size_t size)
{
    unsigned char *bad = malloc(size);
    memcpy(bad, real, size);
    const unsigned char *toc = bad + size - 32 - 24 * (size_t)SY.nsteps;
    uint64_t chunk = 0, chunk9 = 0;
    uint32_t index_bytes = 0;
    memcpy(&chunk, toc + 24 * 7, 8); /* little-endian hosts only, as the library */
    memcpy(&chunk9, toc + 24 * 9, 8);
    memcpy(&index_bytes, bad + chunk + 16, 4);
    const size_t at = (size_t)chunk + (32 + index_bytes + 63) / 64 * 64 + 2;
    bad[at] ^= 0x5a;
    bad[at + 1] ^= 0xa5;
    bad[chunk9 + 40] ^= 0xff;
    src S;
    s_init(&S, bad, size);
    vsv_file *f = NULL;
    vsv_pager *p = NULL;
    if (!open_all(&S, &f, -1, &p)) {
        vsv_volume *v = vsv_pager_volume_new(p);
        int rc = vsv_pager_get(p, 7, 0, 1, v);
        CHECK(rc == VSV_ECORRUPT && strstr(vsv_pager_error(p), "checksum mismatch"),
              "a damaged payload: VSV_ECORRUPT, saying why", "rc %d: %s", rc, vsv_pager_error(p));
        rc = vsv_pager_get(p, 7, 0, 0, v);
        CHECK(rc == VSV_ECORRUPT && strstr(vsv_pager_error(p), "checksum mismatch"),
              "... it stays damaged: a get without wait says so, and why", "rc %d: %s", rc, vsv_pager_error(p));
        const unsigned char sp0[3] = {1, 0, 0};
        CHECK(vsv_pager_ready(p, 7, sp0) == -1, "... ready -1", " ");
        rc = vsv_pager_get(p, 7, 1, 1, v);
        CHECK(rc == 0 && same(v, 7, 1), "... the step's other species are right", "rc %d: %s", rc, vsv_pager_error(p));
        rc = vsv_pager_get(p, 9, 0, 1, v);
        CHECK(rc == VSV_ECORRUPT && strstr(vsv_pager_error(p), "chunk 9"),
              "a damaged chunk index: VSV_ECORRUPT, naming the chunk", "rc %d: %s", rc, vsv_pager_error(p));
        rc = vsv_pager_get(p, 9, 1, 0, v);
        CHECK(rc == VSV_ECORRUPT && strstr(vsv_pager_error(p), "chunk 9"),
              "... it stays damaged: a get without wait says so", "rc %d: %s", rc, vsv_pager_error(p));
        vsv_volume_free(v);
    }
    vsv_pager_free(p);
    vsv_file_free(f);
    s_free(&S);
    free(bad);
}

/* What a player's main thread calls every frame, on its own thread here,
 * so that the test can tell a call that waits. */
typedef struct frame {
    vsv_pager *p;
    vsv_file *f;
    vsv_volume *v;
    int step, get_rc, ready, free_it;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    int done;
} frame;

static void *frame_run(void *arg)
{
    frame *fr = arg;
    if (fr->free_it) { /* a player quitting */
        vsv_file_interrupt(fr->f);
        vsv_pager_free(fr->p);
    } else {
        vsv_pager_playhead(fr->p, fr->step, 0, NULL, 0, NULL);
        fr->ready = vsv_pager_ready(fr->p, fr->step, NULL);
        fr->get_rc = vsv_pager_get(fr->p, fr->step, 0, 0, fr->v);
        vsv_pager_stats st;
        vsv_pager_stats_get(fr->p, &st);
        (void)vsv_pager_error(fr->p);
    }
    pthread_mutex_lock(&fr->mu);
    fr->done = 1;
    pthread_cond_signal(&fr->cv);
    pthread_mutex_unlock(&fr->mu);
    return NULL;
}

/* Runs a frame on its own thread: 1 when it returned within 5 s (else the
 * source is released, so that it can). */
static int frame_in_time(frame *fr, src *s)
{
    pthread_mutex_init(&fr->mu, NULL);
    pthread_cond_init(&fr->cv, NULL);
    fr->done = 0;
    pthread_t t;
    pthread_create(&t, NULL, frame_run, fr);
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += 5;
    pthread_mutex_lock(&fr->mu);
    while (!fr->done && !pthread_cond_timedwait(&fr->cv, &fr->mu, &until)) {
    }
    const int in_time = fr->done;
    pthread_mutex_unlock(&fr->mu);
    if (!in_time)
        s_set(s, &s->block, 0);
    pthread_join(t, NULL);
    pthread_mutex_destroy(&fr->mu);
    pthread_cond_destroy(&fr->cv);
    return in_time;
}

/* Polls gets without wait of (step, 0) until one is not VSV_EAGAIN (10 s at
 * most): its code. */
static int poll_get(vsv_pager *p, int step, vsv_volume *v)
{
    int rc = VSV_EAGAIN;
    for (int i = 0; i < 5000 && rc == VSV_EAGAIN; i++)
        if ((rc = vsv_pager_get(p, step, 0, 0, v)) == VSV_EAGAIN)
            usleep(2000);
    return rc;
}

/* A stalled source and a worker waiting on it. */
static void test_stall(const unsigned char *real, size_t size)
{
    src S;
    s_init(&S, real, size);
    vsv_file *f = NULL;
    vsv_pager *p = NULL;
    if (!open_all(&S, &f, 1, &p)) {
        vsv_volume *v = vsv_pager_volume_new(p);
        s_set(&S, &S.block, 1);
        vsv_pager_playhead(p, 3, 0, NULL, 0, NULL);
        CHECK(s_wait_blocked(&S), "a worker waits on the stalled source", " ");
        frame fr = {.p = p, .v = v, .step = 3};
        CHECK(frame_in_time(&fr, &S),
              "meanwhile a frame's calls (playhead, ready, get without wait, stats) return at once", " ");
        CHECK(fr.get_rc == VSV_EAGAIN && fr.ready == 0, "... the step is not there yet (VSV_EAGAIN, ready 0)",
              "rc %d, ready %d", fr.get_rc, fr.ready);
        pthread_mutex_lock(&S.mu);
        S.release_rc = VSV_EIO; /* the transfer's stall timer runs out */
        S.block = 0;
        pthread_cond_broadcast(&S.cv);
        pthread_mutex_unlock(&S.mu);
        int rc = poll_get(p, 3, v);
        CHECK(rc == VSV_EIO && strstr(vsv_pager_error(p), "the server stalled"),
              "the stalled transfer failing is VSV_EIO from the get, its message kept; not damage", "rc %d: %s", rc,
              vsv_pager_error(p));
        s_set(&S, &S.release_rc, 0);
        for (int i = 0; i < 5000 && rc == VSV_EIO; i++) /* (until the retry: 1 s) */
            if ((rc = vsv_pager_get(p, 3, 0, 0, v)) == VSV_EIO)
                usleep(2000);
        rc = rc == VSV_EAGAIN ? poll_get(p, 3, v) : rc;
        CHECK(rc == 0 && same(v, 3, 0), "a later frame tries again: the step comes, right", "rc %d: %s", rc,
              vsv_pager_error(p));
        vsv_volume_free(v);
        /* quitting while a worker waits on the stalled source */
        s_set(&S, &S.block, 1);
        vsv_pager_playhead(p, 11, 0, NULL, 0, NULL);
        CHECK(s_wait_blocked(&S), "a worker waits on the stalled source again", " ");
        frame q = {.p = p, .f = f, .free_it = 1};
        CHECK(frame_in_time(&q, &S), "vsv_file_interrupt ends the wait: the pager is freed at once", " ");
        p = NULL;
    }
    vsv_pager_free(p);
    vsv_file_free(f);
    s_free(&S);
}

int main(void)
{
    const char *path = vsv_test_tmp("pager_io.vsv");
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.brick = 8;
    o.keyframe = 5;
    char err[512] = "";
    if (!CHECK(synth_write(&SY, path, &o, err, sizeof err) == 0, "write a 14-step, 3-species series", "%s", err))
        return vsv_test_done();
    size_t size;
    unsigned char *real = vsv_test_slurp(path, &size);
    vsv_file *local = NULL;
    if (CHECK(real && !vsv_file_open(path, &local) && !vsv_decoder_create(local, &REF), "the local file opens", " ")) {
        test_transient(real, size);
        test_damage(real, size);
        test_stall(real, size);
    }
    vsv_decoder_free(REF);
    vsv_file_free(local);
    free(real);
    return vsv_test_done();
}
