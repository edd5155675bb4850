/* test_moves.c — a grid that moves in time (SPEC.md "MOVE", format 2.1):
 * a two-time moving nest written by the writer reads back with its
 * placements; a point falls in the cell where the nest stands at the step
 * asked; the ground under the nest masks its step; bad records are
 * refused; frames interpolated across a move are moved by whole cells. */
#include "vsv_convert.h"
#include "vsv_format_internal.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { NX = 20, NY = 10, NZ = 8, PLANE = NX * NY, NC = PLANE * NZ };

/* A Mercator grid of 10 km cells over the Gulf, a terrain that rises to the
 * east at its first place and is flat sea at the second, 3 cells west and
 * 2 north from 3 h on. */
static void nest(vsv_meta *m, float *t0, float *t1)
{
    vsv_meta_init(m);
    m->nx = NX, m->ny = NY, m->nz = NZ;
    m->spacing[0] = m->spacing[1] = 10000, m->spacing[2] = 250;
    m->origin[0] = -300000, m->origin[1] = 2500000, m->origin[2] = 125;
    m->proj = (vsv_proj){.kind = VSV_PROJ_MERCATOR, .lon0 = -89};
    vsv_meta_add_var(m, "QCLOUD", "kg kg-1", "cloud water");
    vsv_meta_alloc_terrain(m);
    for (int c = 0; c < PLANE; c++) {
        t0[c] = (float)(100 * (c % NX)); /* 0 .. 1900 m */
        t1[c] = 0;
    }
    memcpy(m->terrain, t0, PLANE * sizeof *t0);
}

/* predict: the default writer (format 3.0: every place's terrain coded);
 * else the 1.x writer, which a moving nest makes 2.1 (raw planes) */
