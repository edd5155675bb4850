/* vsv_gl_bricks.c — the GPU raycaster's bricks (vsv_gl_internal.h): the
 * atlas (a 3-D R32F texture of slots, grown up to the budget), the keys
 * that say which values a slot holds, the page tables of a frame, and the
 * uploads of the bricks a frame needs and the atlas lacks, batched through
 * one pixel buffer object. */
#include "vsv_gl_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void vsv_gl_bricks_free(vsv_gl_bricks *b)
{
    if (b->atlas)
        glDeleteTextures(1, &b->atlas);
    if (b->pages)
        glDeleteTextures(1, &b->pages);
    if (b->pbo)
        glDeleteBuffers(1, &b->pbo);
    free(b->slot);
    free(b->hash);
    free(b->page);
    free(b->copy);
    free(b->cnt);
    memset(b, 0, sizeof *b);
}

static uint64_t mix(uint64_t h, uint64_t v)
{
    h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    return h * 0x100000001B3ull;
}

/* What brick bi's sampling copy holds, as a key (never 0): the keys of the
 * bricks whose cells it copies (itself and those after it along each
 * axis; equal keys, equal values: vsv_volume.bkey), else the volume's load
 * (a volume without keys: every load new; without a load either: every
 * frame), its place in the grid and the empty value (the copy's cells past
 * the grid and in EMPTY bricks). */
static uint64_t brick_key(const vsv_gl_bricks *b, const vsv_volume *v, int bi)
{
    const int bx = v->bdim[0], by = v->bdim[1], bz = v->bdim[2];
    const int i = bi % bx, j = bi / bx % by, k = bi / (bx * by);
    uint64_t h = mix(0x6A09E667F3BCC908ull, (uint64_t)bi);
    h = mix(h, (uint64_t)v->brick);
    uint32_t e;
    memcpy(&e, &v->empty_value, 4);
    h = mix(h, e);
    if (!v->gen) { /* a volume nobody says the load of: new every frame */
        h = mix(h, b->frame);
        h = mix(h, (uint64_t)(uintptr_t)v);
    } else if (!v->bkey) {
        h = mix(h, v->gen);
        h = mix(h, (uint64_t)(uintptr_t)v);
    } else {
        for (int n = 0; n < 8; n++) {
            const int ii = i + (n & 1), jj = j + (n >> 1 & 1), kk = k + (n >> 2);
            h = mix(h, ii < bx && jj < by && kk < bz ? v->bkey[ii + bx * (jj + by * kk)] : 0x5555ull);
        }
    }
    return h ? h : 1;
}

static int find(const vsv_gl_bricks *b, uint64_t key)
{
    for (uint32_t at = (uint32_t)(key >> 17) & (uint32_t)(b->nhash - 1);; at = (at + 1) & (uint32_t)(b->nhash - 1)) {
        const uint32_t s = b->hash[at];
        if (!s)
            return -1;
        if (b->slot[s - 1].key == key)
            return (int)s - 1;
    }
}

static void insert(vsv_gl_bricks *b, uint64_t key, int slot)
{
    uint32_t at = (uint32_t)(key >> 17) & (uint32_t)(b->nhash - 1);
    while (b->hash[at] && b->slot[b->hash[at] - 1].key != key)
        at = (at + 1) & (uint32_t)(b->nhash - 1);
    b->hash[at] = (uint32_t)slot + 1;
}

/* The hash from the slots as they are (stale entries of evicted slots go). */
static void rehash(vsv_gl_bricks *b)
{
    memset(b->hash, 0, (size_t)b->nhash * sizeof *b->hash);
    for (int s = 0; s < b->nslots; s++)
        if (b->slot[s].key)
            insert(b, b->slot[s].key, s);
}

