/* vsv_moves.c — a grid that moves in time (SPEC.md "MOVE"): a moving nest's
 * placement and the ground under it from each time on, the records in a
 * vsv_meta, and the placed view of one time that every reader draws. */
#include "vsv_format_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int vsv_meta_add_move(vsv_meta *m, int64_t time, const double origin[2], const float *terrain)
{
    const size_t plane = (size_t)m->nx * m->ny;
    if (!isfinite(origin[0]) || !isfinite(origin[1]) || !terrain != !m->terrain ||
        (m->nmoves && time <= m->moves[m->nmoves - 1].time))
        return VSV_EINVAL;
    for (size_t c = 0; terrain && c < plane; c++)
        if (!isfinite(terrain[c]))
            return VSV_EINVAL;
    vsv_move *nm = realloc(m->moves, ((size_t)m->nmoves + 1) * sizeof *nm);
    if (!nm)
        return VSV_ENOMEM;
    m->moves = nm;
    vsv_move *v = &nm[m->nmoves];
    *v = (vsv_move){.time = time, .origin = {origin[0], origin[1]}};
    if (terrain) {
        if (!(v->terrain = malloc(plane * sizeof *v->terrain + 1)))
            return VSV_ENOMEM;
        memcpy(v->terrain, terrain, plane * sizeof *v->terrain);
    }
    m->nmoves++;
    return 0;
}

const vsv_move *vsv_meta_move_at(const vsv_meta *m, int64_t time)
{
    const vsv_move *in = NULL;
    for (int i = 0; i < m->nmoves && m->moves[i].time <= time; i++)
        in = &m->moves[i];
    return in;
}

vsv_meta vsv_meta_placed(const vsv_meta *m, int64_t time)
{
    vsv_meta v = *m;
    const vsv_move *mv = vsv_meta_move_at(m, time);
    if (mv) {
        v.origin[0] = mv->origin[0];
        v.origin[1] = mv->origin[1];
        if (mv->terrain)
            v.terrain = mv->terrain;
    }
    v.nmoves = 0; /* a view of one time stands still */
    v.moves = NULL;
    return v;
}

vsv_meta vsv_meta_span(const vsv_meta *m)
{
    vsv_meta v = *m;
    double lo[2] = {m->origin[0], m->origin[1]}, hi[2] = {lo[0], lo[1]};
    for (int i = 0; i < m->nmoves; i++)
        for (int a = 0; a < 2; a++) {
            lo[a] = fmin(lo[a], m->moves[i].origin[a]);
            hi[a] = fmax(hi[a], m->moves[i].origin[a]);
        }
    v.origin[0] = lo[0], v.origin[1] = lo[1];
    v.nx = m->nx + (int)lround((hi[0] - lo[0]) / m->spacing[0]);
    v.ny = m->ny + (int)lround((hi[1] - lo[1]) / m->spacing[1]);
    if (m->nmoves) { /* no per-column array fits the larger grid */
        v.terrain = v.landuse = NULL;
        v.nheights = 0;
        v.heights = NULL;
    }
    v.nmoves = 0;
    v.moves = NULL;
    return v;
}

void vsv_moves_clear_all(vsv_meta *m)
{
    for (int i = 0; i < m->nmoves; i++)
        free(m->moves[i].terrain);
    free(m->moves);
    m->moves = NULL;
    m->nmoves = 0;
}

int vsv_moves_copy_all(vsv_meta *dst, const vsv_meta *src)
{
    dst->moves = NULL;
    dst->nmoves = 0;
    for (int i = 0; i < src->nmoves; i++) {
        const vsv_move *v = &src->moves[i];
        const int rc = vsv_meta_add_move(dst, v->time, v->origin, v->terrain);
        if (rc)
            return rc;
    }
    return 0;
}

int vsv_moves_encode(const vsv_meta *m, const vsv_move *v, int coded, vsv_buf *b)
{
    const size_t plane = v->terrain ? (size_t)m->nx * m->ny : 0;
    coded = coded && plane;
    int rc;
    if ((rc = vsv_buf_u32(b, coded ? 1 : 0)) || (rc = vsv_buf_u32(b, 0)) || (rc = vsv_buf_u64(b, (uint64_t)v->time)) ||
        (rc = vsv_buf_f64(b, v->origin[0])) || (rc = vsv_buf_f64(b, v->origin[1])))
        return rc;
    if (coded)
        return vsv_plane_code(v->terrain, plane, b);
    if ((rc = vsv_buf_reserve(b, plane * 4)))
        return rc;
    for (size_t i = 0; i < plane; i++)
        vsv_wrf32(b->p + b->len + 4 * i, v->terrain[i]);
    b->len += plane * 4;
    return 0;
}

int vsv_moves_decode(vsv_meta *m, const unsigned char *p, size_t len, char *msg, size_t cap)
{
    const size_t plane = (size_t)m->nx * m->ny;
    const size_t want = 32 + (m->terrain ? 4 * plane : 0);
    const int coded = len >= 32 && vsv_rd32(p) == 1; /* format 3: the terrain coded */
    if ((coded ? !m->terrain || len == 32 : len != want || vsv_rd32(p)) || vsv_rd32(p + 4)) {
        vsv_msg(msg, cap, "MOVE record %d: %zu bytes where a %dx%d grid %s terrain needs %zu, or reserved bytes set",
                m->nmoves, (size_t)len, m->nx, m->ny, m->terrain ? "with" : "without", want);
        return VSV_ECORRUPT;
    }
    const double origin[2] = {vsv_rdf64(p + 16), vsv_rdf64(p + 24)};
    float *t = NULL;
    if (m->terrain) {
        if (!(t = malloc(plane * sizeof *t + 1)))
            return VSV_ENOMEM;
        const int crc = coded ? vsv_plane_decode(p + 32, len - 32, plane, t) : 0;
        if (crc) {
            free(t);
            vsv_msg(msg, cap, "MOVE record %d: its coded terrain %s a %dx%d plane", m->nmoves,
                    crc == VSV_ENOMEM ? "(out of memory) does not decode to" : "does not decode to", m->nx, m->ny);
            return crc;
        }
        for (size_t i = 0; i < plane && !coded; i++)
            t[i] = vsv_rdf32(p + 32 + 4 * i);
    }
    const int rc = vsv_meta_add_move(m, (int64_t)vsv_rd64(p + 8), origin, t);
    free(t);
    if (rc == VSV_EINVAL) {
        vsv_msg(msg, cap, "MOVE record %d: a position or terrain not finite, or out of time order", m->nmoves);
        return VSV_ECORRUPT;
    }
    return rc;
}
