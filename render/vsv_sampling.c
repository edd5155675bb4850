/* vsv_sampling.c — the raycaster's sampling copies (vsv_rc.h): every brick
 * with one more cell along each axis, built brick by brick on the pool. */
#include "vsv_renderer.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Whether brick b's sampling copy holds data: one of the eight bricks
 * whose cells it copies has some. */
int vsv_rc_copy_has_data(const vsv_volume *v, int b)
{
    const int bx = v->bdim[0], by = v->bdim[1], bz = v->bdim[2];
    const int bi = b % bx, bj = b / bx % by, bk = b / (bx * by);
    for (int n = 0; n < 8; n++) {
        const int i = bi + (n & 1), j = bj + (n >> 1 & 1), k = bk + (n >> 2);
        if (i < bx && j < by && k < bz && v->bricks[i + bx * (j + by * k)])
            return 1;
    }
    return 0;
}

/* Sets c up to hold v's sampling copy (vsv_rc_cells): room for the bricks
 * whose copy holds data and for the shared empty brick, which is filled
 * here; copy_brick fills the others. */
int vsv_rc_copy_prepare(vsv_rc_copy *c, const vsv_volume *v)
{
    const size_t n3 = (size_t)(v->brick + 1) * (v->brick + 1) * (v->brick + 1);
    if (v->nbricks > c->cells_cap) {
        const float **p = realloc(c->cells, (size_t)v->nbricks * sizeof *p);
        if (!p)
            return -1;
        c->cells = p;
        c->cells_cap = v->nbricks;
    }
    size_t own = 0;
    for (int b = 0; b < v->nbricks; b++)
        own += (size_t)vsv_rc_copy_has_data(v, b);
    if ((own + 1) * n3 > c->store_cap) {
        float *p = realloc(c->store, (own + 1) * n3 * sizeof *p);
        if (!p)
            return -1;
        c->store = p;
        c->store_cap = (own + 1) * n3;
    }
    int nb[3];
    vsv_rc_block_dims(v, nb);
    const size_t nblk = (size_t)nb[0] * nb[1] * nb[2];
    if (2 * nblk > c->mm_cap) {
        float *p = realloc(c->mm, 2 * nblk * sizeof *p);
        if (!p)
            return -1;
        c->mm = p;
        c->mm_cap = 2 * nblk;
    }
    c->empty = c->store + own * n3;
    for (size_t i = 0; i < n3; i++)
        c->empty[i] = v->empty_value;
    own = 0;
    for (int b = 0; b < v->nbricks; b++)
        c->cells[b] = vsv_rc_copy_has_data(v, b) ? c->store + own++ * n3 : c->empty;
    c->vol = v;
    c->gen = v->gen;
    return 0;
}

void vsv_rc_copy_fill(const vsv_volume *v, int b, float *dst)
{
    const int B = v->brick, e = B + 1, s = v->shift, m = B - 1, bx = v->bdim[0], by = v->bdim[1];
    const int i0 = b % bx * B, j0 = b / bx % by * B, k0 = b / (bx * by) * B;
    for (int k = 0; k < e; k++) {
        const int gk = k0 + k < v->nz ? k0 + k : v->nz - 1;
        for (int j = 0; j < e; j++) {
            const int gj = j0 + j < v->ny ? j0 + j : v->ny - 1;
            float *row = dst + ((size_t)k * e + j) * e;
            if (i0 + B < v->nx) { /* the brick's row and the next cell inside the grid */
                const float *src = v->bricks[b % bx + bx * ((gj >> s) + by * (gk >> s))];
                if (src)
                    memcpy(row, src + ((gj & m) << s) + ((gk & m) << (2 * s)), (size_t)B * sizeof *row);
                else
                    for (int i = 0; i < B; i++)
                        row[i] = v->empty_value;
                row[B] = vsv_volume_at(v, i0 + B, gj, gk);
            } else {
                for (int i = 0; i < e; i++)
                    row[i] = vsv_volume_at(v, i0 + i < v->nx ? i0 + i : v->nx - 1, gj, gk);
            }
        }
    }
}

void vsv_rc_copy_minmax(const vsv_rc_copy *c, int b)
{
    const vsv_volume *v = c->vol;
    const int B = v->brick, e = B + 1, bx = v->bdim[0], by = v->bdim[1];
    const int org[3] = {b % bx * B, b / bx % by * B, b / (bx * by) * B};
    int nb[3];
    vsv_rc_block_dims(v, nb);
    const float *cells = c->cells[b];
    for (int lk = 0; lk < B / VSV_RC_BLOCK; lk++)
        for (int lj = 0; lj < B / VSV_RC_BLOCK; lj++)
            for (int li = 0; li < B / VSV_RC_BLOCK; li++) {
                const int g[3] = {(org[0] >> VSV_RC_BSHIFT) + li, (org[1] >> VSV_RC_BSHIFT) + lj,
                                  (org[2] >> VSV_RC_BSHIFT) + lk};
                if (g[0] >= nb[0] || g[1] >= nb[1] || g[2] >= nb[2])
                    continue;
                float lo = INFINITY, hi = -INFINITY; /* NaN fails both tests: left out */
                if (cells == c->empty) {
                    lo = v->empty_value < lo ? v->empty_value : lo;
                    hi = v->empty_value > hi ? v->empty_value : hi;
                } else {
                    for (int k = 0; k <= VSV_RC_BLOCK; k++)
                        for (int j = 0; j <= VSV_RC_BLOCK; j++) {
                            const float *row = cells +
                                               ((size_t)(lk * VSV_RC_BLOCK + k) * e + lj * VSV_RC_BLOCK + j) * e +
                                               li * VSV_RC_BLOCK;
                            for (int i = 0; i <= VSV_RC_BLOCK; i++) {
                                lo = row[i] < lo ? row[i] : lo;
                                hi = row[i] > hi ? row[i] : hi;
                            }
                        }
                }
                float *mm = c->mm + 2 * (g[0] + (size_t)nb[0] * (g[1] + (size_t)nb[1] * g[2]));
                mm[0] = lo;
                mm[1] = hi;
            }
}

/* Brick item % nbricks of the copy item / nbricks being rebuilt. */
void vsv_rc_copy_brick(void *ctx, int item, int thread)
{
    const vsv_renderer *r = ctx;
    (void)thread;
    const vsv_rc_copy *c = r->build[item / r->build[0]->vol->nbricks];
    const int b = item % c->vol->nbricks;
    if (c->cells[b] != c->empty)
        vsv_rc_copy_fill(c->vol, b, (float *)c->cells[b]);
    vsv_rc_copy_minmax(c, b);
}
