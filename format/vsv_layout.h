/* vsv_layout.h — geometry of bricks and octree levels, derived from the
 * grid and the brick edge, shared by the writer and the reader. Private. */
#ifndef VSV_LAYOUT_H
#define VSV_LAYOUT_H

#include <stddef.h>
#include <stdint.h>

#define VSV_MAX_LEVELS 16

typedef struct vsv_layout {
    int nx, ny, nz, brick;
    int bdim[3]; /* bricks per axis */
    int nbricks;
    int levels;                        /* octree levels, level 0 = bricks */
    int ldim[VSV_MAX_LEVELS][3];       /* nodes per axis per level */
    size_t lstart[VSV_MAX_LEVELS + 1]; /* first node of each level */
    size_t nnodes;
    size_t octree_bytes;        /* nnodes * 4 padded to 8 */
    size_t species_index_bytes; /* octree + brick table */
} vsv_layout;

static inline int vsv_layout_init(vsv_layout *l, int nx, int ny, int nz, int brick)
{
    l->nx = nx;
    l->ny = ny;
    l->nz = nz;
    l->brick = brick;
    l->bdim[0] = (nx + brick - 1) / brick;
    l->bdim[1] = (ny + brick - 1) / brick;
    l->bdim[2] = (nz + brick - 1) / brick;
    l->nbricks = l->bdim[0] * l->bdim[1] * l->bdim[2];
    l->levels = 0;
    l->lstart[0] = 0;
    int d[3] = {l->bdim[0], l->bdim[1], l->bdim[2]};
    for (;;) {
        if (l->levels >= VSV_MAX_LEVELS)
            return -1;
        for (int a = 0; a < 3; a++)
            l->ldim[l->levels][a] = d[a];
        l->lstart[l->levels + 1] = l->lstart[l->levels] + (size_t)d[0] * (size_t)d[1] * (size_t)d[2];
        l->levels++;
        if (d[0] == 1 && d[1] == 1 && d[2] == 1)
            break;
        for (int a = 0; a < 3; a++)
            d[a] = (d[a] + 1) / 2;
    }
    l->nnodes = l->lstart[l->levels];
    l->octree_bytes = (l->nnodes * 4 + 7) / 8 * 8;
    l->species_index_bytes = l->octree_bytes + (size_t)l->nbricks * 24;
    return 0;
}

/* First cell and extent (clipped to the grid) of brick b. */
static inline void vsv_layout_box(const vsv_layout *l, int b, int org[3], int ext[3])
{
    int bi = b % l->bdim[0], bj = b / l->bdim[0] % l->bdim[1], bk = b / (l->bdim[0] * l->bdim[1]);
    const int n[3] = {l->nx, l->ny, l->nz};
    const int idx[3] = {bi, bj, bk};
    for (int a = 0; a < 3; a++) {
        org[a] = idx[a] * l->brick;
        ext[a] = n[a] - org[a] < l->brick ? n[a] - org[a] : l->brick;
    }
}

/* Fills levels 1.. of an octree whose level 0 (min,max per brick) is set:
 * each node's min/max over its up-to-8 children. nodes: 2 u16 per node. */
static inline void vsv_layout_reduce(const vsv_layout *l, uint16_t *nodes)
{
    for (int L = 1; L < l->levels; L++) {
        const int *cd = l->ldim[L - 1], *pd = l->ldim[L];
        for (int k = 0; k < pd[2]; k++)
            for (int j = 0; j < pd[1]; j++)
                for (int i = 0; i < pd[0]; i++) {
                    unsigned mn = 0xffff, mx = 0;
                    for (int dk = 0; dk < 2; dk++)
                        for (int dj = 0; dj < 2; dj++)
                            for (int di = 0; di < 2; di++) {
                                int ci = 2 * i + di, cj = 2 * j + dj, ck = 2 * k + dk;
                                if (ci >= cd[0] || cj >= cd[1] || ck >= cd[2])
                                    continue;
                                size_t c = l->lstart[L - 1] + ((size_t)ck * cd[1] + cj) * cd[0] + ci;
                                if (nodes[2 * c] < mn)
                                    mn = nodes[2 * c];
                                if (nodes[2 * c + 1] > mx)
                                    mx = nodes[2 * c + 1];
                            }
                    size_t p = l->lstart[L] + ((size_t)k * pd[1] + j) * pd[0] + i;
                    nodes[2 * p] = (uint16_t)mn;
                    nodes[2 * p + 1] = (uint16_t)mx;
                }
    }
}

#endif
