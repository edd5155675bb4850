/* test_vdb.c — OpenVDB out and in through the shim, on the real MM5
 * sample: every exported value equals the decoded .vsv value, the active
 * voxels are exactly the non-empty cells, the sequence reads back as the
 * same grid, and .vsv -> .vdb -> .vsv keeps every value within the bound. */
#include "vsv_testlib.h"
#include "vsv_vdb.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* What the checks share: the .vsv, its decoder, the exported sequence as scanned, and where the
 * .vsv's cell (0, 0, 0) lies in the sequence's box. */
typedef struct {
    vsv_file *f;
    const vsv_meta *m;
    vsv_decoder *d;
    int ns, nt;
    size_t cells;
    const char **pp;
    vsv_vdb_info vi;
    long oi, oj, ok_;
    float *ref;
    char err[1024];
} vdb_case;

/* Exports every step of the .vsv to its own .vdb (paths in pp); 1 if all were written. */
static int export_steps(vdb_case *c, vsv_volume **vols, char (*paths)[512])
{
    int ok = 1;
    for (int t = 0; t < c->nt && ok; t++) {
        for (int s = 0; s < c->ns; s++) {
            if (!vols[s])
                vsv_volume_create(c->f, &vols[s]);
            vsv_volume_load(vols[s], c->d, t, s);
        }
        char name[64];
        snprintf(name, sizeof name, "vdb-%04d.vdb", t);
        snprintf(paths[t], sizeof paths[t], "%s", vsv_test_tmp(name));
        c->pp[t] = paths[t];
        ok = !vsv_vdb_write(paths[t], c->m, vsv_file_time(c->f, t), (const vsv_volume *const *)vols, c->ns, c->err,
                            sizeof c->err);
    }
    return ok;
}

/* A grid with cells 1 x 2 and moved north exports each axis's own voxel size and origin. */
static void check_anisotropic(vdb_case *c, vsv_volume **vols)
{
    const vsv_meta *m = c->m;
    /* cells twice as long north-south as east-west, the grid moved 7 km
     * north: the transform keeps each axis's own cell size and origin
     * (cell (i, j, k) at origin + (i dx, j dy, k dz)) */
    vsv_meta m2;
    vsv_meta_init(&m2);
    vsv_vdb_info v2;
    memset(&v2, 0, sizeof v2);
    const char *aniso = vsv_test_tmp("vdb-aniso.vdb");
    int aok = !vsv_meta_copy(&m2, m);
    m2.spacing[1] = 2 * m->spacing[0], m2.origin[1] = m->origin[1] + 7000;
    aok = aok &&
          !vsv_vdb_write(aniso, &m2, vsv_file_time(c->f, c->nt - 1), (const vsv_volume *const *)vols, c->ns, c->err,
                         sizeof c->err) &&
          !vsv_vdb_scan(&aniso, 1, &v2, c->err, sizeof c->err);
    double werr = 0;
    for (int a = 0; aok && a < 3; a++) {
        const double cell = (v2.origin[a] - m2.origin[a]) / m2.spacing[a];
        werr = fmax(werr, fabs(v2.voxel[a] - m2.spacing[a]) + fabs(cell - round(cell)));
    }
    CHECK(aok && werr < 1e-6, "a grid of 1 x 2 cells: voxel size per axis and origin on the grid's own lattice",
          "(%s) voxel %g %g %g, origin y %g (grid's %g)", c->err, v2.voxel[0], v2.voxel[1], v2.voxel[2], v2.origin[1],
          m2.origin[1]);
    if (aok)
        vsv_vdb_info_free(&v2);
    vsv_meta_clear(&m2);
}

/* Every value read back through the shim equals the decoded .vsv; empty and no-data cells are inactive. */
static void check_values(vdb_case *c)
{
    const vsv_meta *m = c->m;
    const vsv_vdb_info *vi = &c->vi;
    const long oi = c->oi, oj = c->oj, ok_ = c->ok_;
    float *ref = c->ref, *got = malloc((size_t)vi->nx * vi->ny * vi->nz * sizeof(float));
    size_t mism = 0, outside = 0;
    for (int t = 0; t < c->nt; t++)
        for (int s = 0; s < c->ns; s++) {
            vsv_decoder_volume(c->d, t, s, ref);
            if (vsv_vdb_read(c->pp[t], m->vars[s].name, &c->vi, got, c->err, sizeof c->err)) {
                mism++;
                continue;
            }
            const float empty = vsv_quant_value(vsv_file_quant(c->f, s), 0);
            for (int k = 0; k < m->nz; k++)
                for (int j = 0; j < m->ny; j++)
                    for (int i = 0; i < m->nx; i++) {
                        const float r = ref[((size_t)k * m->ny + j) * m->nx + i];
                        const long a = i - oi, bj = j - oj, cz = k - ok_;
                        const int in = a >= 0 && bj >= 0 && cz >= 0 && a < vi->nx && bj < vi->ny && cz < vi->nz;
                        const int held = r == r && r != empty;
                        if (!in) {
                            outside += held;
                            continue;
                        }
                        const float g = got[((size_t)cz * vi->ny + bj) * vi->nx + a];
                        if (held ? g != r : g != 0)
                            mism++;
                    }
        }
    CHECK(mism == 0 && outside == 0,
          "read back through the shim, every cell equals the decoded .vsv (empty and no-data cells inactive: 0)",
          "(%zu differ, %zu outside the box) %s", mism, outside, c->err);
    free(got);
}

