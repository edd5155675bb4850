/* test_iso.c — isosurface extraction (vsv_iso_*, issue 35) against analytic
 * fields: a sphere's distance field gives the sphere's area within 2 %,
 * closed (every edge in two triangles) and consistently wound, its normals
 * toward the centre; a linear field gives a plane of exactly the grid's
 * area; native levels put vertices at their columns' heights; an empty
 * field, or a value outside the data, gives nothing without visiting a
 * brick; unchanged bricks keep their triangles across steps. */
#include "vsv_format.h"
#include "vsv_render.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { B = 16 };

typedef double (*field_fn)(const double *ctx, int i, int j, int k);

/* An in-memory volume of f over nx x ny x nz cells, bricks of B, with exact
 * brick ranges and a key per brick of its values (a hash: equal values,
 * equal keys, as a file's). */
static vsv_volume *make_volume(int nx, int ny, int nz, field_fn f, const double *ctx)
{
    vsv_volume *v = calloc(1, sizeof *v);
    v->nx = nx, v->ny = ny, v->nz = nz, v->brick = B, v->shift = 4;
    v->bdim[0] = (nx + B - 1) / B, v->bdim[1] = (ny + B - 1) / B, v->bdim[2] = (nz + B - 1) / B;
    v->nbricks = v->bdim[0] * v->bdim[1] * v->bdim[2];
    v->bricks = calloc((size_t)v->nbricks, sizeof *v->bricks);
    v->bmin = calloc((size_t)v->nbricks, sizeof *v->bmin);
    v->bmax = calloc((size_t)v->nbricks, sizeof *v->bmax);
    v->bkey = calloc((size_t)v->nbricks, sizeof *v->bkey);
    v->gen = vsv_volume_new_gen();
    for (int b = 0; b < v->nbricks; b++) {
        const int i0 = b % v->bdim[0] * B, j0 = b / v->bdim[0] % v->bdim[1] * B, k0 = b / (v->bdim[0] * v->bdim[1]) * B;
        v->bmin[b] = INFINITY, v->bmax[b] = -INFINITY;
        v->bkey[b] = 1469598103934665603u;
        if (!f) { /* EMPTY */
            v->bmin[b] = v->bmax[b] = 0;
            continue;
        }
        float *p = v->bricks[b] = calloc(B * B * B, sizeof(float));
        for (int k = 0; k < B; k++)
            for (int j = 0; j < B; j++)
                for (int i = 0; i < B; i++) {
                    const int gi = i0 + i, gj = j0 + j, gk = k0 + k;
                    if (gi >= nx || gj >= ny || gk >= nz)
                        continue;
                    const float x = p[i + B * (j + B * k)] = (float)f(ctx, gi, gj, gk);
                    v->bmin[b] = fminf(v->bmin[b], x);
                    v->bmax[b] = fmaxf(v->bmax[b], x);
                    uint32_t bits;
                    memcpy(&bits, &x, 4);
                    v->bkey[b] = (v->bkey[b] ^ bits) * 1099511628211u;
                }
    }
    return v;
}

static void free_volume(vsv_volume *v)
{
    for (int b = 0; v && b < v->nbricks; b++)
        free(v->bricks[b]);
    if (v) {
        free(v->bricks);
        free(v->bmin);
        free(v->bmax);
        free(v->bkey);
    }
    free(v);
}

/* An even grid of cells d metres wide and dz tall, cell (0, 0, 0) at the
 * origin. */
static void grid(vsv_meta *m, int nx, int ny, int nz, double d, double dz)
{
    vsv_meta_init(m);
    m->nx = nx, m->ny = ny, m->nz = nz;
    m->spacing[0] = m->spacing[1] = d;
    m->spacing[2] = dz;
    m->vert_kind = VSV_VERT_EVEN;
}

/* The whole surface as one mesh: every brick's vertices and triangles. */
typedef struct mesh {
    float *pos, *nrm;
    uint32_t *tri;
    size_t nv, nt;
} mesh;

