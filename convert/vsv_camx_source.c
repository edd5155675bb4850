/* vsv_camx_source.c — the CAMx source: a UAM-IV AVERAGE file (vsv_uamiv.c)
 * with its companions (the ZP heights, --heights, and the other met files
 * of --met DIR: vsv_camxmet.c) as one vsv_source. Heights come from the ZP
 * file; without it the vertical axis is the layer index. */
#include "vsv_uamiv.h"
#include "vsv_source_internal.h"
#include "vsv_vgrid.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

typedef struct camx {
    vsv_uamiv *u;
    vsv_camxmet *zp;   /* the vertical coordinate, or NULL; also in met[] */
    vsv_camxmet **met; /* companions, each offering fields */
    int nmet;
    int *fmet, *fidx; /* per field beyond the species: companion, its field */
    float *zm;        /* nz*plane layer-middle heights (m above ground) */
    float *nat;
    vsv_vgrid vg;
    int vg_hour;
} camx;

static int is_aerosol(const char *n)
{
    static const char *const a[] = {"PSO4", "PNO3", "PNH4", "POA",  "PEC",  "PCL",  "NA",   "PH2O",
                                    "FPRM", "FCRS", "CPRM", "CCRS", "SOPA", "SOPB", "SOA1", "SOA2",
                                    "SOA3", "SOA4", "SOA5", "SOA6", "SOA7", "PM25", "PM10", NULL};
    for (int i = 0; a[i]; i++)
        if (!strcmp(n, a[i]))
            return 1;
    return !strncmp(n, "PM", 2);
}

static int camx_probe(const unsigned char *h, size_t n) { return vsv_uamiv_probe(h, n); }