/* vdb_print's voxel count equals the non-empty cells */
static void check_vdb_print(vdb_case *c)
{
    const vsv_meta *m = c->m;
    float *ref = c->ref;
    char cmd[4096];
    long want = 0;
    vsv_decoder_volume(c->d, c->nt - 1, 0, ref);
    for (size_t c2 = 0; c2 < c->cells; c2++)
        want += ref[c2] == ref[c2] && ref[c2] != vsv_quant_value(vsv_file_quant(c->f, 0), 0);
    snprintf(cmd, sizeof cmd, "vdb_print -l %s 2>&1", c->pp[c->nt - 1]);
    FILE *p = popen(cmd, "r");
    char line[512], grid[64] = "";
    long count = -1;
    while (p && fgets(line, sizeof line, p)) {
        if (!strncmp(line, "Name: ", 6))
            sscanf(line + 6, "%63s", grid);
        if (!strcmp(grid, m->vars[0].name) && strstr(line, "Number of active voxels:")) {
            count = 0; /* printed with thousands separators */
            for (const char *q = strchr(line, ':') + 1; *q; q++)
                if (*q >= '0' && *q <= '9')
                    count = count * 10 + (*q - '0');
        }
    }
    if (p)
        pclose(p);
    CHECK(count == want, "vdb_print counts the species' non-empty cells as active voxels", "(%s: %ld, want %ld)",
          m->vars[0].name, count, want);
}

/* The repacked .vsv's values against the original's, within the two quantisation bounds. */
static void check_repacked_values(vdb_case *c, vsv_file *g)
{
    const vsv_meta *m = c->m, *gm = vsv_file_meta(g);
    const long oi = c->oi, oj = c->oj, ok_ = c->ok_;
    float *ref = c->ref;
    vsv_decoder *gd = NULL;
    vsv_decoder_create(g, &gd);
    float *back = malloc((size_t)gm->nx * gm->ny * gm->nz * sizeof(float));
    double worst = 0;
    int bad = 0;
    for (int t = 0; t < c->nt; t++)
        for (int s = 0; s < c->ns; s++) {
            const int gs = vsv_meta_find_var(gm, m->vars[s].name);
            vsv_decoder_volume(c->d, t, s, ref);
            vsv_decoder_volume(gd, t, gs, back);
            const double bound = vsv_file_quant(c->f, s)->max_abs_error + vsv_file_quant(g, gs)->max_abs_error;
            for (int k = 0; k < gm->nz; k++)
                for (int j = 0; j < gm->ny; j++)
                    for (int i = 0; i < gm->nx; i++) {
                        const float r = ref[((size_t)(k + ok_) * m->ny + (j + oj)) * m->nx + (i + oi)];
                        const float v = back[((size_t)k * gm->ny + j) * gm->nx + i];
                        if (r != r)
                            continue; /* no data: not exported */
                        const double e = fabs((double)v - r);
                        worst = e / bound > worst ? e / bound : worst;
                        bad += e > bound;
                    }
        }
    CHECK(!bad, ".vsv -> .vdb -> .vsv: every value within the two quantisation bounds",
          "(%d outside, worst %.2f of the bound)", bad, worst);
    free(back);
    vsv_decoder_free(gd);
}

/* .vsv -> .vdb -> .vsv through vsv-extract and vsv-pack */
static void check_round_trip(vdb_case *c, const char *b, const char *rt)
{
    const vsv_meta *m = c->m;
    const int nt = c->nt;
    char cmd[4096];
    size_t n = (size_t)snprintf(cmd, sizeof cmd, "%s/vsv-extract", b);
    for (int t = 0; t < nt; t++)
        n += (size_t)snprintf(cmd + n, sizeof cmd - n, " %s", c->pp[t]);
    snprintf(cmd + n, sizeof cmd - n, " | %s/vsv-pack -q -o %s", b, rt);
    vsv_file *g = NULL;
    if (CHECK(system(cmd) == 0 && !vsv_file_open(rt, &g), "vsv-extract reads the .vdb sequence; vsv-pack packs it",
              " ")) {
        const vsv_meta *gm = vsv_file_meta(g);
        vsv_file_info gi;
        vsv_file_info_get(g, &gi);
        CHECK(gi.nsteps == nt && gm->proj.kind == m->proj.kind &&
                  vsv_file_time(g, nt - 1) == vsv_file_time(c->f, nt - 1),
              "the round trip keeps the steps, their times and the projection", "(%d steps)", gi.nsteps);
        check_repacked_values(c, g);
    }
    vsv_file_free(g);
}