static mesh gather(const vsv_iso *s)
{
    vsv_iso_info in;
    vsv_iso_get_info(s, &in);
    mesh M = {malloc(in.nverts * 12 + 12), malloc(in.nverts * 12 + 12), malloc(in.ntris * 12 + 12), 0, 0};
    vsv_iso_mesh b;
    for (int i = 0; vsv_iso_brick(s, i, &b) == 0; i++) {
        if (!b.nverts) /* a skipped brick: no arrays */
            continue;
        memcpy(M.pos + 3 * M.nv, b.pos, (size_t)b.nverts * 12);
        memcpy(M.nrm + 3 * M.nv, b.nrm, (size_t)b.nverts * 12);
        for (int t = 0; t < 3 * b.ntris; t++)
            M.tri[3 * M.nt + t] = (uint32_t)M.nv + b.tri[t];
        M.nv += (size_t)b.nverts;
        M.nt += (size_t)b.ntris;
    }
    return M;
}

static void mesh_free(mesh *M) { free(M->pos), free(M->nrm), free(M->tri); }

static double tri_area(const mesh *M, size_t t, double n[3])
{
    const float *a = M->pos + 3 * M->tri[3 * t], *b = M->pos + 3 * M->tri[3 * t + 1],
                *c = M->pos + 3 * M->tri[3 * t + 2];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * w[2] - u[2] * w[1], n[1] = u[2] * w[0] - u[0] * w[2], n[2] = u[0] * w[1] - u[1] * w[0];
    return sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) / 2;
}

static double area(const mesh *M)
{
    double A = 0, n[3];
    for (size_t t = 0; t < M->nt; t++)
        A += tri_area(M, t, n);
    return A;
}

/* Vertices welded by position (bit for bit): id[v] the first vertex at v's
 * place. */
static const float *sort_pos;
static int cmp_pos(const void *a, const void *b)
{
    const uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    const int c = memcmp(sort_pos + 3 * x, sort_pos + 3 * y, 12);
    return c ? c : (x > y) - (x < y);
}

static uint32_t *weld(const mesh *M)
{
    uint32_t *ord = malloc(M->nv * 4 + 4), *id = malloc(M->nv * 4 + 4);
    for (size_t v = 0; v < M->nv; v++)
        ord[v] = (uint32_t)v;
    sort_pos = M->pos;
    qsort(ord, M->nv, 4, cmp_pos);
    for (size_t v = 0; v < M->nv; v++)
        id[ord[v]] = v && !memcmp(M->pos + 3 * ord[v], M->pos + 3 * ord[v - 1], 12) ? id[ord[v - 1]] : ord[v];
    free(ord);
    return id;
}

static int cmp_u64(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* Closed and consistently wound: after welding, every directed edge (a, b)
 * appears once and (b, a) once too; degenerate triangles (two corners at one
 * place, where the surface passes through a point) are counted apart. *bad
 * gets the edges that break the rule. */
static void closed(const mesh *M, size_t *bad, size_t *degenerate)
{
    uint32_t *id = weld(M);
    uint64_t *e = malloc(M->nt * 3 * 8 + 8);
    size_t ne = 0;
    *degenerate = 0;
    for (size_t t = 0; t < M->nt; t++) {
        const uint32_t v[3] = {id[M->tri[3 * t]], id[M->tri[3 * t + 1]], id[M->tri[3 * t + 2]]};
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
            (*degenerate)++;
            continue;
        }
        for (int q = 0; q < 3; q++)
            e[ne++] = (uint64_t)v[q] << 32 | v[(q + 1) % 3];
    }
    qsort(e, ne, 8, cmp_u64);
    *bad = 0;
    for (size_t i = 0; i < ne; i++) {
        const uint64_t rev = e[i] << 32 | e[i] >> 32;
        const int dup = (i > 0 && e[i - 1] == e[i]) || (i + 1 < ne && e[i + 1] == e[i]);
        if (dup || !bsearch(&rev, e, ne, 8, cmp_u64))
            (*bad)++;
    }
    free(e);
    free(id);
}

