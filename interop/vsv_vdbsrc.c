/* vsv_vdbsrc.c — OpenVDB files as a source: each .vdb is one time step of
 * a sequence; the grid is the union of the sequence's active bounding boxes
 * and of the whole grids vsv-export recorded (interop/vsv_vdb.h), every float grid a field. Times come from
 * --time-step/--time-start, else from each file's "time" metadata (what
 * vsv-export writes). */
#include "vsv_source_reader.h"
#include "vsv_vdb.h"

#include <stdio.h>

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

/* The sequence's scan, shared by the sources of its files (one per file). */
static struct {
    pthread_mutex_t mu;
    const char *const *seq;
    int nseq;
    vsv_vdb_info info;
    int users;
} cache = {PTHREAD_MUTEX_INITIALIZER, NULL, 0, {0}, 0};

typedef struct vdbsrc {
    vsv_vdb_info info; /* a private scan, or unused when shared */
    int shared;        /* the cache's scan is used (and counted) */
} vdbsrc;

static int probe(const unsigned char *head, size_t n) { return vsv_vdb_probe(head, n); }

static void parse_projection(const char *text, vsv_proj *p)
{
    char name[32];
    double lat0, lon0, lat1, lat2, radius;
    if (sscanf(text, "%31s lat0=%lf lon0=%lf lat1=%lf lat2=%lf radius=%lf", name, &lat0, &lon0, &lat1, &lat2,
               &radius) != 6)
        return;
    for (int k = 0; k < VSV_PROJ_COUNT; k++)
        if (!strcmp(name, vsv_proj_name(k))) {
            *p = (vsv_proj){k, lat0, lon0, lat1, lat2, radius};
            return;
        }
}

static int open_vdb(vsv_source *s)
{
    const char *const lone[1] = {s->path};
    const char *const *seq = s->opts.seq && s->opts.nseq > 0 ? s->opts.seq : lone;
    const int nseq = s->opts.seq && s->opts.nseq > 0 ? s->opts.nseq : 1, idx = s->opts.seq ? s->opts.seq_index : 0;
    char err[512];
    vdbsrc *v = calloc(1, sizeof *v);
    if (!v)
        return VSV_ENOMEM;
    s->priv = v;
    pthread_mutex_lock(&cache.mu);
    if (cache.seq != seq || cache.nseq != nseq) {
        if (cache.users == 0 && cache.seq)
            vsv_vdb_info_free(&cache.info);
        else if (cache.seq) { /* another sequence still in use: scan privately */
            pthread_mutex_unlock(&cache.mu);
            if (vsv_vdb_scan(seq, nseq, &v->info, err, sizeof err)) {
                snprintf(s->err, sizeof s->err, "%s", err);
                return VSV_ECORRUPT;
            }
            goto have;
        }
        cache.seq = NULL;
        if (vsv_vdb_scan(seq, nseq, &cache.info, err, sizeof err)) {
            pthread_mutex_unlock(&cache.mu);
            snprintf(s->err, sizeof s->err, "%s", err);
            return VSV_ECORRUPT;
        }
        cache.seq = seq;
        cache.nseq = nseq;
    }
    cache.users++;
    v->shared = 1;
    pthread_mutex_unlock(&cache.mu);
have:;
    const vsv_vdb_info *in = v->shared ? &cache.info : &v->info;
    vsv_meta *g = &s->grid;
    g->nx = in->nx, g->ny = in->ny, g->nz = in->nz;
    for (int a = 0; a < 3; a++) {
        g->origin[a] = in->origin[a];
        g->spacing[a] = in->voxel[a];
    }
    g->vert_kind = VSV_VERT_EVEN;
    snprintf(g->vert_units, sizeof g->vert_units, "m");
    snprintf(g->model, sizeof g->model, "OpenVDB%s%s", in->model[0] ? " from " : "", in->model);
    snprintf(g->run, sizeof g->run, "OpenVDB sequence of %d file%s", nseq, nseq > 1 ? "s" : "");
    parse_projection(in->projection, &g->proj);
    s->nfields = in->ngrids;
    s->fields = calloc((size_t)in->ngrids, sizeof *s->fields);
    s->times = malloc(sizeof *s->times);
    if (!s->fields || !s->times)
        return VSV_ENOMEM;
    for (int i = 0; i < in->ngrids; i++) {
        vsv_field_info *f = &s->fields[i];
        snprintf(f->name, sizeof f->name, "%s", in->names[i]);
        snprintf(f->units, sizeof f->units, "%s", in->units[i][0] ? in->units[i] : "1");
        snprintf(f->description, sizeof f->description, "OpenVDB float grid");
        snprintf(f->ordering, sizeof f->ordering, "XYZ");
        f->nlevels = in->nz;
        f->is_volume = f->is_default = 1;
    }
    s->ntimes = 1;
    if (s->opts.time_step > 0 && in->times[idx] != INT64_MIN) {
        char when[40];
        vsv_time_format(in->times[idx], when, sizeof when);
        return vsv_source_fail(s, VSV_EINVAL,
                               "has its own time %s (\"time\" metadata); --time-step would replace it: drop "
                               "--time-step and --time-start",
                               when);
    }
    if (s->opts.time_step > 0) {
        s->times[0] = s->opts.time_start + (int64_t)idx * s->opts.time_step;
    } else if (in->times[idx] != INT64_MIN) {
        s->times[0] = in->times[idx];
    } else {
        return vsv_source_fail(
            s, VSV_EINVAL,
            "no \"time\" metadata: give the sequence's spacing and start with --time-step and --time-start");
    }
    return 0;
}