/* An atlas of at least `need` slots (all empty), within the budget. */
static int make_atlas(vsv_gl_bricks *b, int need, int brick, char *err, size_t cap)
{
    const size_t slot_bytes = (size_t)(brick + 1) * (brick + 1) * (brick + 1) * sizeof(float);
    const size_t most = b->budget / slot_bytes;
    if ((size_t)need > most) {
        snprintf(err, cap, "the frame's %d bricks need %.1f MB of GPU memory; the budget is %.1f MB", need,
                 (double)need * slot_bytes / 1048576, (double)b->budget / 1048576);
        return VSV_ENOMEM;
    }
    GLint max3d = 256;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3d);
    const int e = brick + 1, per = max3d / e > 0 ? max3d / e : 1;
    size_t want = (size_t)need + need / 4 + 16;
    want = want > most ? most : want;
    const int sx = (int)(want < (size_t)per ? want : (size_t)per);
    const int sy = (int)((want + sx - 1) / sx < (size_t)per ? (want + sx - 1) / sx : (size_t)per);
    const int sz = (int)((want + (size_t)sx * sy - 1) / ((size_t)sx * sy));
    if (sz > per || (size_t)sx * sy * sz < (size_t)need) {
        snprintf(err, cap, "%d bricks of %d^3 do not fit a %d^3 texture", need, e, (int)max3d);
        return VSV_ENOMEM;
    }
    if (b->atlas)
        glDeleteTextures(1, &b->atlas);
    free(b->slot);
    free(b->hash);
    b->atlas = 0, b->slot = NULL, b->hash = NULL, b->nslots = 0, b->hand = 0;
    int nhash = 1;
    while (nhash < 4 * sx * sy * sz)
        nhash *= 2;
    b->slot = calloc((size_t)sx * sy * sz, sizeof *b->slot);
    b->hash = calloc((size_t)nhash, sizeof *b->hash);
    if (!b->slot || !b->hash) {
        free(b->slot), free(b->hash);
        b->slot = NULL, b->hash = NULL;
        snprintf(err, cap, "out of memory");
        return VSV_ENOMEM;
    }
    b->nslots = sx * sy * sz, b->nhash = nhash;
    b->sx = sx, b->sy = sy, b->sz = sz, b->e = e, b->brick = brick;
    while (glGetError() != GL_NO_ERROR) /* (earlier errors are not this one's) */
        ;
    glGenTextures(1, &b->atlas);
    glBindTexture(GL_TEXTURE_3D, b->atlas);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexImage3D(GL_TEXTURE_3D, 0, GL_R32F, sx * e, sy * e, sz * e, 0, GL_RED, GL_FLOAT, NULL);
    if (glGetError() != GL_NO_ERROR) {
        snprintf(err, cap, "the GPU has no room for a brick atlas of %d x %d x %d", sx * e, sy * e, sz * e);
        glDeleteTextures(1, &b->atlas);
        b->atlas = 0, b->nslots = 0;
        return VSV_ENOMEM;
    }
    return 0;
}

/* A slot for a brick this frame lacks: a free one, else the one used least
 * recently (never one this frame uses); -1 when none is left. The hand
 * goes on from where it stopped, so a frame takes the oldest first. */
static int victim(vsv_gl_bricks *b)
{
    int best = -1;
    for (int tries = 0; tries < b->nslots; tries++) {
        const int s = b->hand;
        b->hand = (b->hand + 1) % b->nslots;
        if (!b->slot[s].key)
            return s;
        if (b->slot[s].used != b->frame && (best < 0 || b->slot[s].used < b->slot[best].used))
            best = s;
    }
    return best;
}

/* Forgets the slots this frame was to fill and did not (a failed frame
 * must not leave a key over the values of another brick). */
static void forget_unfilled(vsv_gl_bricks *b, int nl, int nb)
{
    for (size_t i = 0; i < (size_t)nl * nb; i++) {
        const int *pg = b->page + 2 * i;
        if (pg[0] >= 0 && pg[1] == -2)
            b->slot[pg[0]].key = 0;
    }
}

/* Uploads the bricks marked -2 in the page entries, in batches through the
 * staging buffer (VSV_GL_STAGING bytes), computing each slot's value range
 * on the way. 0, or VSV_ENOMEM with err (the unfilled ones forgotten). */