static double sphere(const double *c, int i, int j, int k)
{
    return sqrt((i - c[0]) * (i - c[0]) + (j - c[1]) * (j - c[1]) + (k - c[2]) * (k - c[2]));
}

/* A sphere of radius 15 m off the grid's centre, in a 48-cube grid of
 * 1 m cells (three bricks a side): the sphere's area within 2 %, closed,
 * every triangle and vertex normal facing the centre (the values below). */
static void test_sphere(void)
{
    const double c[3] = {23.3, 24.1, 22.7}, r = 15;
    vsv_meta m;
    grid(&m, 48, 48, 48, 1, 1);
    vsv_volume *v = make_volume(48, 48, 48, sphere, c);
    vsv_iso *s = NULL;
    if (!CHECK(vsv_iso_create(2, &s) == 0 && vsv_iso_extract(s, &m, v, (float)r) == 0, "sphere: extracted"))
        goto done;
    mesh M = gather(s);
    const double A = area(&M), want = 4 * M_PI * r * r;
    CHECK(M.nt > 1000 && fabs(A / want - 1) < 0.02, "sphere: area within 2 % of 4 pi r^2",
          "(%zu triangles, %.2f m2 for %.2f: %+.3f %%)", M.nt, A, want, 100 * (A / want - 1));
    printf("sphere r %g: %zu triangles, area %.2f for 4 pi r^2 = %.2f (%+.3f %%)\n", r, M.nt, A, want,
           100 * (A / want - 1));
    size_t bad, deg;
    closed(&M, &bad, &deg);
    CHECK(bad == 0, "sphere: closed, every edge in two triangles wound oppositely", "(%zu edges wrong, %zu degenerate)",
          bad, deg);
    size_t out = 0, nbad = 0;
    double maxd = 0;
    for (size_t t = 0; t < M.nt; t++) {
        double n[3];
        const double a = tri_area(&M, t, n);
        const float *p = M.pos + 3 * M.tri[3 * t];
        if (a > 1e-9 && n[0] * (p[0] - c[0]) + n[1] * (p[1] - c[1]) + n[2] * (p[2] - c[2]) >= 0)
            out++;
    }
    for (size_t i = 0; i < M.nv; i++) {
        const float *p = M.pos + 3 * i, *n = M.nrm + 3 * i;
        const double d[3] = {c[0] - p[0], c[1] - p[1], c[2] - p[2]}, L = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        nbad += (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]) / L < 0.98;
        maxd = fmax(maxd, fabs(L - r));
    }
    CHECK(out == 0, "sphere: every triangle wound to face the centre", "(%zu face out)", out);
    CHECK(nbad == 0 && maxd < 0.05, "sphere: vertices on the sphere, normals toward the centre",
          "(%zu normals off, farthest vertex %.4f m off)", nbad, maxd);
    /* a sphere of 5 m inside the middle brick's cells: only that brick's
     * cubes straddle it (the others' points all lie farther) */
    vsv_iso_info in;
    vsv_iso_extract(s, &m, v, 5);
    vsv_iso_get_info(s, &in);
    int with = 0;
    vsv_iso_mesh bm;
    for (int b = 0; vsv_iso_brick(s, b, &bm) == 0; b++)
        with += bm.ntris > 0 ? 1 + b : 0;
    /* the bricks whose own or followers' ranges straddle 5: those at 0 or
     * 1 along every axis; triangles in the middle one (13) only */
    CHECK(in.nbricks == 27 && in.visited == 8 && with == 14, "sphere: only bricks the surface may cross visited",
          "(%d of %d, triangles in brick %d)", in.visited, in.nbricks, with - 1);
    vsv_iso_extract(s, &m, v, (float)r);
    /* the same on one thread: the same triangles, bit for bit */
    vsv_iso *s1 = NULL;
    int same = vsv_iso_create(1, &s1) == 0 && vsv_iso_extract(s1, &m, v, (float)r) == 0;
    if (same) {
        mesh M1 = gather(s1);
        same = M1.nt == M.nt && M1.nv == M.nv && !memcmp(M1.pos, M.pos, M.nv * 12) && !memcmp(M1.tri, M.tri, M.nt * 12);
        mesh_free(&M1);
    }
    CHECK(same, "sphere: one thread or two, the same triangles");
    vsv_iso_free(s1);
    mesh_free(&M);