static void test_roundtrip(int predict)
{
    float t0[PLANE], t1[PLANE], *v0 = malloc(NC * sizeof *v0), *v1 = malloc(NC * sizeof *v1);
    float *out = malloc(NC * sizeof *out);
    vsv_meta m;
    nest(&m, t0, t1);
    const double o1[2] = {-330000, 2520000};
    CHECK(vsv_meta_add_move(&m, 10800, o1, t1) == 0, "a placement from 3 h on");
    CHECK(vsv_meta_add_move(&m, 10800, o1, t1) == VSV_EINVAL, "one at the same time refused");
    CHECK(vsv_meta_add_move(&m, 7200, o1, t1) == VSV_EINVAL, "one out of time order refused");
    const double bad[2] = {NAN, 0};
    CHECK(vsv_meta_add_move(&m, 20000, bad, t1) == VSV_EINVAL, "a position not finite refused");
    CHECK(vsv_meta_add_move(&m, 20000, o1, NULL) == VSV_EINVAL, "no terrain where the grid has one refused");
    for (int c = 0; c < NC; c++) {
        v0[c] = (float)(c % PLANE) * 1e-6f;
        v1[c] = 1e-3f - (float)(c % PLANE) * 1e-6f;
    }
    const char *path = vsv_test_tmp("moves.vsv");
    vsv_writer *w = NULL;
    const float *s0[1] = {v0}, *s1[1] = {v1};
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.predict = predict;
    int rc = vsv_writer_create(path, &m, &o, &w);
    if (!rc)
        rc = vsv_writer_add_step(w, 0, s0);
    if (!rc)
        rc = vsv_writer_add_step(w, 10800, s1);
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    vsv_file *f = NULL;
    CHECK(rc == 0 && vsv_file_open(path, &f) == 0, "a moving nest written and opened", "%d", rc);
    vsv_file_info info = {0};
    if (f)
        vsv_file_info_get(f, &info);
    CHECK(info.major == (predict ? 3 : 2) && info.minor == !predict,
          predict ? "its header says 3.0 (coded terrain)" : "written for 1.x readers, its header says 2.1", "%d.%d",
          info.major, info.minor);
    const vsv_meta *fm = f ? vsv_file_meta(f) : &m;
    CHECK(fm->nmoves == 1 && fm->moves[0].time == 10800 && fm->moves[0].origin[0] == o1[0] &&
              fm->moves[0].origin[1] == o1[1] && fm->moves[0].terrain && !memcmp(fm->moves[0].terrain, t1, sizeof t1),
          "the placement reads back: time, place and ground");
    const vsv_meta p0 = vsv_meta_placed(fm, 0), p1 = vsv_meta_placed(fm, 10800), pl = vsv_meta_placed(fm, 99999);
    CHECK(p0.origin[0] == -300000 && p0.terrain == fm->terrain && p1.origin[0] == o1[0] &&
              p1.terrain == fm->moves[0].terrain && pl.origin[1] == o1[1] && !p1.nmoves,
          "placed views: GRID's before the move, the move's from it on");
    /* a point where the nest stands later: cell (5, 5) of the second place
       is cell (2, 7) of the first */
    double lat, lon;
    vsv_meta_cell_latlon(&p1, 5, 5, &lat, &lon);
    vsv_point pt0, pt1;
    char msg[256];
    const int r0 = vsv_point_locate_at(fm, 0, lat, lon, NAN, &pt0, msg, sizeof msg);
    const int r1 = vsv_point_locate_at(fm, 10800, lat, lon, NAN, &pt1, msg, sizeof msg);
    CHECK(!r0 && !r1 && pt1.cell[0] == 5 && pt1.cell[1] == 5 && pt0.cell[0] == 2 && pt0.cell[1] == 7,
          "a point is in the cell where the nest stands at the time asked", "(%d,%d) (%d,%d)", pt0.cell[0], pt0.cell[1],
          pt1.cell[0], pt1.cell[1]);
    const vsv_meta span = vsv_meta_span(fm);
    CHECK(span.nx == NX + 3 && span.ny == NY + 2 && span.origin[0] == o1[0] && span.origin[1] == 2500000 &&
              !span.terrain,
          "the span covers both places", "%d x %d at %g, %g", span.nx, span.ny, span.origin[0], span.origin[1]);
    /* the ground: the first place's rises to 1900 m, the second is sea */
    vsv_decoder *d = NULL;
    int under0 = 0, under1 = 0;
    if (f && !vsv_decoder_create(f, &d) && !vsv_decoder_volume(d, 0, 0, out))
        for (int c = 0; c < NC; c++)
            under0 += isnan(out[c]);
    if (d && !vsv_decoder_volume(d, 1, 0, out))
        for (int c = 0; c < NC; c++)
            under1 += isnan(out[c]);
    CHECK(under0 == 760 && under1 == 0, "no data below the ground under the nest at each step", "%d, %d", under0,
          under1);
    vsv_decoder_free(d);
    vsv_file_free(f);
    vsv_meta_clear(&m);
    free(v0);
    free(v1);
    free(out);
}

/* Malformed MOVE records: each a clear error, never a misplaced grid. */
static void test_bad_records(void)
{
    float t0[PLANE], t1[PLANE];
    vsv_meta m, back;
    nest(&m, t0, t1);
    vsv_meta_add_var(&m, "Q", "kg kg-1", "");
    const double o1[2] = {-330000, 2520000};
    vsv_meta_add_move(&m, 10800, o1, t1);
    vsv_buf b = {0};
    vsv_meta_init(&back);
    char msg[256];
    int rc = vsv_meta_encode(&m, NULL, 0, &b);
    CHECK(!rc && !vsv_meta_decode(b.p, b.len, &back, NULL, msg, sizeof msg) && back.nmoves == 1 &&
              back.moves[0].time == 10800,
          "encoded and decoded");
    unsigned char *mv = NULL;
    for (size_t at = 0; !rc && at + 8 <= b.len; at += 8 + (size_t)vsv_align_up(vsv_rd32(b.p + at + 4), 8))
        if (!memcmp(b.p + at, "MOVE", 4))
            mv = b.p + at;
    CHECK(mv && vsv_rd32(mv + 4) == 32 + 4 * PLANE, "the record holds place and ground");
    if (mv) {
        mv[8] = 1; /* a reserved byte */
        rc = vsv_meta_decode(b.p, b.len, &back, NULL, msg, sizeof msg);
        CHECK(rc == VSV_ECORRUPT && strstr(msg, "MOVE record 0"), "reserved bytes set refused", "%s", msg);
        mv[8] = 0;
        memcpy(mv + 24, (const unsigned char[8]){0, 0, 0, 0, 0, 0, 0xf0, 0x7f}, 8); /* x = +inf */
        rc = vsv_meta_decode(b.p, b.len, &back, NULL, msg, sizeof msg);
        CHECK(rc == VSV_ECORRUPT && strstr(msg, "not finite"), "a place not finite refused", "%s", msg);
    }
    vsv_buf_free(&b);
    vsv_meta_clear(&back);
    vsv_meta_clear(&m);
}