static int upload(vsv_gl_bricks *b, const vsv_march *m, int nb, char *err, size_t cap)
{
    const int e = b->e;
    const size_t n3 = (size_t)e * e * e, per = VSV_GL_STAGING / (n3 * sizeof(float));
    if (!b->pbo) {
        glGenBuffers(1, &b->pbo);
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, b->pbo);
        glBufferData(GL_PIXEL_UNPACK_BUFFER, VSV_GL_STAGING, NULL, GL_STREAM_DRAW);
    }
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, b->pbo);
    glBindTexture(GL_TEXTURE_3D, b->atlas);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    size_t at = 0; /* the next page entry to look at */
    const size_t total = (size_t)m->nlayers * nb;
    int rc = 0;
    while (at < total && !rc) {
        /* a batch: map the staging buffer anew (orphaned: no wait for the GPU) */
        float *dst = glMapBufferRange(GL_PIXEL_UNPACK_BUFFER, 0, VSV_GL_STAGING,
                                      GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT);
        if (!dst) {
            snprintf(err, cap, "cannot map the %zu MB staging buffer", VSV_GL_STAGING >> 20);
            rc = VSV_ENOMEM;
            break;
        }
        size_t k = 0, first = at;
        for (; at < total && k < per; at++) {
            int *pg = b->page + 2 * at;
            if (pg[0] < 0 || pg[1] != -2)
                continue;
            vsv_march_brick(m->layer[at / (size_t)nb].vol, (int)(at % (size_t)nb), b->copy);
            float lo = INFINITY, hi = -INFINITY;
            for (size_t c = 0; c < n3; c++) { /* NaN left out */
                lo = b->copy[c] < lo ? b->copy[c] : lo;
                hi = b->copy[c] > hi ? b->copy[c] : hi;
            }
            b->slot[pg[0]].lo = lo, b->slot[pg[0]].hi = hi;
            memcpy(dst + k * n3, b->copy, n3 * sizeof *dst);
            pg[1] = -3 - (int)k++; /* in the batch, at k */
        }
        if (!glUnmapBuffer(GL_PIXEL_UNPACK_BUFFER)) { /* the buffer's contents were lost */
            snprintf(err, cap, "the staging buffer's contents were lost");
            rc = VSV_ENOMEM;
        }
        for (size_t i = first; i < at; i++) {
            int *pg = b->page + 2 * i;
            if (pg[0] < 0 || pg[1] > -3)
                continue;
            const int s = pg[0];
            if (!rc)
                glTexSubImage3D(GL_TEXTURE_3D, 0, s % b->sx * e, s / b->sx % b->sy * e, s / (b->sx * b->sy) * e, e, e,
                                e, GL_RED, GL_FLOAT, (const void *)((size_t)(-3 - pg[1]) * n3 * sizeof(float)));
            pg[1] = rc ? -2 : -1; /* (uploaded: resident) */
            b->uploads += !rc;
            b->last_uploads += !rc;
        }
    }
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    if (!rc && glGetError() == GL_OUT_OF_MEMORY) {
        snprintf(err, cap, "the GPU ran out of memory uploading bricks");
        rc = VSV_ENOMEM;
    }
    return rc;
}