done:
    vsv_iso_free(s);
    free_volume(v);
    vsv_meta_clear(&m);
}

/* The sphere with no data (NaN) west of x = 9.5: its cap there is cut off. */
static double sphere_cut(const double *c, int i, int j, int k) { return i <= 9 ? NAN : sphere(c, i, j, k); }

/* Beside cells without data the cubes that hold them are left out and the
 * normals come from one side: every normal a unit vector. */
static void test_nodata(void)
{
    const double c[3] = {23.3, 24.1, 22.7};
    vsv_meta m;
    grid(&m, 48, 48, 48, 1, 1);
    vsv_volume *v = make_volume(48, 48, 48, sphere_cut, c);
    vsv_iso *s = NULL;
    if (!CHECK(vsv_iso_create(1, &s) == 0 && vsv_iso_extract(s, &m, v, 15) == 0, "no data: extracted"))
        goto done;
    mesh M = gather(s);
    size_t bad = 0;
    double west = INFINITY;
    for (size_t i = 0; i < M.nv; i++) {
        const float *n = M.nrm + 3 * i;
        bad += !(fabs(sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) - 1) < 1e-5);
        west = fmin(west, M.pos[3 * i]);
    }
    CHECK(M.nt > 0 && bad == 0 && west >= 10, "no data: the cubes with none left out, every normal a unit vector",
          "(%zu triangles, %zu bad normals, westmost vertex %.2f)", M.nt, bad, west);
    mesh_free(&M);
done:
    vsv_iso_free(s);
    free_volume(v);
    vsv_meta_clear(&m);
}

static double zlevel(const double *c, int i, int j, int k) { return (void)c, (void)i, (void)j, k; }

/* f = k over 40 x 37 x 20 cells of 1000 x 1000 x 250 m (bricks cut short
 * at the edges): VALUE 7.3 is the plane z = 125 + 7.3 * 250 across the
 * cell centres' span, exactly 39 x 36 km2, its normals down the gradient. */
static void test_plane(void)
{
    vsv_meta m;
    grid(&m, 40, 37, 20, 1000, 250);
    m.origin[2] = 125;
    vsv_volume *v = make_volume(40, 37, 20, zlevel, NULL);
    vsv_iso *s = NULL;
    if (!CHECK(vsv_iso_create(0, &s) == 0 && vsv_iso_extract(s, &m, v, 7.3f) == 0, "plane: extracted"))
        goto done;
    mesh M = gather(s);
    const double A = area(&M), want = 39e3 * 36e3, z = 125 + (double)7.3f * 250;
    CHECK(fabs(A / want - 1) < 1e-6, "plane: the grid's area exactly", "(%.1f m2 for %.1f)", A, want);
    double dz = 0, dn = 0;
    for (size_t i = 0; i < M.nv; i++) {
        dz = fmax(dz, fabs(M.pos[3 * i + 2] - z));
        dn = fmax(dn, fabs(M.nrm[3 * i + 2] + 1));
    }
    size_t up = 0;
    for (size_t t = 0; t < M.nt; t++) {
        double n[3];
        up += tri_area(&M, t, n) > 0 && n[2] >= 0;
    }
    CHECK(dz < 1e-3 && dn < 1e-6 && up == 0, "plane: flat at its height, normals and triangles facing down",
          "(%.2g m off, normals %.2g off, %zu up)", dz, dn, up);
    size_t bad, deg;
    closed(&M, &bad, &deg);
    vsv_iso_info in;
    vsv_iso_get_info(s, &in);
    CHECK(in.visited == 3 * 3 && deg == 0, "plane: the bricks of one layer visited", "(%d, %zu degenerate)", in.visited,
          deg);
    mesh_free(&M);
done:
    vsv_iso_free(s);
    free_volume(v);
    vsv_meta_clear(&m);
}

