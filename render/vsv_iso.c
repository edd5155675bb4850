/* vsv_iso.c — isosurfaces extracted brick by brick (vsv_render.h's
 * vsv_iso_*): marching tetrahedra over the cells' centres, each cube of
 * eight centres cut into the six tetrahedra around its main diagonal, so no
 * case is ambiguous and neighbouring cubes and bricks cut their shared
 * faces alike (no cracks); a brick's triangles are kept and reused while
 * the values it reads stay the same (the volumes' brick keys). */
#include "vsv_geo.h"
#include "vsv_pool.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

/* The six tetrahedra of a cube around the diagonal from corner 0 to corner
 * 7 (corner bits: 1 x, 2 y, 4 z): the paths 0 -> +a -> +a+b -> 7 over the
 * orders of the axes (Freudenthal's). Every edge goes from a corner to one
 * whose bits hold its own, so an edge is its lower corner plus a direction
 * 1..7, the key the vertices are shared by. */
static const unsigned char tets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                                         {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

/* One brick's triangles, kept across steps. */
typedef struct iso_brick {
    uint64_t key;  /* of the values it read (0: none known) */
    int done;      /* extracted for the current surface */
    float *pos;    /* nv * 3 world metres */
    float *nrm;    /* nv * 3 unit normals */
    uint32_t *tri; /* nt * 3 indices into pos */
    int nv, nt, vcap, tcap;
} iso_brick;

/* Per-thread scratch, made once for a brick size. */
typedef struct iso_scratch {
    float *val;      /* (B + 3)^3 samples: the brick's points and one more each way */
    uint32_t *stamp; /* (B + 1)^3 * 7 edges: which brick visit set the slot */
    uint32_t *slot;  /* vertex index of the edge's crossing */
    double *fsum;    /* per vertex of the brick: its triangles' normals summed (agree_with_faces) */
    int fcap;
    uint32_t visit;
    int err;
} iso_scratch;

struct vsv_iso {
    vsv_pool pool, *run; /* its own pool, or the renderer's it runs on */
    int nthreads;
    iso_scratch scr[VSV_POOL_MAX];
    int brick; /* scratch made for this brick size (0: none) */
    iso_brick *b;
    int nb;
    /* the surface the kept bricks belong to */
    float value;
    const float *heights;
    uint64_t gen;
    int nx, ny, nz;
    double geo[6]; /* ox, oy, oz, dx, dy, dz */
    /* the current extraction */
    const vsv_volume *v;
    int *todo, ntodo;
    vsv_iso_info info;
};

static void free_scratch(vsv_iso *s);

int vsv_iso_create(int threads, vsv_iso **out)
{
    vsv_iso *s = *out = calloc(1, sizeof *s);
    if (!s)
        return VSV_ENOMEM;
    vsv_pool_start(&s->pool, threads > 0 ? threads : vsv_ncpus());
    s->run = &s->pool;
    s->nthreads = s->pool.nthreads;
    return 0;
}

void vsv_iso_use_pool(vsv_iso *s, vsv_pool *pool)
{
    free_scratch(s); /* made again for the pool's threads */
    s->run = pool;
    s->nthreads = pool->nthreads;
}

static void free_bricks(vsv_iso *s)
{
    for (int b = 0; b < s->nb; b++) {
        free(s->b[b].pos);
        free(s->b[b].nrm);
        free(s->b[b].tri);
    }
    free(s->b);
    free(s->todo);
    s->b = NULL;
    s->todo = NULL;
    s->nb = 0;
}

static void free_scratch(vsv_iso *s)
{
    for (int t = 0; t < VSV_POOL_MAX; t++) {
        free(s->scr[t].val);
        free(s->scr[t].stamp);
        free(s->scr[t].slot);
        free(s->scr[t].fsum);
        memset(&s->scr[t], 0, sizeof s->scr[t]);
    }
    s->brick = 0;
}

void vsv_iso_free(vsv_iso *s)
{
    if (!s)
        return;
    vsv_pool_stop(&s->pool);
    free_bricks(s);
    free_scratch(s);
    free(s);
}

/* ---------------------------------------------------------------- a brick */

/* What one brick's extraction reads: the grid's geometry and where its
 * sample block starts. */
typedef struct iso_job {
    const vsv_iso *s;
    const vsv_volume *v;
    float value;
    int i0, j0, k0;   /* the brick's first point */
    int n[3];         /* its points per axis (one past its cubes) */
    int e[3];         /* the sample block: n + 2 per axis */
    const float *hts; /* per-column heights, or NULL: oz + k dz */
    iso_scratch *scr;
    iso_brick *out;
} iso_job;

static inline int clampi(int x, int lo, int hi) { return x < lo ? lo : x > hi ? hi : x; }

/* World position of grid point (i, j, k) (inside the grid). */
static inline void point_pos(const iso_job *J, int i, int j, int k, double p[3])
{
    const double *g = J->s->geo;
    p[0] = g[0] + i * g[3];
    p[1] = g[1] + j * g[4];
    p[2] = J->hts ? J->hts[((size_t)k * J->v->ny + j) * J->v->nx + i] : g[2] + k * g[5];
}

/* Sample of the block at local point (a, b, c), each -1 .. n. */
static inline float sample(const iso_job *J, int a, int b, int c)
{
    return J->scr->val[(a + 1) + J->e[0] * ((b + 1) + J->e[1] * (c + 1))];
}

/* The field's gradient at local point (a, b, c) in world units, by central
 * differences between the neighbours in the grid's cell directions (one
 * side at the grid's edges, where the block repeats the last point, and
 * beside cells without data). */
static void gradient(const iso_job *J, int a, int b, int c, double g[3])
{
    const int d[3] = {a, b, c}, gi[3] = {J->i0 + a, J->j0 + b, J->k0 + c};
    const int nmax[3] = {J->v->nx - 1, J->v->ny - 1, J->v->nz - 1};
    for (int ax = 0; ax < 3; ax++) {
        int lo[3] = {d[0], d[1], d[2]}, hi[3] = {d[0], d[1], d[2]};
        const int glo = clampi(gi[ax] - 1, 0, nmax[ax]), ghi = clampi(gi[ax] + 1, 0, nmax[ax]);
        lo[ax] += glo - gi[ax];
        hi[ax] += ghi - gi[ax];
        /* a neighbour without data (NaN): one side only, from this point */
        if (isnan(sample(J, hi[0], hi[1], hi[2])))
            hi[ax] = d[ax];
        if (isnan(sample(J, lo[0], lo[1], lo[2])))
            lo[ax] = d[ax];
        if (lo[ax] == hi[ax]) {
            g[ax] = 0;
            continue;
        }
        double p0[3], p1[3];
        point_pos(J, J->i0 + lo[0], J->j0 + lo[1], J->k0 + lo[2], p0);
        point_pos(J, J->i0 + hi[0], J->j0 + hi[1], J->k0 + hi[2], p1);
        const double span = p1[ax] - p0[ax];
        g[ax] = span != 0 ? (sample(J, hi[0], hi[1], hi[2]) - sample(J, lo[0], lo[1], lo[2])) / span : 0;
    }
}

/* Appends a vertex to the brick's mesh, growing it (amortised: the arrays
 * are kept across steps). Its index, or UINT32_MAX when out of memory. */
static uint32_t add_vertex(iso_brick *o, const double p[3], const double n[3])
{
    if (o->nv == o->vcap) {
        const int cap = o->vcap ? 2 * o->vcap : 256;
        float *np = realloc(o->pos, (size_t)cap * 3 * sizeof *np);
        if (np)
            o->pos = np;
        float *nn = np ? realloc(o->nrm, (size_t)cap * 3 * sizeof *nn) : NULL;
        if (!nn)
            return UINT32_MAX;
        o->nrm = nn;
        o->vcap = cap;
    }
    for (int a = 0; a < 3; a++) {
        o->pos[3 * o->nv + a] = (float)p[a];
        o->nrm[3 * o->nv + a] = (float)n[a];
    }
    return (uint32_t)o->nv++;
}

/* Where the surface crosses the edge from local point (a, b, c) in
 * direction dir (corner bits): p, between the edge's ends p0 and p1, at
 * the fraction returned. */
static double edge_cut(const iso_job *J, int a, int b, int c, int dir, double p0[3], double p1[3], double p[3])
{
    const int a1 = a + (dir & 1), b1 = b + (dir >> 1 & 1), c1 = c + (dir >> 2 & 1);
    const double f0 = sample(J, a, b, c), f1 = sample(J, a1, b1, c1);
    const double t = (J->value - f0) / (f1 - f0);
    point_pos(J, J->i0 + a, J->j0 + b, J->k0 + c, p0);
    point_pos(J, J->i0 + a1, J->j0 + b1, J->k0 + c1, p1);
    for (int x = 0; x < 3; x++)
        p[x] = p0[x] + t * (p1[x] - p0[x]);
    return t;
}

/* The slot of the edge from local point (a, b, c) in direction dir among
 * the brick's edges (both ends among its points), or -1 when it is not
 * one of them. */
static ptrdiff_t edge_key(const iso_job *J, int a, int b, int c, int dir)
{
    const int a1 = a + (dir & 1), b1 = b + (dir >> 1 & 1), c1 = c + (dir >> 2 & 1);
    if (a < 0 || b < 0 || c < 0 || a1 >= J->n[0] || b1 >= J->n[1] || c1 >= J->n[2])
        return -1;
    return (ptrdiff_t)(((size_t)a + (size_t)(J->n[0]) * ((size_t)b + (size_t)J->n[1] * c)) * 7 + (size_t)(dir - 1));
}

/* The vertex where the surface crosses the edge from local point (a, b, c)
 * in direction dir (corner bits), made once per brick: the same two
 * samples in the same order give the same position and normal in every
 * brick that has the edge, so bricks meet without cracks. */
static uint32_t edge_vertex(iso_job *J, int a, int b, int c, int dir)
{
    iso_scratch *S = J->scr;
    const size_t key = (size_t)edge_key(J, a, b, c, dir);
    if (S->stamp[key] == S->visit)
        return S->slot[key];
    const int a1 = a + (dir & 1), b1 = b + (dir >> 1 & 1), c1 = c + (dir >> 2 & 1);
    double p0[3], p1[3], g0[3], g1[3], p[3], n[3];
    const double t = edge_cut(J, a, b, c, dir, p0, p1, p);
    gradient(J, a, b, c, g0);
    gradient(J, a1, b1, c1, g1);
    for (int x = 0; x < 3; x++)
        n[x] = -(g0[x] + t * (g1[x] - g0[x])); /* down the gradient: out of the cloud */
    vsv_normalize(n);
    const double len = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    if (!(len > 0.5)) { /* no gradient to go by: along the edge, toward the point below */
        const double sg = sample(J, a1, b1, c1) > sample(J, a, b, c) ? -1 : 1;
        for (int x = 0; x < 3; x++)
            n[x] = sg * (p1[x] - p0[x]);
        vsv_normalize(n);
    }
    const uint32_t id = add_vertex(J->out, p, n);
    S->stamp[key] = S->visit;
    S->slot[key] = id;
    return id;
}

/* Appends triangle (a, b, c), wound so that its normal (counter-clockwise
 * seen from its front) points toward the values below the surface: away
 * from `in`, a corner of the tetrahedron above it. The triangle lies on the
 * plane where the tetrahedron's linear field equals the value, which parts
 * its corners above from those below, so the test never fails. */
static int add_tri(iso_brick *o, uint32_t a, uint32_t b, uint32_t c, const double in[3])
{
    if (a == UINT32_MAX || b == UINT32_MAX || c == UINT32_MAX)
        return -1;
    const float *P = o->pos;
    double u[3], w[3], q[3];
    for (int x = 0; x < 3; x++) {
        u[x] = (double)P[3 * b + x] - P[3 * a + x];
        w[x] = (double)P[3 * c + x] - P[3 * a + x];
        q[x] = in[x] - P[3 * a + x];
    }
    const double nx = u[1] * w[2] - u[2] * w[1], ny = u[2] * w[0] - u[0] * w[2], nz = u[0] * w[1] - u[1] * w[0];
    if (nx * q[0] + ny * q[1] + nz * q[2] > 0) {
        const uint32_t t = b;
        b = c;
        c = t;
    }
    if (o->nt == o->tcap) {
        const int cap = o->tcap ? 2 * o->tcap : 256;
        uint32_t *nt = realloc(o->tri, (size_t)cap * 3 * sizeof *nt);
        if (!nt)
            return -1;
        o->tri = nt;
        o->tcap = cap;
    }
    o->tri[3 * o->nt] = a, o->tri[3 * o->nt + 1] = b, o->tri[3 * o->nt + 2] = c;
    o->nt++;
    return 0;
}

/* A cube beside the brick's (a neighbour's, lower corner (a, b, c)) cut
 * by one tetrahedron (ncut crossings on the edges ends, walking around;
 * `in` a corner above): its triangles' normals, wound as add_tri winds
 * them, added to sum for those of their corners the brick has as vertices
 * (the edges on the faces it shares). */
static void halo_tris(const iso_job *J, int a, int b, int c, const int ends[4][2], int ncut, const double in[3],
                      double *sum)
{
    const iso_scratch *S = J->scr;
    /* as the brick that makes the vertex stores it: floats (GCC 12.2 at -O2
     * was seen to drop (float) rounding stored into a double array) */
    float P[4][3];
    uint32_t id[4];
    int any = 0;
    for (int q = 0; q < ncut; q++) {
        const int lo = ends[q][0] & ends[q][1], dir = (ends[q][0] | ends[q][1]) ^ lo;
        const int la = a + (lo & 1), lb = b + (lo >> 1 & 1), lc = c + (lo >> 2 & 1);
        double p0[3], p1[3], p[3];
        edge_cut(J, la, lb, lc, dir, p0, p1, p);
        for (int x = 0; x < 3; x++)
            P[q][x] = (float)p[x];
        const ptrdiff_t key = edge_key(J, la, lb, lc, dir);
        id[q] = key >= 0 && S->stamp[key] == S->visit ? S->slot[key] : UINT32_MAX;
        any |= id[q] != UINT32_MAX;
    }
    for (int t = 0; any && t < ncut - 2; t++) { /* (0, 1, 2), then (0, 2, 3) */
        const int v1 = t + 1, v2 = t + 2;
        double u[3], w[3], q[3];
        for (int x = 0; x < 3; x++)
            u[x] = (double)P[v1][x] - P[0][x], w[x] = (double)P[v2][x] - P[0][x], q[x] = in[x] - P[0][x];
        double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        const double sg = n[0] * q[0] + n[1] * q[1] + n[2] * q[2] > 0 ? -1 : 1;
        for (int k = 0; k < 3; k++) {
            const uint32_t i = id[k ? t + k : 0];
            for (int x = 0; i != UINT32_MAX && x < 3; x++)
                sum[3 * i + x] += sg * n[x];
        }
    }
}

/* Marching tetrahedra over one cube (local lower corner (a, b, c)): per
 * tetrahedron, one corner apart from the others (above or below) cuts one
 * triangle, two and two a quad of two. A corner is above when its value is
 * greater than the surface's; NaN (no data) leaves the cube out. With halo
 * (a cube beside the brick's), no triangle is made: their normals are
 * added to halo (halo_tris). */
static inline __attribute__((always_inline)) int cube(iso_job *J, int a, int b, int c, double *halo)
{
    float f[8];
    int above = 0, nan = 0;
    for (int q = 0; q < 8; q++) {
        f[q] = sample(J, a + (q & 1), b + (q >> 1 & 1), c + (q >> 2 & 1));
        above |= (f[q] > J->value) << q;
        nan |= isnan(f[q]);
    }
    if (nan || above == 0 || above == 255)
        return 0;
    for (int t = 0; t < 6; t++) {
        const unsigned char *T = tets[t];
        int up[4], dn[4], nu = 0, nd = 0;
        for (int q = 0; q < 4; q++) {
            if (above >> T[q] & 1)
                up[nu++] = T[q];
            else
                dn[nd++] = T[q];
        }
        if (!nu || !nd)
            continue;
        /* the crossings: a lone corner's three edges, or for two and two
         * the four edges in the order that walks around the quad */
        int ends[4][2], ncut;
        if (nu == 1 || nd == 1) {
            const int *one = nu == 1 ? up : dn, *rest = nu == 1 ? dn : up;
            for (int q = 0; q < 3; q++)
                ends[q][0] = one[0], ends[q][1] = rest[q];
            ncut = 3;
        } else {
            const int w[4][2] = {{up[0], dn[0]}, {up[0], dn[1]}, {up[1], dn[1]}, {up[1], dn[0]}};
            memcpy(ends, w, sizeof w);
            ncut = 4;
        }
        double in[3];
        const int u0 = up[0];
        point_pos(J, J->i0 + a + (u0 & 1), J->j0 + b + (u0 >> 1 & 1), J->k0 + c + (u0 >> 2 & 1), in);
        if (halo) {
            halo_tris(J, a, b, c, (const int(*)[2])ends, ncut, in, halo);
            continue;
        }
        uint32_t e[4];
        for (int q = 0; q < ncut; q++) {
            const int lo = ends[q][0] & ends[q][1], hi = ends[q][0] | ends[q][1];
            e[q] = edge_vertex(J, a + (lo & 1), b + (lo >> 1 & 1), c + (lo >> 2 & 1), hi ^ lo);
        }
        if (add_tri(J->out, e[0], e[1], e[2], in) || (ncut == 4 && add_tri(J->out, e[0], e[2], e[3], in)))
            return -1;
    }
    return 0;
}

/* Fills the sample block of brick b: its points and one more each way,
 * clamped into the grid (the gradient's neighbours at its edges). */
static void fill_block(iso_job *J)
{
    const vsv_volume *v = J->v;
    float *dst = J->scr->val;
    for (int c = -1; c <= J->n[2]; c++)
        for (int b = -1; b <= J->n[1]; b++) {
            const int gk = clampi(J->k0 + c, 0, v->nz - 1), gj = clampi(J->j0 + b, 0, v->ny - 1);
            for (int a = -1; a <= J->n[0]; a++)
                *dst++ = vsv_volume_at(v, clampi(J->i0 + a, 0, v->nx - 1), gj, gk);
        }
}

/* Each vertex normal of the brick made to face as its triangles do: where
 * the gradient's points against the sum of its triangles' (area-weighted)
 * normals, that sum instead. Central differences reach a point beyond the
 * edge's two, so across a layer one or two cells thick (most clouds on a
 * model's levels) the gradient can point into the cloud: the triangles,
 * wound from the edge's own samples, never do. A vertex on a face the brick
 * shares with another has triangles in both: the cubes beside the brick
 * (the neighbours' along the faces it shares, whose points its sample
 * block holds) add theirs, so both bricks give it one normal. 0, or -1 out
 * of memory. */
static int agree_with_faces(iso_job *J)
{
    iso_scratch *S = J->scr;
    iso_brick *o = J->out;
    if (o->nv > S->fcap) { /* grown by doubling, kept across bricks and steps */
        const int want = o->nv > 2 * S->fcap ? o->nv : 2 * S->fcap;
        double *f = realloc(S->fsum, (size_t)want * 3 * sizeof *f);
        if (!f)
            return -1;
        S->fsum = f, S->fcap = want;
    }
    double *const sum = S->fsum;
    const float *const P = o->pos;
    float *const N = o->nrm;
    memset(sum, 0, (size_t)o->nv * 3 * sizeof *sum);
    for (int t = 0; t < o->nt; t++) {
        const uint32_t *v = o->tri + 3 * t;
        double u[3], w[3];
        for (int x = 0; x < 3; x++)
            u[x] = (double)P[3 * v[1] + x] - P[3 * v[0] + x], w[x] = (double)P[3 * v[2] + x] - P[3 * v[0] + x];
        const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        for (int c = 0; c < 3; c++)
            for (int x = 0; x < 3; x++)
                sum[3 * v[c] + x] += n[x];
    }
    /* the cubes beside: one layer out on each side where the grid goes on */
    const int g0[3] = {J->i0, J->j0, J->k0}, gn[3] = {J->v->nx, J->v->ny, J->v->nz};
    int lo[3], hi[3];
    for (int x = 0; x < 3; x++) {
        lo[x] = g0[x] > 0 ? -1 : 0;
        hi[x] = g0[x] + J->n[x] < gn[x] ? J->n[x] - 1 : J->n[x] - 2;
    }
    for (int c = lo[2]; o->nv && c <= hi[2]; c++)
        for (int b = lo[1]; b <= hi[1]; b++)
            for (int a = lo[0]; a <= hi[0]; a++)
                if (a < 0 || b < 0 || c < 0 || a > J->n[0] - 2 || b > J->n[1] - 2 || c > J->n[2] - 2)
                    cube(J, a, b, c, sum);
    for (int i = 0; i < o->nv; i++) {
        float *const n = N + 3 * i;
        const double *const f = sum + 3 * i;
        if (n[0] * f[0] + n[1] * f[1] + n[2] * f[2] >= 0)
            continue;
        double d[3] = {f[0], f[1], f[2]};
        vsv_normalize(d);
        for (int x = 0; x < 3; x++)
            n[x] = (float)d[x];
    }
    return 0;
}

static void brick_job(void *ctx, int item, int thread)
{
    vsv_iso *s = ctx;
    const vsv_volume *v = s->v;
    const int bi = s->todo[item], B = v->brick, bx = v->bdim[0], by = v->bdim[1];
    iso_job J = {.s = s, .v = v, .value = s->value, .hts = s->heights, .scr = &s->scr[thread], .out = &s->b[bi]};
    J.i0 = bi % bx * B, J.j0 = bi / bx % by * B, J.k0 = bi / (bx * by) * B;
    const int np[3] = {v->nx - J.i0, v->ny - J.j0, v->nz - J.k0};
    for (int a = 0; a < 3; a++) {
        J.n[a] = np[a] < B + 1 ? np[a] : B + 1; /* the next brick's first point closes the cubes */
        J.e[a] = J.n[a] + 2;
    }
    J.out->nv = J.out->nt = 0;
    J.out->done = 1;
    if (J.n[0] < 2 || J.n[1] < 2 || J.n[2] < 2) /* the grid's last point: no cube starts here */
        return;
    fill_block(&J);
    if (++J.scr->visit == 0) { /* the stamps wrapped: start them afresh */
        memset(J.scr->stamp, 0, (size_t)(B + 1) * (B + 1) * (B + 1) * 7 * sizeof *J.scr->stamp);
        J.scr->visit = 1;
    }
    for (int c = 0; c + 1 < J.n[2]; c++)
        for (int b = 0; b + 1 < J.n[1]; b++)
            for (int a = 0; a + 1 < J.n[0]; a++)
                if (cube(&J, a, b, c, NULL)) {
                    J.scr->err = 1;
                    J.out->done = 0;
                    return;
                }
    if (agree_with_faces(&J)) {
        J.scr->err = 1;
        J.out->done = 0;
    }
}

/* --------------------------------------------------------------- the driver */

/* The value range of the points brick b's cubes read: its own and those of
 * the bricks after it along each axis (a NULL brick holds the empty value;
 * NaN counts as nothing). */
static void brick_range(const vsv_volume *v, int b, float *lo, float *hi)
{
    const int bx = v->bdim[0], by = v->bdim[1], bz = v->bdim[2];
    const int i = b % bx, j = b / bx % by, k = b / (bx * by);
    *lo = INFINITY, *hi = -INFINITY;
    for (int q = 0; q < 8; q++) {
        const int ii = i + (q & 1), jj = j + (q >> 1 & 1), kk = k + (q >> 2 & 1);
        if (ii >= bx || jj >= by || kk >= bz)
            continue;
        const int n = ii + bx * (jj + by * kk);
        const float mn = v->bricks[n] ? v->bmin[n] : v->empty_value, mx = v->bricks[n] ? v->bmax[n] : v->empty_value;
        *lo = fminf(*lo, mn);
        *hi = fmaxf(*hi, mx);
    }
}

/* The key of every value brick b's triangles depend on: the keys of the 27
 * bricks around it (its cubes read the next brick's first points, their
 * normals one point further each way); 0 when one is not known. */
static uint64_t brick_key(const vsv_volume *v, int b)
{
    if (!v->bkey)
        return 0;
    const int bx = v->bdim[0], by = v->bdim[1], bz = v->bdim[2];
    const int i = b % bx, j = b / bx % by, k = b / (bx * by);
    uint64_t h = 0x9e3779b97f4a7c15u;
    for (int dk = -1; dk <= 1; dk++)
        for (int dj = -1; dj <= 1; dj++)
            for (int di = -1; di <= 1; di++) {
                const int ii = i + di, jj = j + dj, kk = k + dk;
                uint64_t key = 1; /* past the grid */
                if (ii >= 0 && jj >= 0 && kk >= 0 && ii < bx && jj < by && kk < bz) {
                    key = v->bkey[ii + bx * (jj + by * kk)];
                    if (!key)
                        return 0;
                }
                h ^= key + 0x9e3779b97f4a7c15u + (h << 6) + (h >> 2);
            }
    return h ? h : 1;
}

/* Makes the per-thread scratch for bricks of B and the kept bricks for
 * nb of them, forgetting what was kept when the grid changed. */
static int prepare(vsv_iso *s, const vsv_volume *v)
{
    const int B = v->brick;
    if (s->brick != B) {
        free_scratch(s);
        const size_t pts = (size_t)(B + 3) * (B + 3) * (B + 3), edges = (size_t)(B + 1) * (B + 1) * (B + 1) * 7;
        for (int t = 0; t < s->nthreads; t++) {
            iso_scratch *S = &s->scr[t];
            S->val = malloc(pts * sizeof *S->val);
            S->stamp = calloc(edges, sizeof *S->stamp);
            S->slot = malloc(edges * sizeof *S->slot);
            if (!S->val || !S->stamp || !S->slot) {
                free_scratch(s);
                return VSV_ENOMEM;
            }
        }
        s->brick = B;
    }
    if (s->nb != v->nbricks) {
        free_bricks(s);
        s->b = calloc((size_t)v->nbricks, sizeof *s->b);
        s->todo = malloc((size_t)v->nbricks * sizeof *s->todo);
        if (!s->b || !s->todo) {
            free_bricks(s);
            return VSV_ENOMEM;
        }
        s->nb = v->nbricks;
    }
    return 0;
}

int vsv_iso_extract(vsv_iso *s, const vsv_meta *m, const vsv_volume *v, float value)
{
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    if (!m || !v || v->nx != m->nx || v->ny != m->ny || v->nz != m->nz || !isfinite(value) || v->brick < 1 ||
        (v->brick & (v->brick - 1)))
        return VSV_EINVAL;
    int rc = prepare(s, v);
    if (rc)
        return rc;
    /* where the points are: the renderers' world metres (vsv_scene_geo), z
     * unexaggerated, per-column heights where the file has them */
    const vsv_scene sc = {.meta = m, .exaggeration = 1};
    vsv_geo g;
    vsv_scene_geo(&sc, &g);
    const double geo[6] = {g.ox, g.oy, g.oz, g.dx, g.dy, g.dz};
    const float *hts = m->vert_kind == VSV_VERT_NATIVE ? vsv_meta_heights_at(m, v->time) : NULL;
    /* the kept triangles stand for another surface: none is reused */
    const int same = s->value == value && s->heights == hts && !memcmp(s->geo, geo, sizeof geo) && s->nx == v->nx &&
                     s->ny == v->ny && s->nz == v->nz;
    const int same_vol = same && s->gen == v->gen && v->gen;
    s->value = value, s->heights = hts, s->gen = v->gen, s->nx = v->nx, s->ny = v->ny, s->nz = v->nz;
    memcpy(s->geo, geo, sizeof geo);
    memset(&s->info, 0, sizeof s->info);
    s->info.nbricks = v->nbricks;
    s->ntodo = 0;
    for (int b = 0; b < v->nbricks; b++) {
        iso_brick *o = &s->b[b];
        float lo, hi;
        brick_range(v, b, &lo, &hi);
        if (!(lo <= value && hi > value)) { /* every point on one side: no surface */
            o->nv = o->nt = 0, o->key = 0, o->done = 1;
            continue;
        }
        s->info.visited++;
        const uint64_t key = brick_key(v, b);
        if (o->done && ((same && key && key == o->key) || same_vol)) {
            s->info.reused++;
            continue;
        }
        o->key = key;
        o->done = 0;
        s->todo[s->ntodo++] = b;
    }
    s->v = v;
    for (int t = 0; t < s->nthreads; t++)
        s->scr[t].err = 0;
    if (s->ntodo)
        vsv_pool_run(s->run, brick_job, s, s->ntodo);
    s->v = NULL;
    for (int t = 0; t < s->nthreads; t++)
        if (s->scr[t].err)
            return VSV_ENOMEM;
    for (int b = 0; b < v->nbricks; b++) {
        s->info.nverts += s->b[b].nv;
        s->info.ntris += s->b[b].nt;
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    s->info.seconds = (t1.tv_sec - t0.tv_sec) + (t1.tv_nsec - t0.tv_nsec) * 1e-9;
    return 0;
}

void vsv_iso_get_info(const vsv_iso *s, vsv_iso_info *info) { *info = s->info; }

int vsv_iso_brick(const vsv_iso *s, int b, vsv_iso_mesh *mesh)
{
    memset(mesh, 0, sizeof *mesh);
    if (b < 0 || b >= s->nb)
        return VSV_ERANGE;
    const iso_brick *o = &s->b[b];
    mesh->pos = o->pos, mesh->nrm = o->nrm, mesh->tri = o->tri;
    mesh->nverts = o->nv, mesh->ntris = o->nt;
    return 0;
}