typedef struct frames {
    int n;
    int64_t t[4];
    float f[4][NC];
} frames;

static int keep(void *ctx, int64_t t, const float *const *f)
{
    frames *fr = ctx;
    if (fr->n >= 4)
        return -1;
    fr->t[fr->n] = t;
    memcpy(fr->f[fr->n++], f[0], NC * sizeof(float));
    return 0;
}

/* Interpolated across a move, the frame between lies at the earlier place
 * and blends each cell with the later output's value at the same place:
 * the later frame moved back 3 cells east and 2 south into it. */
static void test_interp(void)
{
    static float t0[PLANE], t1[PLANE], a[NC], b[NC];
    static frames fr;
    vsv_meta m;
    nest(&m, t0, t1);
    const double o1[2] = {-330000, 2520000};
    vsv_meta_add_move(&m, 7200, o1, t1);
    for (int c = 0; c < NC; c++) {
        const int i = c % NX, j = c / NX % NY;
        a[c] = 0;
        b[c] = (float)(100 * j + i); /* at the later place */
    }
    vsv_interp_opts o = {VSV_TIME_LINEAR, 1};
    vsv_interp *ip = NULL;
    int rc = vsv_interp_open(3600, &m, &o, keep, &fr, &ip);
    const float *fa[1] = {a}, *fb[1] = {b};
    if (!rc)
        rc = vsv_interp_push(ip, 0, fa);
    if (!rc)
        rc = vsv_interp_push(ip, 7200, fb);
    CHECK(rc == 0 && fr.n == 3 && fr.t[1] == 3600, "three frames, one between", "%d: %s", rc, vsv_interp_error(ip));
    /* cell (i, j) of the first place is cell (i + 3, j - 2) of the second */
    const float mid_in = fr.f[1][5 * NX + 7], want_in = 0.5f * (float)(100 * 3 + 10);
    const float mid_out = fr.f[1][1 * NX + 1]; /* (1, 1): (4, -1) of the later, not covered: the earlier's */
    CHECK(fabsf(mid_in - want_in) < 1e-4f && mid_out == 0.0f && !memcmp(fr.f[2], b, sizeof b),
          "the frame between blends the same place; the later frame passes through", "%g (want %g), %g", mid_in,
          want_in, mid_out);
    vsv_interp_free(ip);
    /* a move by part of a cell cannot be interpolated: said so */
    vsv_meta_clear(&m);
    nest(&m, t0, t1);
    const double half[2] = {-305000, 2500000};
    vsv_meta_add_move(&m, 7200, half, t1);
    fr.n = 0;
    rc = vsv_interp_open(3600, &m, &o, keep, &fr, &ip);
    if (!rc)
        rc = vsv_interp_push(ip, 0, fa);
    if (!rc)
        rc = vsv_interp_push(ip, 7200, fb);
    CHECK(rc == VSV_EUNSUPPORTED && strstr(vsv_interp_error(ip), "0.500 x 0.000 cells"),
          "a move by half a cell is refused with its size", "%d: %s", rc, vsv_interp_error(ip));
    vsv_interp_free(ip);
    vsv_meta_clear(&m);
}

int main(void)
{
    test_roundtrip(1);
    test_roundtrip(0);
    test_bad_records();
    test_interp();
    return vsv_test_done();
}