static int cmp_names(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

/* Layer-middle heights of hour h from the ZP layer tops. */
static int camx_heights(vsv_source *s, camx *c, int hour)
{
    const vsv_uamiv_header *h = vsv_uamiv_header_get(c->u);
    const size_t plane = (size_t)h->nx * h->ny;
    int rc = vsv_camxmet_heights(c->zp, hour, c->nat);
    if (rc)
        return vsv_source_fail(s, rc, "%s", vsv_camxmet_error(c->zp));
    for (int k = 0; k < h->nz; k++)
        for (size_t i = 0; i < plane; i++) {
            const float below = k ? c->nat[(size_t)(k - 1) * plane + i] : 0.0f;
            c->zm[(size_t)k * plane + i] = 0.5f * (below + c->nat[(size_t)k * plane + i]);
        }
    return 0;
}

/* Adds companion path (kind want, or -1: detect; quiet: skip files that are
 * no met file) after checking its hours against the average file's. */
static int camx_add_met(vsv_source *s, camx *c, const char *path, int want, int quiet)
{
    const vsv_uamiv_header *h = vsv_uamiv_header_get(c->u);
    vsv_camxmet *m = NULL;
    int rc = vsv_camxmet_open(path, want, h->nx, h->ny, h->nz, s->path, &m);
    if (rc == VSV_ENOTVSV && quiet) {
        vsv_camxmet_free(m);
        return 0;
    }
    if (rc) {
        vsv_source_fail(s, rc, "companion %s", vsv_camxmet_error(m));
        vsv_camxmet_free(m);
        return rc;
    }
    const int kind = vsv_camxmet_kind(m), nh = vsv_camxmet_nhours(m);
    for (int i = 0; i < c->nmet; i++)
        if (vsv_camxmet_kind(c->met[i]) == kind) {
            rc = vsv_source_fail(s, VSV_EINVAL, "two %s files: %s and %s", vsv_camxmet_kind_name(kind),
                                 vsv_camxmet_path(c->met[i]), path);
            vsv_camxmet_free(m);
            return rc;
        }
    /* hours: the met file's hour i is the instant the average's hour i
     * begins (one more, the last hour's end, is allowed); both local */
    if (nh != h->nhours && nh != h->nhours + 1)
        rc = vsv_source_fail(s, VSV_EINVAL, "%s has %d hour%s, this file %d (a companion has as many, or one more)",
                             path, nh, nh == 1 ? "" : "s", h->nhours);
    for (int t = 0; !rc && t < h->nhours; t++) {
        int bd, ed, md;
        float bh, eh, mt;
        vsv_uamiv_hour(c->u, t, &bd, &bh, &ed, &eh);
        vsv_camxmet_stamp(m, t, &md, &mt);
        const float mh = floorf(mt / 100) + fmodf(mt, 100) / 60;
        if (vsv_uamiv_time(md, mh) != vsv_uamiv_time(bd, bh))
            rc = vsv_source_fail(s, VSV_EINVAL, "hour %d begins at date %d %.2f h, but %s's hour %d is date %d, %04.0f",
                                 t, bd, bh, path, t, md, mt);
    }
    if (rc) {
        vsv_camxmet_free(m);
        return rc;
    }
    vsv_camxmet **grown = realloc(c->met, (size_t)(c->nmet + 1) * sizeof *grown);
    if (!grown) {
        vsv_camxmet_free(m);
        return VSV_ENOMEM;
    }
    c->met = grown;
    c->met[c->nmet++] = m;
    if (kind == VSV_MET_ZP)
        c->zp = m;
    return 0;
}

static int camx_companions(vsv_source *s, camx *c)
{
    int rc;
    if (s->opts.heights && (rc = camx_add_met(s, c, s->opts.heights, VSV_MET_ZP, 0)))
        return rc;
    if (!s->opts.met)
        return 0;
    DIR *dir = opendir(s->opts.met);
    if (!dir)
        return vsv_source_fail(s, VSV_EIO, "--met %s: cannot read the folder: %s", s->opts.met, strerror(errno));
    /* names sorted, so the order of fields does not depend on the folder */
    char **names = NULL;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(dir))) {
        if (e->d_name[0] == '.')
            continue;
        char **g = realloc(names, (size_t)(n + 1) * sizeof *g);
        if (!g || !(g[n] = strdup(e->d_name))) {
            free(g ? g : names);
            closedir(dir);
            return VSV_ENOMEM;
        }
        names = g;
        n++;
    }
    closedir(dir);
    qsort(names, (size_t)n, sizeof *names, cmp_names);
    struct stat self;
    rc = stat(s->path, &self) ? VSV_EIO : 0;
    for (int i = 0; i < n && !rc; i++) {
        char path[2048];
        snprintf(path, sizeof path, "%s/%s", s->opts.met, names[i]);
        struct stat st;
        unsigned char head[512];
        if (stat(path, &st) || !S_ISREG(st.st_mode) || (st.st_dev == self.st_dev && st.st_ino == self.st_ino))
            continue;
        if (s->opts.heights && c->zp) {
            struct stat zs;
            if (!stat(s->opts.heights, &zs) && zs.st_dev == st.st_dev && zs.st_ino == st.st_ino)
                continue;
        }
        char why[300]; /* (replaced since the stat: a FIFO is refused, not waited on) */
        FILE *fp = vsv_input_fopen(path, "rb", why, sizeof why);
        const size_t got = fp ? fread(head, 1, sizeof head, fp) : 0;
        if (fp)
            fclose(fp);
        if (vsv_uamiv_probe(head, got))
            continue; /* other CAMx output, boundary or emission files */
        if (vsv_camx_is_landuse(head, got)) {
            rc = vsv_camx_landuse(s, path);
            continue;
        }
        rc = camx_add_met(s, c, path, -1, 1);
    }
    for (int i = 0; i < n; i++)
        free(names[i]);
    free(names);
    return rc;
}

/* The grid's projection (the header's, v6+; else the options'; else none),
 * the run's names and the time zone, into s->grid; 0 or the error. */
