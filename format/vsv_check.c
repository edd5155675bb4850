/* vsv_check.c — the full check of a .vsv file (vsv-info --check): every
 * chunk index, brick entry and payload checksum, and the bricks decoded. */
#include "vsv_reader_internal.h"

#include <stdlib.h>
#include <string.h>

int vsv_file_check(vsv_file *f, void (*progress)(void *, int, int), void *ctx)
{
    size_t z;
    const uint64_t first = vsv_align_up(f->meta_end, VSV_ALIGN);
    int rc = vsv_file_need(f, f->meta_end, first - f->meta_end, 0, f->err, sizeof f->err);
    if (rc)
        return rc;
    if (!vsv_all_zero(f->data + f->meta_end, (size_t)(first - f->meta_end), &z))
        return vsv_file_fail(f, VSV_ECORRUPT, "non-zero padding after the metadata at offset %llu",
                             (unsigned long long)(f->meta_end + z));
    vsv_decoder *d = NULL;
    rc = vsv_decoder_create(f, &d);
    if (rc)
        return vsv_file_fail(f, rc, "out of memory");
    const vsv_layout *L = &f->lay;
    const size_t n = (size_t)L->brick * L->brick * L->brick;
    uint16_t *state = calloc((size_t)f->meta.nvars * L->nbricks * n, sizeof *state);
    if (!state) {
        vsv_decoder_free(d);
        return vsv_file_fail(f, VSV_ENOMEM, "out of memory");
    }
    for (int t = 0; t < f->nsteps && !rc; t++) {
        const unsigned char *te = f->toc + (size_t)t * VSV_TOC_ENTRY_SIZE;
        const uint64_t coff = vsv_rd64(te), csize = vsv_rd64(te + 8);
        if ((rc = vsv_file_need(f, coff, csize, 0, f->err, sizeof f->err)))
            break; /* the whole chunk, padding included */
        const unsigned char *c = vsv_file_chunk_index(f, t, f->err, sizeof f->err);
        if (!c) {
            rc = VSV_ECORRUPT;
            break;
        }
        /* padding after the index, and between and after payloads */
        const size_t index_end = VSV_CHUNK_HEADER_SIZE + (size_t)f->meta.nvars * L->species_index_bytes;
        uint64_t pos = index_end;
        for (int s = 0; s < f->meta.nvars && !rc; s++) {
            const unsigned char *oct = c + VSV_CHUNK_HEADER_SIZE + (size_t)s * L->species_index_bytes;
            for (int b = 0; b < L->nbricks && !rc; b++) {
                const unsigned char *be = vsv_file_brick_entry(f, c, s, b);
                uint16_t *codes = state + ((size_t)s * L->nbricks + b) * n;
                if (vsv_brick_stored(be[0])) {
                    const uint64_t off = vsv_rd64(be + 8), size = vsv_rd32(be + 16);
                    if (off < pos || off > csize || size > csize - off) { /* the mapping changed since */
                        rc = vsv_file_fail(f, VSV_ECORRUPT,
                                           "chunk %d, species %d, brick %d: brick entry changed after it was checked",
                                           t, s, b);
                        break;
                    }
                    if (!vsv_all_zero(c + pos, (size_t)(off - pos), &z)) {
                        rc = vsv_file_fail(f, VSV_ECORRUPT, "chunk %d: non-zero padding at offset %llu", t,
                                           (unsigned long long)(coff + pos + z));
                        break;
                    }
                    pos = off + size;
                }
                if ((rc = vsv_decoder_apply(d, c, t, s, b, be, codes))) {
                    vsv_msg(f->err, sizeof f->err, "%s", d->err);
                    break;
                }
                /* octree level 0 must match the decoded codes */
                int org[3], ext[3];
                vsv_layout_box(L, b, org, ext);
                unsigned mn = 0xffff, mx = 0, stray = 0;
                for (int k = 0; k < L->brick; k++)
                    for (int j = 0; j < L->brick; j++)
                        for (int i = 0; i < L->brick; i++) {
                            unsigned v = codes[((size_t)k * L->brick + j) * L->brick + i];
                            if (i >= ext[0] || j >= ext[1] || k >= ext[2]) {
                                stray |= v;
                                continue;
                            }
                            mn = v < mn ? v : mn;
                            mx = v > mx ? v : mx;
                        }
                unsigned omn, omx;
                vsv_octree_node(oct, (size_t)b, &omn, &omx);
                if (stray || omn != mn || omx != mx || (f->quant[s].bits == 8 && mx > 255))
                    rc = vsv_file_fail(f, VSV_ECORRUPT,
                                       "chunk %d, species %d, brick %d: decoded codes disagree with the octree", t, s,
                                       b);
            }
            if (!rc) {
                /* upper octree levels must reduce level 0 */
                uint16_t *nodes = malloc(L->nnodes * 4);
                if (!nodes) {
                    rc = vsv_file_fail(f, VSV_ENOMEM, "out of memory");
                    break;
                }
                for (int b = 0; b < L->nbricks; b++) {
                    unsigned a0, a1;
                    vsv_octree_node(oct, (size_t)b, &a0, &a1);
                    nodes[2 * b] = (uint16_t)a0;
                    nodes[2 * b + 1] = (uint16_t)a1;
                }
                vsv_layout_reduce(L, nodes);
                for (size_t i = L->lstart[1]; L->levels > 1 && i < L->nnodes; i++) {
                    unsigned a0, a1;
                    vsv_octree_node(oct, i, &a0, &a1);
                    if (a0 != nodes[2 * i] || a1 != nodes[2 * i + 1]) {
                        rc =
                            vsv_file_fail(f, VSV_ECORRUPT,
                                          "chunk %d, species %d: octree node %zu disagrees with its children", t, s, i);
                        break;
                    }
                }
                free(nodes);
            }
        }
        if (!rc && !vsv_all_zero(c + pos, (size_t)(csize - pos), &z))
            rc = vsv_file_fail(f, VSV_ECORRUPT, "chunk %d: non-zero padding at offset %llu", t,
                               (unsigned long long)(coff + pos + z));
        if (progress)
            progress(ctx, t + 1, f->nsteps);
    }
    free(state);
    vsv_decoder_free(d);
    /* zeros a truncation left (vsv_mapguard.c) are not the file's damage */
    return vsv_file_cut(f, rc, f->err, sizeof f->err);
}
