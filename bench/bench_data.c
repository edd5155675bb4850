/* bench_data.c — the benchmarks' data sets read into memory (bench_data.h). */
#include "bench_data.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int bench_data_source(bench_data *d, const char *name, const char *path, const char *const *vars, int nv)
{
    vsv_source *s = NULL;
    d->name = name;
    d->data = NULL;
    vsv_meta_init(&d->meta);
    if (vsv_source_open(path, NULL, &s)) {
        fprintf(stderr, "bench: %s\n", s ? vsv_source_error(s) : path);
        vsv_source_free(s);
        return -1;
    }
    /* the grid and levels only: the terrain, land use, per-column heights of
     * native levels (MM5's derived from the terrain) and a moving nest's
     * placements a .vsv also carries are left out, so both sides hold the
     * species alone, on the model's levels */
    vsv_meta g = *vsv_source_grid(s);
    g.terrain = g.landuse = NULL;
    g.nheights = g.nmoves = g.nvars = 0;
    g.heights = NULL;
    g.moves = NULL;
    g.vars = NULL;
    g.tf = NULL;
    if (vsv_meta_copy(&d->meta, &g)) {
        fprintf(stderr, "bench: %s: out of memory\n", path);
        vsv_source_free(s);
        return -1;
    }
    int idx[64], n = 0;
    for (int i = 0; i < vsv_source_nfields(s) && n < 64; i++) {
        const vsv_field_info *f = vsv_source_field(s, i);
        int want = !vars && f->is_volume && f->is_default;
        for (int v = 0; vars && v < nv; v++)
            want |= f->is_volume && !strcmp(f->name, vars[v]);
        if (want)
            idx[n++] = i;
    }
    d->nt = vsv_source_ntimes(s);
    d->nv = n;
    int rc = n && (!vars || n == nv) ? 0 : -1;
    if (rc)
        fprintf(stderr, "bench: %s: not every field asked for is there\n", path);
    else if (!(d->data = malloc((size_t)d->nt * n * bench_cells(d) * sizeof(float))))
        rc = -1;
    for (int v = 0; v < n && !rc; v++) {
        const vsv_field_info *f = vsv_source_field(s, idx[v]);
        vsv_meta_add_var(&d->meta, f->name, f->units, f->description);
        for (int t = 0; t < d->nt && !rc; t++)
            if ((rc = vsv_source_read(s, idx[v], t, bench_field(d, t, v))))
                fprintf(stderr, "bench: %s: %s\n", path, vsv_source_error(s));
    }
    vsv_source_free(s);
    return rc;
}

int bench_data_plume(bench_data *d, const char *name, const char *dir, const char *const *names, int nt)
{
    d->name = name;
    vsv_meta_init(&d->meta);
    d->meta.nx = 256, d->meta.ny = 256, d->meta.nz = 64;
    d->meta.spacing[0] = d->meta.spacing[1] = d->meta.spacing[2] = 1000;
    vsv_meta_add_var(&d->meta, "plume", "1", "gen-plume");
    d->nt = nt, d->nv = 1;
    if (!(d->data = malloc((size_t)nt * bench_cells(d) * sizeof(float))))
        return -1;
    for (int t = 0; t < nt; t++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", dir, names[t]);
        FILE *fp = fopen(path, "rb");
        const size_t got = fp ? fread(bench_field(d, t, 0), 4, bench_cells(d), fp) : 0;
        if (fp)
            fclose(fp);
        if (got != bench_cells(d)) {
            fprintf(stderr, "bench: %s: cannot read %zu floats\n", path, bench_cells(d));
            return -1;
        }
    }
    return 0;
}

int bench_data_write(const bench_data *d, int v0, int v1, int predict, const char *path)
{
    vsv_meta m;
    vsv_meta_init(&m);
    int rc = vsv_meta_copy(&m, &d->meta);
    m.nvars = 0; /* the grid's copy, with the species asked for */
    for (int v = v0; v < v1 && !rc; v++)
        rc = vsv_meta_add_var(&m, d->meta.vars[v].name, d->meta.vars[v].units, d->meta.vars[v].description) < 0;
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.predict = predict;
    vsv_writer *w = NULL;
    const float **f = calloc((size_t)(v1 - v0) + 1, sizeof *f);
    if (!rc && f)
        rc = vsv_writer_create(path, &m, &o, &w);
    for (int t = 0; t < d->nt && !rc; t++) {
        for (int v = v0; v < v1; v++)
            f[v - v0] = bench_field(d, t, v);
        rc = vsv_writer_add_step(w, 3600 * (int64_t)t, f);
    }
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    if (rc || !f)
        fprintf(stderr, "bench: %s: %s\n", path, w ? vsv_writer_error(w) : "cannot create");
    vsv_writer_free(w);
    vsv_meta_clear(&m);
    free(f);
    return rc || !f;
}

void bench_data_free(bench_data *d)
{
    vsv_meta_clear(&d->meta);
    free(d->data);
    d->data = NULL;
}