static int camx_describe(vsv_source *s, const vsv_uamiv_header *h)
{
    vsv_meta *g = &s->grid;
    /* projection: the header's (v6+), else the options', else none */
    if (s->opts.proj.kind != VSV_PROJ_NONE) {
        g->proj = s->opts.proj;
        if (!(s->opts.proj_set & 8)) /* no --lat2: a tangent (or one-parallel) projection */
            g->proj.lat2 = g->proj.lat1;
    } else if (h->v6) {
        g->proj.radius = 6370000;
        g->proj.lon0 = h->plon;
        g->proj.lat0 = h->plat;
        g->proj.lat1 = h->tlat1;
        g->proj.lat2 = h->tlat2;
        switch (h->iproj) {
        case 0: g->proj.kind = VSV_PROJ_LATLON; break;
        case 2: g->proj.kind = VSV_PROJ_LCC; break;
        case 4: g->proj.kind = VSV_PROJ_PSTEREO; break;
        case 5: g->proj.kind = VSV_PROJ_MERCATOR; break;
        default:
            return vsv_source_fail(s, VSV_EUNSUPPORTED,
                                   "projection code %d (%s) is not supported; give one with --proj", h->iproj,
                                   h->iproj == 1   ? "UTM"
                                   : h->iproj == 3 ? "rotated polar stereographic"
                                                   : "unknown");
        }
    } else {
        vsv_meta_add_attr(g, "projection", "unknown (CAMx 5 header has none; give --proj lcc --lat1 ... )");
    }
    snprintf(g->model, sizeof g->model, "CAMx");
    snprintf(g->run, sizeof g->run, "%s %s", h->name, h->note);
    char buf[64];
    snprintf(buf, sizeof buf, "%s", h->v6 ? "6+" : "5");
    vsv_meta_add_attr(g, "CAMx header", buf);
    if (h->v6) {
        if (h->nseg_or_tz < -12 || h->nseg_or_tz > 14)
            return vsv_source_fail(s, VSV_ECORRUPT, "header record 1: time zone %d is not an hour offset (-12..14)",
                                   h->nseg_or_tz);
        snprintf(buf, sizeof buf, "%d (the file's hours are UTC%+d; times here are UTC)", h->nseg_or_tz,
                 -h->nseg_or_tz);
        vsv_meta_add_attr(g, "time zone", buf);
    } else {
        snprintf(buf, sizeof buf, "%d", h->nseg_or_tz);
        vsv_meta_add_attr(g, "nseg", buf);
        vsv_meta_add_attr(g, "time zone", "none in a v5 header: hours taken as UTC");
    }
    return 0;
}