int vsv_gl_bricks_frame(vsv_gl_bricks *b, const vsv_march *m, char *err, size_t cap)
{
    b->frame++;
    b->last_uploads = b->last_bricks = 0;
    if (!m->nlayers)
        return 0;
    const vsv_volume *v0 = m->layer[0].vol;
    const int nb = v0->nbricks, e = v0->brick + 1;
    const size_t n3 = (size_t)e * e * e;
    if (n3 * sizeof(float) > VSV_GL_STAGING) {
        snprintf(err, cap, "bricks of %d^3 are larger than the staging buffer", v0->brick);
        return VSV_EUNSUPPORTED;
    }
    int need = 0;
    for (int l = 0; l < m->nlayers; l++)
        for (int i = 0; i < nb; i++)
            need += !vsv_march_brick_empty(m->layer[l].vol, i);
    int rc;
    if ((!b->atlas || b->brick != v0->brick || need > b->nslots) && (rc = make_atlas(b, need, v0->brick, err, cap)))
        return rc;
    rehash(b);
    const size_t pages = (size_t)nb * m->nlayers * 2;
    if (pages > b->page_cap) {
        int *p = realloc(b->page, pages * sizeof *p);
        if (!p)
            goto oom;
        b->page = p;
        b->page_cap = pages;
    }
    if (n3 > b->copy_cap) {
        float *c = realloc(b->copy, n3 * sizeof *c);
        if (!c)
            goto oom;
        b->copy = c;
        b->copy_cap = n3;
    }
    if (!b->cnt && !(b->cnt = malloc((VSV_TF_LUT + 1) * sizeof *b->cnt)))
        goto oom;
    /* what is resident first (marked used, so no miss evicts it), then a
     * slot for each miss: free ones, then the least recently used */
    for (int l = 0; l < m->nlayers; l++) {
        const vsv_volume *v = m->layer[l].vol;
        for (int i = 0; i < nb; i++) {
            int *pg = b->page + 2 * ((size_t)l * nb + i);
            if (vsv_march_brick_empty(v, i)) {
                pg[0] = -1, pg[1] = 0;
                continue;
            }
            const uint64_t key = brick_key(b, v, i);
            const int s = find(b, key);
            pg[0] = s;
            pg[1] = s < 0 ? -2 : -1; /* -2: to upload; -1: resident */
            if (s >= 0)
                b->slot[s].used = b->frame;
            b->last_bricks++;
        }
    }
    for (int l = 0; l < m->nlayers; l++)
        for (int i = 0; i < nb; i++) {
            int *pg = b->page + 2 * ((size_t)l * nb + i);
            if (pg[1] != -2 || pg[0] >= 0 || vsv_march_brick_empty(m->layer[l].vol, i))
                continue;
            const int s = victim(b);
            if (s < 0) { /* (the atlas holds the frame's need: not reached) */
                snprintf(err, cap, "no free slot among %d", b->nslots);
                forget_unfilled(b, m->nlayers, nb);
                return VSV_ENOMEM;
            }
            const uint64_t key = brick_key(b, m->layer[l].vol, i);
            b->slot[s].key = key;
            b->slot[s].used = b->frame;
            insert(b, key, s);
            pg[0] = s;
        }
    if ((rc = upload(b, m, nb, err, cap))) {
        forget_unfilled(b, m->nlayers, nb);
        return rc;
    }
    /* the page tables: slot, and whether the brick is clear in the layer */
    for (int l = 0; l < m->nlayers; l++) {
        const vsv_march_layer *L = &m->layer[l];
        vsv_march_counts(L, b->cnt);
        const float ev = L->vol->empty_value;
        const int empty_clear = vsv_march_clear(L, b->cnt, ev, ev);
        for (int i = 0; i < nb; i++) {
            int *pg = b->page + 2 * ((size_t)l * nb + i);
            if (pg[0] < 0) {
                pg[1] = empty_clear;
                continue;
            }
            const vsv_gl_slot *s = &b->slot[pg[0]];
            pg[1] = s->lo > s->hi ? 1 /* (no data at all) */ : vsv_march_clear(L, b->cnt, s->lo, s->hi);
        }
    }
    if (!b->pages)
        glGenTextures(1, &b->pages);
    glBindTexture(GL_TEXTURE_3D, b->pages);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    const int pw = v0->bdim[0], ph = v0->bdim[1], pd = v0->bdim[2] * m->nlayers;
    if (pw != b->pw || ph != b->ph || pd != b->pd) {
        glTexImage3D(GL_TEXTURE_3D, 0, GL_RG32I, pw, ph, pd, 0, GL_RG_INTEGER, GL_INT, b->page);
        b->pw = pw, b->ph = ph, b->pd = pd;
    } else {
        glTexSubImage3D(GL_TEXTURE_3D, 0, 0, 0, 0, pw, ph, pd, GL_RG_INTEGER, GL_INT, b->page);
    }
    return 0;
oom:
    snprintf(err, cap, "out of memory");
    return VSV_ENOMEM;
}