/* a damaged .vdb: a clear error */
static void check_truncated(vdb_case *c)
{
    char *err = c->err;
    size_t size = 0;
    unsigned char *bytes = vsv_test_slurp(c->pp[0], &size);
    const char *cut = vsv_test_tmp("cut.vdb");
    vsv_test_write(cut, bytes, size / 2);
    const char *one[1] = {cut};
    vsv_vdb_info ci;
    const int rc = vsv_vdb_scan(one, 1, &ci, err, sizeof c->err);
    if (rc)
        vsv_vdb_info_free(&ci);
    CHECK(rc == -1 && strstr(err, "cut.vdb") && strstr(err, "OpenVDB"), "a truncated .vdb is a clear error", "(%s)",
          err);
    free(bytes);
}

int main(void)
{
    const char *b = getenv("B") ? getenv("B") : "build";
    const char *src = vsv_test_tmp("vdb-crop.vsv"), *rt = vsv_test_tmp("vdb-rt.vsv");
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "%s/vsv-convert -q --vertical even samples/mm5/MMOUT_DOMAIN1_CROP -o %s", b, src);
    if (!CHECK(system(cmd) == 0, "convert the bundled MM5 sample", " "))
        return vsv_test_done();
    vdb_case c = {0};
    vsv_file_open(src, &c.f);
    c.m = vsv_file_meta(c.f);
    const vsv_meta *m = c.m;
    vsv_file_info info;
    vsv_file_info_get(c.f, &info);
    vsv_decoder_create(c.f, &c.d);
    c.ns = m->nvars, c.nt = info.nsteps;
    const int ns = c.ns, nt = c.nt;
    c.cells = (size_t)m->nx * m->ny * m->nz;
    vsv_volume **vols = calloc((size_t)ns, sizeof *vols);
    char(*paths)[512] = calloc((size_t)nt, sizeof *paths);
    c.pp = calloc((size_t)nt, sizeof *c.pp);
    CHECK(export_steps(&c, vols, paths), "every step exports to a .vdb", "(%s)", c.err);
    vsv_vdb_info *vi = &c.vi;
    if (!CHECK(!vsv_vdb_scan(c.pp, nt, vi, c.err, sizeof c.err), "the sequence scans", "(%s)", c.err))
        return vsv_test_done();
    int named = vi->ngrids == ns;
    for (int s = 0; s < ns && named; s++) {
        int found = 0;
        for (int k = 0; k < vi->ngrids; k++)
            found |= !strcmp(vi->names[k], m->vars[s].name) && !strcmp(vi->units[k], m->vars[s].units);
        named = found;
    }
    CHECK(named, "one float grid per species, named after it, with its units", "(%d grids)", vi->ngrids);
    CHECK(fabs(vi->voxel[0] - m->spacing[0]) < 1e-9 && fabs(vi->voxel[2] - m->spacing[2]) < 1e-9,
          "the voxel size is the cell size in metres", "(%g %g %g)", vi->voxel[0], vi->voxel[1], vi->voxel[2]);
    check_anisotropic(&c, vols);
    int times_ok = 1;
    for (int t = 0; t < nt; t++)
        times_ok &= vi->times[t] == vsv_file_time(c.f, t);
    CHECK(times_ok, "each file carries its model time", " ");
    /* every value, on the world lattice: cell (i, j, k) of the .vsv at index imin + (i, j, k) of the union box */
    c.oi = lround((vi->origin[0] - m->origin[0]) / m->spacing[0]);
    c.oj = lround((vi->origin[1] - m->origin[1]) / m->spacing[1]);
    c.ok_ = lround((vi->origin[2] - m->origin[2]) / m->spacing[2]);
    c.ref = malloc(c.cells * sizeof(float));
    check_values(&c);
    check_vdb_print(&c);
    check_round_trip(&c, b, rt);
    check_truncated(&c);
    vsv_vdb_info_free(vi);
    free(c.ref);
    for (int s = 0; s < ns; s++)
        vsv_volume_free(vols[s]);
    free(vols);
    free(paths);
    free(c.pp);
    vsv_decoder_free(c.d);
    vsv_file_free(c.f);
    return vsv_test_done();
}