/* Two layers one cell thick (f 1 at level 5, 10 at level 7, else 0; a
 * bump of level 5 in the middle): at VALUE 0.5 the top of the lower layer
 * lies between its own 1 and a 0, but the central difference at the 0
 * reaches the 10 above and points down, into the layer. Every normal
 * faces as its triangles do (the gradient's pointed into the layer on
 * its whole top). */
static double layers(const double *c, int i, int j, int k)
{
    (void)c;
    const int bump = i > 8 && i < 14 && j > 8 && j < 14;
    return k == 7 ? 10 : k == 5 || (bump && k == 4) ? 1 : 0;
}

static void test_thin_layers(void)
{
    vsv_meta m;
    grid(&m, 24, 22, 12, 1000, 250);
    vsv_volume *v = make_volume(24, 22, 12, layers, NULL);
    vsv_iso *s = NULL;
    if (!CHECK(vsv_iso_create(2, &s) == 0 && vsv_iso_extract(s, &m, v, 0.5f) == 0, "thin layers: extracted"))
        goto done;
    mesh M = gather(s);
    size_t against = 0;
    for (size_t t = 0; t < M.nt; t++) {
        double n[3];
        if (!(tri_area(&M, t, n) > 0))
            continue;
        for (int c = 0; c < 3; c++) {
            const float *vn = M.nrm + 3 * M.tri[3 * t + c];
            against += vn[0] * n[0] + vn[1] * n[1] + vn[2] * n[2] < 0;
        }
    }
    CHECK(M.nt > 1000 && against == 0, "thin layers: every vertex normal faces as its triangles",
          "(%zu triangles, %zu corners against)", M.nt, against);
    mesh_free(&M);
done:
    vsv_iso_free(s);
    free_volume(v);
    vsv_meta_clear(&m);
}

/* A layer one cell thick that steps between levels 5 and 6 along lines
 * across both faces between bricks: vertices on those faces where the
 * gradient points into the layer and the surface bends there. */
static double steps(const double *c, int i, int j, int k)
{
    (void)c;
    return k == 5 + (i * 7 + j * 3) / 11 % 2 ? 1 : 0;
}

/* A vertex that two bricks both make (their common face) gets one normal:
 * each brick's rule for normals sees the triangles of both (it saw its own
 * alone: a shading seam where they differed), from the same float
 * positions, far from the projection's origin as real grids are. */
static void test_seams(double (*f)(const double *, int, int, int), const char *what)
{
    vsv_meta m;
    grid(&m, 24, 22, 12, 1013.7, 250);
    m.origin[0] = -1971620.3, m.origin[1] = 1821000.7; /* a float's step there: 0.125 m */
    vsv_volume *v = make_volume(24, 22, 12, f, NULL);
    vsv_iso *s = NULL;
    if (!CHECK(vsv_iso_create(2, &s) == 0 && vsv_iso_extract(s, &m, v, 0.5f) == 0, "seams: extracted", "%s", what))
        goto done;
    mesh M = gather(s);
    uint32_t *id = weld(&M);
    size_t shared = 0, differ = 0;
    for (size_t i = 0; i < M.nv; i++) {
        if (id[i] == i)
            continue;
        const float *a = M.nrm + 3 * i, *b = M.nrm + 3 * id[i];
        shared++;
        differ += fabs(a[0] - b[0]) + fabs(a[1] - b[1]) + fabs(a[2] - b[2]) > 1e-5;
    }
    CHECK(shared > 50 && differ == 0, "seams: a vertex two bricks make has one normal", "%s: %zu shared, %zu differ",
          what, shared, differ);
    free(id);
    mesh_free(&M);
done:
    vsv_iso_free(s);
    free_volume(v);
    vsv_meta_clear(&m);
}