static int camx_open(vsv_source *s)
{
    camx *c = calloc(1, sizeof *c);
    if (!c)
        return VSV_ENOMEM;
    s->priv = c;
    c->vg_hour = -1;
    int rc = vsv_uamiv_open(s->path, &c->u);
    if (rc) {
        vsv_msg(s->err, sizeof s->err, "%s", vsv_uamiv_error(c->u));
        return rc;
    }
    const vsv_uamiv_header *h = vsv_uamiv_header_get(c->u);
    vsv_meta *g = &s->grid;
    g->nx = h->nx;
    g->ny = h->ny;
    g->origin[0] = h->xorg + h->dx / 2.0;
    g->origin[1] = h->yorg + h->dy / 2.0;
    g->spacing[0] = h->dx;
    g->spacing[1] = h->dy;
    if ((rc = camx_describe(s, h)))
        return rc;
    const size_t plane = (size_t)h->nx * h->ny;
    c->nat = malloc(plane * (size_t)h->nz * sizeof *c->nat);
    c->zm = malloc(plane * (size_t)h->nz * sizeof *c->zm);
    if (!c->nat || !c->zm)
        return VSV_ENOMEM;
    /* companions: --heights, and the met files of --met DIR */
    if ((rc = camx_companions(s, c)))
        return rc;
    /* vertical */
    if (c->zp) {
        if ((rc = camx_heights(s, c, 0)))
            return rc;
        if ((rc = vsv_source_axis(s, c->zm, h->nz, 10.0)) < 0)
            return rc;
        char note[1200];
        snprintf(note, sizeof note, "above ground, from the CAMx height/pressure file %s", vsv_camxmet_path(c->zp));
        if (vsv_meta_add_attr(g, "heights", note) < 0 || vsv_meta_add_attr(g, VSV_ATTR_DATUM, "ground") < 0)
            return VSV_ENOMEM;
    } else {
        g->nz = h->nz;
        g->vert_kind = VSV_VERT_INDEX;
    }
    /* species and hours, then the companions' fields */
    int nmf = 0;
    for (int i = 0; i < c->nmet; i++)
        nmf += vsv_camxmet_nfields(c->met[i]);
    s->fields = calloc((size_t)h->nspec + (size_t)nmf, sizeof *s->fields);
    c->fmet = calloc((size_t)nmf + 1, sizeof *c->fmet);
    c->fidx = calloc((size_t)nmf + 1, sizeof *c->fidx);
    if (!c->fmet || !c->fidx)
        return VSV_ENOMEM;
    s->times = calloc((size_t)h->nhours, sizeof *s->times);
    if (!s->fields || !s->times)
        return VSV_ENOMEM;
    const int emis = !strcmp(h->name, "EMISSIONS");
    for (int i = 0; i < h->nspec; i++) {
        vsv_field_info *f = &s->fields[i];
        snprintf(f->name, sizeof f->name, "%s", h->species[i]);
        const int aero = is_aerosol(f->name);
        snprintf(f->units, sizeof f->units, "%s", emis ? (aero ? "g/h" : "mol/h") : aero ? "ug/m3" : "ppm");
        snprintf(f->description, sizeof f->description, "%s %s", aero ? "aerosol" : "gas", h->name);
        snprintf(f->ordering, sizeof f->ordering, "UAM-IV");
        f->nlevels = h->nz;
        f->is_volume = f->is_default = 1;
    }
    s->nfields = h->nspec;
    for (int i = 0; i < c->nmet; i++)
        for (int f = 0; f < vsv_camxmet_nfields(c->met[i]); f++) {
            const char *name, *units, *desc;
            vsv_camxmet_field(c->met[i], f, &name, &units, &desc);
            if (vsv_source_find_field(s, name) >= 0)
                return vsv_source_fail(s, VSV_EINVAL, "%s and a species both are %s", vsv_camxmet_path(c->met[i]),
                                       name);
            vsv_field_info *fi = &s->fields[s->nfields];
            snprintf(fi->name, sizeof fi->name, "%s", name);
            snprintf(fi->units, sizeof fi->units, "%s", units);
            snprintf(fi->description, sizeof fi->description, "%s", desc);
            snprintf(fi->ordering, sizeof fi->ordering, "CAMx met");
            fi->nlevels = h->nz;
            fi->is_volume = 1;
            c->fmet[s->nfields - h->nspec] = i;
            c->fidx[s->nfields - h->nspec] = f;
            s->nfields++;
        }
    /* times: the file's hours are in its time zone (v6+: hours behind UTC);
     * every time in a .vsv is UTC */
    const int zone = h->v6 ? h->nseg_or_tz : 0;
    for (int t = 0; t < h->nhours; t++) {
        int bd, ed;
        float bh, eh;
        vsv_uamiv_hour(c->u, t, &bd, &bh, &ed, &eh);
        /* a date YYJJJ or YYYYJJJ and an hour 0..24: a NaN or a wild value
         * would make a time of nothing (and undefined arithmetic) */
        if (!isfinite(bh) || bh < 0 || bh > 24 || bd < 0 || bd / 1000 > 9999 || bd % 1000 < 1 || bd % 1000 > 366)
            return vsv_source_fail(s, VSV_ECORRUPT,
                                   "hour %d: begins at date %d, hour %g: not a time (record of hour %d)", t, bd, bh, t);
        s->times[t] = vsv_uamiv_time(bd, bh) + (int64_t)zone * 3600;
        if (t && s->times[t] <= s->times[t - 1])
            return vsv_source_fail(s, VSV_ECORRUPT, "hour %d (date %d, %.2f h) does not follow hour %d", t, bd, bh,
                                   t - 1);
    }
    s->ntimes = h->nhours;
    /* native levels with heights: their heights in every column, every hour they move */
    for (int t = 0; c->zp && g->vert_kind == VSV_VERT_NATIVE && t < s->ntimes; t++)
        if ((rc = camx_heights(s, c, t)) || (rc = vsv_source_native_heights(s, t, c->zm)))
            return rc;
    return 0;
}