static int read_vdb(vsv_source *s, int field, int t, float *out)
{
    (void)t;
    vdbsrc *v = s->priv;
    const vsv_vdb_info *in = v->shared ? &cache.info : &v->info;
    char err[512];
    if (vsv_vdb_read(s->path, in->names[field], in, out, err, sizeof err)) {
        snprintf(s->err, sizeof s->err, "%s", err);
        return VSV_ECORRUPT;
    }
    return 0;
}

static void close_vdb(vsv_source *s)
{
    vdbsrc *v = s->priv;
    if (!v)
        return;
    if (!v->shared) {
        vsv_vdb_info_free(&v->info);
    } else {
        pthread_mutex_lock(&cache.mu);
        if (--cache.users == 0) {
            vsv_vdb_info_free(&cache.info);
            cache.seq = NULL;
            cache.nseq = 0;
        }
        pthread_mutex_unlock(&cache.mu);
    }
    free(v);
}

static char *summary(vsv_source *s)
{
    vdbsrc *v = s->priv;
    const vsv_vdb_info *in = v->shared ? &cache.info : &v->info;
    const vsv_meta *g = &s->grid;
    char when[64];
    vsv_time_format(s->times[0], when, sizeof when);
    size_t cap = 1024 + (size_t)in->ngrids * 160, n = 0;
    char *t = malloc(cap);
    if (!t)
        return NULL;
    n += (size_t)snprintf(
        t + n, cap - n,
        "OpenVDB%s%s\n  grid        %d x %d x %d voxels (the active bounding box, or the grid written)\n"
        "  origin      %g, %g, %g (centre of the first voxel)\n  voxel       %g x %g x %g\n"
        "  projection  %s\n  time        %s\n  grids       %d float\n",
        in->model[0] ? " from " : "", in->model, g->nx, g->ny, g->nz, g->origin[0], g->origin[1], g->origin[2],
        g->spacing[0], g->spacing[1], g->spacing[2], vsv_proj_name(g->proj.kind), when, in->ngrids);
    for (int i = 0; i < in->ngrids && n < cap; i++)
        n += (size_t)snprintf(t + n, cap - n, "    %-12s %s\n", in->names[i], in->units[i][0] ? in->units[i] : "-");
    return t;
}

static const vsv_source_ops vdb_ops = {"OpenVDB", probe, open_vdb, read_vdb, close_vdb, summary, NULL, NULL};

int vsv_vdb_source_register(void) { return vsv_source_register(&vdb_ops); }