/* Native levels with per-column heights 50 i + 10 j + 125 + 250 k and
 * f = k: VALUE 3.5 lies halfway between levels 3 and 4 in every column,
 * at 50 i + 10 j + 1000 m, wherever the vertex is. */
static void test_native(void)
{
    enum { NX = 20, NY = 18, NZ = 10 };
    vsv_meta m;
    grid(&m, NX, NY, NZ, 1000, 250);
    m.vert_kind = VSV_VERT_NATIVE;
    vsv_meta_alloc_levels(&m);
    vsv_meta_alloc_terrain(&m);
    float *z = malloc(sizeof(float) * NX * NY * NZ);
    for (int k = 0; k < NZ; k++)
        for (int j = 0; j < NY; j++)
            for (int i = 0; i < NX; i++) {
                m.terrain[j * NX + i] = (float)(50.0 * i + 10.0 * j);
                z[((size_t)k * NY + j) * NX + i] = (float)(50.0 * i + 10.0 * j + 125 + 250 * k);
            }
    for (int k = 0; k < NZ; k++)
        m.levels[k] = 125 + 250 * k + 500;
    vsv_volume *v = make_volume(NX, NY, NZ, zlevel, NULL);
    vsv_iso *s = NULL;
    if (!CHECK(vsv_meta_add_heights(&m, 0, z, NULL, NULL) == 0 && vsv_iso_create(1, &s) == 0 &&
                   vsv_iso_extract(s, &m, v, 3.5f) == 0,
               "native: extracted"))
        goto done;
    mesh M = gather(s);
    double off = 0;
    for (size_t i = 0; i < M.nv; i++) {
        const float *p = M.pos + 3 * i;
        off = fmax(off, fabs(p[2] - (50.0 * p[0] / 1000 + 10.0 * p[1] / 1000 + 1000)));
    }
    CHECK(M.nt > 0 && off < 1e-2, "native: vertices at their columns' heights", "(%zu triangles, %.3g m off)", M.nt,
          off);
    mesh_free(&M);
done:
    vsv_iso_free(s);
    free_volume(v);
    free(z);
    vsv_meta_clear(&m);
}

/* Nothing to extract: an EMPTY field, values above or below the data, a
 * value that is not a number. */
static void test_nothing(void)
{
    const double c[3] = {20, 20, 20};
    vsv_meta m;
    grid(&m, 40, 40, 40, 1, 1);
    vsv_volume *e = make_volume(40, 40, 40, NULL, NULL), *v = make_volume(40, 40, 40, sphere, c);
    vsv_iso *s = NULL;
    vsv_iso_info in;
    if (!CHECK(vsv_iso_create(1, &s) == 0, "nothing: extractor"))
        goto done;
    const float values[3] = {100, -1, 0.5f};
    const vsv_volume *vols[3] = {v, v, e};
    const char *what[3] = {"above", "below", "empty"};
    for (int q = 0; q < 3; q++) {
        int rc = vsv_iso_extract(s, &m, vols[q], values[q]);
        vsv_iso_get_info(s, &in);
        CHECK(rc == 0 && in.ntris == 0 && in.visited == 0, "nothing: no triangle, no brick visited",
              "(%s: rc %d, %zu triangles, %d bricks)", what[q], rc, in.ntris, in.visited);
    }
    CHECK(vsv_iso_extract(s, &m, v, NAN) == VSV_EINVAL, "nothing: a NaN value refused");
done:
    vsv_iso_free(s);
    free_volume(v);
    free_volume(e);
    vsv_meta_clear(&m);
}

/* The sphere with the values of brick 0 (cells 0..15 each way) raised. */
static double sphere_bumped(const double *c, int i, int j, int k)
{
    return sphere(c, i, j, k) + (i < B && j < B && k < B ? 0.5 : 0);
}