static int camx_read(vsv_source *s, int field, int t, float *out)
{
    camx *c = s->priv;
    const vsv_uamiv_header *h = vsv_uamiv_header_get(c->u);
    const size_t plane = (size_t)h->nx * h->ny;
    const int even = s->grid.vert_kind == VSV_VERT_EVEN;
    float *dst = even ? c->nat : out;
    int rc;
    if (even && c->vg_hour != t) {
        if ((rc = camx_heights(s, c, t)))
            return rc;
        if (vsv_vgrid_plan(&c->vg, c->zm, h->nz, plane, NULL, s->grid.nz, s->grid.origin[2], s->grid.spacing[2]))
            return VSV_ENOMEM;
        c->vg_hour = t;
    }
    if (field >= h->nspec) {
        vsv_camxmet *m = c->met[c->fmet[field - h->nspec]];
        for (int k = 0; k < h->nz; k++)
            if ((rc = vsv_camxmet_read(m, t, c->fidx[field - h->nspec], k, dst + (size_t)k * plane)))
                return vsv_source_fail(s, rc, "%s", vsv_camxmet_error(m));
    }
    for (int k = 0; k < h->nz && field < h->nspec; k++)
        if ((rc = vsv_uamiv_read(c->u, t, field, k, dst + (size_t)k * plane)))
            return vsv_source_fail(s, rc, "%s", vsv_uamiv_error(c->u) + strlen(s->path) + 2);
    if (even)
        vsv_vgrid_apply(&c->vg, c->nat, out);
    return 0;
}

static void camx_close(vsv_source *s)
{
    camx *c = s->priv;
    if (!c)
        return;
    vsv_uamiv_free(c->u);
    for (int i = 0; i < c->nmet; i++)
        vsv_camxmet_free(c->met[i]);
    free(c->met);
    free(c->fmet);
    free(c->fidx);
    free(c->zm);
    free(c->nat);
    vsv_vgrid_free(&c->vg);
    free(c);
}

static char *camx_summary(vsv_source *s)
{
    camx *c = s->priv;
    const vsv_uamiv_header *h = vsv_uamiv_header_get(c->u);
    vsv_buf b = {0};
    char line[600];
    snprintf(
        line, sizeof line,
        "CAMx UAM-IV %s file (%s-endian, v%s header)\n  note        %s\n  grid        %d x %d x %d, origin (%g, %g), "
        "cells %g x %g, projection code %d (true lat %g/%g, centre %g, %g)\n  hours       %d, from date %d %.2f h to "
        "%d %.2f h\n  species     %d:",
        h->name, h->little_endian ? "little" : "big", h->v6 ? "6+" : "5", h->note, h->nx, h->ny, h->nz, h->xorg,
        h->yorg, h->dx, h->dy, h->iproj, h->tlat1, h->tlat2, h->plat, h->plon, h->nhours, h->bdate, h->bhour, h->edate,
        h->ehour, h->nspec);
    vsv_buf_put(&b, line, strlen(line));
    for (int i = 0; i < h->nspec; i++) {
        snprintf(line, sizeof line, " %s", h->species[i]);
        vsv_buf_put(&b, line, strlen(line));
    }
    vsv_buf_put(&b, "\n", 2);
    return (char *)b.p;
}

/* A met field's companion file; a species' is the average file itself. */
static const char *camx_field_path(const vsv_source *s, int field)
{
    const camx *c = s->priv;
    const int nspec = vsv_uamiv_header_get(c->u)->nspec;
    return field >= nspec && field < s->nfields ? vsv_camxmet_path(c->met[c->fmet[field - nspec]]) : s->path;
}

const vsv_source_ops vsv_camx_ops = {"CAMx UAM-IV", camx_probe,   camx_open, camx_read,
                                     camx_close,    camx_summary, NULL,      camx_field_path};
