/* vsv_volume.c — decoded volumes of a file: one species at one step, brick
 * by brick (vsv_volume in vsv_format.h). */
#include "vsv_reader_internal.h"

#include <stdlib.h>
#include <string.h>

typedef struct volume_impl {
    vsv_volume pub;
    uint16_t *codes; /* nbricks * B^3: the decoded codes, kept for deltas */
    float *store;    /* nbricks * B^3 floats */
} volume_impl;

uint64_t vsv_volume_new_gen(void)
{
    static uint64_t gens;
    return __atomic_add_fetch(&gens, 1, __ATOMIC_RELAXED);
}

/* Bit 63 set (a volume's gen, a small count, never has it), then 29 bits
 * of the file's uid, 10 of the species (< 1024), 24 of the step (< 10^7;
 * all ones for EMPTY). */
uint64_t vsv_file_brick_key(const vsv_file *f, int s, int def)
{
    return 1ull << 63 | (f->uid & 0x1FFFFFFFu) << 34 | (uint64_t)(s & 0x3FF) << 24 |
           (uint64_t)(def < 0 ? 0xFFFFFF : def);
}

/* The release of vsv_volume_create's volumes (what marks them as such). */
static void volume_release(vsv_volume *pv)
{
    volume_impl *v = (volume_impl *)pv;
    free(v->pub.bricks);
    free(v->pub.bmin);
    free(v->pub.bmax);
    free(v->pub.bkey);
    free(v->codes);
    free(v->store);
    free(v);
}

int vsv_volume_create(const vsv_file *f, vsv_volume **out)
{
    *out = NULL;
    volume_impl *v = calloc(1, sizeof *v);
    if (!v)
        return VSV_ENOMEM;
    const vsv_layout *L = &f->lay;
    const size_t n = (size_t)L->brick * L->brick * L->brick;
    v->pub.nx = f->meta.nx;
    v->pub.ny = f->meta.ny;
    v->pub.nz = f->meta.nz;
    v->pub.brick = L->brick;
    while ((1 << v->pub.shift) < L->brick)
        v->pub.shift++;
    for (int a = 0; a < 3; a++)
        v->pub.bdim[a] = L->bdim[a];
    v->pub.nbricks = L->nbricks;
    v->pub.step = v->pub.species = -1;
    v->pub.release_ = volume_release;
    v->pub.bricks = calloc((size_t)L->nbricks, sizeof *v->pub.bricks);
    v->pub.bmin = calloc((size_t)L->nbricks, sizeof(float));
    v->pub.bmax = calloc((size_t)L->nbricks, sizeof(float));
    v->pub.bkey = calloc((size_t)L->nbricks, sizeof *v->pub.bkey);
    v->codes = calloc((size_t)L->nbricks * n, sizeof *v->codes);
    v->store = malloc((size_t)L->nbricks * n * sizeof *v->store);
    if (!v->pub.bricks || !v->pub.bmin || !v->pub.bmax || !v->pub.bkey || !v->codes || !v->store) {
        vsv_volume_free(&v->pub);
        return VSV_ENOMEM;
    }
    *out = &v->pub;
    return 0;
}

void vsv_volume_free(vsv_volume *v)
{
    if (v && v->release_)
        v->release_(v);
}

int vsv_volume_load(vsv_volume *pv, vsv_decoder *d, int step, int s)
{
    volume_impl *v = (volume_impl *)pv;
    vsv_file *f = d->f;
    if (!pv || pv->release_ != volume_release) {
        vsv_msg(d->err, sizeof d->err, "%s: not a volume of vsv_volume_create", f->name);
        return VSV_EINVAL;
    }
    int rc = vsv_file_check_args(f, step, s, 0, d->err, sizeof d->err);
    if (rc)
        return rc;
    const vsv_layout *L = &f->lay;
    if (pv->nx != f->meta.nx || pv->ny != f->meta.ny || pv->nz != f->meta.nz || pv->brick != L->brick) {
        vsv_msg(d->err, sizeof d->err, "%s: the volume was made for another grid (%dx%dx%d, brick %d)", f->name, pv->nx,
                pv->ny, pv->nz, pv->brick);
        return VSV_EINVAL;
    }
    const size_t n = (size_t)L->brick * L->brick * L->brick;
    const int seq = pv->species == s && pv->step >= 0 && pv->step < step && step - pv->step <= f->keyframe;
    const int prev = pv->step;
    pv->step = pv->species = -1;
    pv->gen = 0;
    const unsigned char *oct = vsv_file_octree(f, step, s, NULL);
    if (!oct) {
        vsv_msg(d->err, sizeof d->err, "%s", f->err);
        return VSV_ECORRUPT;
    }
    const vsv_quant *q = &f->quant[s];
    pv->empty_value = vsv_quant_value(q, 0);
    for (int b = 0; b < L->nbricks; b++) {
        uint16_t *codes = v->codes + (size_t)b * n;
        if (seq) {
            for (int t = prev + 1; t <= step && !rc; t++)
                rc = vsv_decoder_brick_advance(d, t, s, b, codes);
        } else {
            rc = vsv_decoder_brick_codes(d, step, s, b, codes);
        }
        if (rc)
            return rc;
        unsigned mn, mx;
        vsv_octree_node(oct, (size_t)b, &mn, &mx);
        pv->bmin[b] = vsv_quant_value(q, mn);
        pv->bmax[b] = vsv_quant_value(q, mx);
        /* the step that last set the codes (keyframes hold no UNCHANGED) */
        int t = step, kind;
        while ((kind = vsv_file_brick_kind(f, t, s, b)) == VSV_BRICK_UNCHANGED && t > 0)
            t--;
        if (kind < 0) {
            vsv_msg(d->err, sizeof d->err, "%s", f->err);
            return VSV_ECORRUPT;
        }
        pv->bkey[b] = vsv_file_brick_key(f, s, mx == 0 || kind == VSV_BRICK_EMPTY ? -1 : t);
        if (mx == 0) {
            pv->bricks[b] = NULL;
            continue;
        }
        float *dst = v->store + (size_t)b * n;
        vsv_file_dequantise_brick(f, s, b, codes, dst); /* outside the grid: the empty value */
        pv->bricks[b] = dst;
    }
    pv->step = step;
    pv->species = s;
    pv->time = vsv_file_time(f, step);
    pv->gen = vsv_volume_new_gen();
    return 0;
}