/* 1 when s and t hold the same triangles, brick by brick, bit for bit. */
static int same_meshes(const vsv_iso *s, const vsv_iso *t)
{
    vsv_iso_mesh a, b;
    for (int i = 0; vsv_iso_brick(s, i, &a) == 0; i++)
        if (vsv_iso_brick(t, i, &b) || a.nverts != b.nverts || a.ntris != b.ntris ||
            (a.nverts && memcmp(a.pos, b.pos, (size_t)a.nverts * 12)) ||
            (a.nverts && memcmp(a.nrm, b.nrm, (size_t)a.nverts * 12)) ||
            (a.ntris && memcmp(a.tri, b.tri, (size_t)a.ntris * 12)))
            return 0;
    return 1;
}

/* Steps: the same volume again, a new volume of the same values (new
 * generation, the same brick keys), and one with brick 0 changed, after
 * which only the visited bricks whose neighbourhood holds brick 0 are
 * redone, and the triangles are those of a fresh extraction. */
static void test_steps(void)
{
    const double c[3] = {23.3, 24.1, 22.7};
    vsv_meta m;
    grid(&m, 48, 48, 48, 1, 1);
    vsv_volume *v = make_volume(48, 48, 48, sphere, c), *v2 = make_volume(48, 48, 48, sphere, c);
    vsv_volume *v3 = make_volume(48, 48, 48, sphere_bumped, c);
    vsv_iso *s = NULL, *fresh = NULL;
    vsv_iso_info a, b;
    if (!CHECK(vsv_iso_create(2, &s) == 0 && vsv_iso_create(1, &fresh) == 0 && vsv_iso_extract(s, &m, v, 15) == 0,
               "steps: extracted"))
        goto done;
    vsv_iso_get_info(s, &a);
    vsv_iso_extract(s, &m, v, 15);
    vsv_iso_get_info(s, &b);
    CHECK(b.reused == a.visited && b.ntris == a.ntris, "steps: the same volume again reuses every brick", "(%d of %d)",
          b.reused, a.visited);
    vsv_iso_extract(s, &m, v2, 15);
    vsv_iso_get_info(s, &b);
    CHECK(b.reused == a.visited && b.ntris == a.ntris, "steps: the same values again (brick keys) reuse every brick",
          "(%d of %d)", b.reused, a.visited);
    /* brick 0's neighbourhood: the bricks at (0|1, 0|1, 0|1) */
    int near = 0;
    for (int q = 0; q < 8; q++) {
        const int n = (q & 1) + 3 * ((q >> 1 & 1) + 3 * (q >> 2 & 1));
        float lo = INFINITY, hi = -INFINITY;
        for (int r = 0; r < 8; r++) { /* visited: its and its followers' range straddle 15 */
            const int ii = n % 3 + (r & 1), jj = n / 3 % 3 + (r >> 1 & 1), kk = n / 9 + (r >> 2 & 1);
            if (ii < 3 && jj < 3 && kk < 3) {
                const int o = ii + 3 * (jj + 3 * kk);
                lo = fminf(lo, v3->bmin[o]), hi = fmaxf(hi, v3->bmax[o]);
            }
        }
        near += lo <= 15 && hi > 15;
    }
    vsv_iso_extract(s, &m, v3, 15);
    vsv_iso_get_info(s, &b);
    vsv_iso_extract(fresh, &m, v3, 15);
    CHECK(near > 0 && b.reused == b.visited - near, "steps: one brick changed redoes the bricks that read it",
          "(%d reused of %d visited, %d near)", b.reused, b.visited, near);
    CHECK(same_meshes(s, fresh), "steps: the kept and redone bricks are a fresh extraction's");
    vsv_iso_extract(s, &m, v3, 14);
    vsv_iso_get_info(s, &b);
    CHECK(b.reused == 0, "steps: another value redoes every brick", "(%d reused)", b.reused);
done:
    vsv_iso_free(s);
    vsv_iso_free(fresh);
    free_volume(v);
    free_volume(v2);
    free_volume(v3);
    vsv_meta_clear(&m);
}

int main(void)
{
    test_sphere();
    test_plane();
    test_thin_layers();
    test_seams(layers, "thin layers");
    test_seams(steps, "a stepped layer");
    test_native();
    test_nothing();
    test_nodata();
    test_steps();
    return vsv_test_done();
}
