/* vsv_outlines.c — coast, lake and border lines for the map under a grid,
 * read straight from the GSHHG binned netCDF files of Debian's
 * gmt-gshhg-low (binned_GSHHS_R.nc: shorelines by level, 1 land/sea, 2 lake,
 * 3 island in a lake, 4 pond; binned_border_R.nc: 1 national, 2 state or
 * province, 3 maritime) and projected with the grid's own projection.
 *
 * Both files cut the world into square bins (Bin_size_in_minutes; bin b has
 * its south-west corner at longitude (b mod nx) * size, latitude 90 -
 * (b / nx + 1) * size); a bin lists its segments, a segment its points as
 * unsigned 16-bit offsets from that corner in 1/65535 of the bin size. A
 * shore segment's Embedded_npts_levels_exit_entry word holds its point count
 * (bits 9 up) and level (bits 6-8). */
#include "vsv_annot_internal.h"

#include <math.h>
#include <netcdf.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define VSV_GSHHG_DIR "/usr/share/gmt-gshhg"

typedef struct line {
    int kind, first, n; /* VSV_OUTLINE_*, its points */
} line;

struct vsv_outlines {
    line *lines;
    int nlines, cap;
    double *xy; /* world x, y pairs */
    size_t npts, ptcap;
    char res;
};

/* The lat/lon box a grid covers: its boundary cells inverse-projected
 * (longitudes unwrapped around the centre's), widened by a margin, the
 * whole circle of longitude when a pole is inside. */
int vsv_grid_latlon_box(const vsv_meta *m, double box[4])
{
    double *s = &box[0], *n = &box[1], *w = &box[2], *e = &box[3];
    double clat, clon;
    const double cx = m->origin[0] + 0.5 * (m->nx - 1) * m->spacing[0];
    const double cy = m->origin[1] + 0.5 * (m->ny - 1) * m->spacing[1];
    if (vsv_proj_inverse(&m->proj, cx, cy, &clat, &clon))
        return VSV_EUNSUPPORTED;
    *s = *w = INFINITY;
    *n = *e = -INFINITY;
    const int per = 64;
    for (int side = 0; side < 4; side++)
        for (int k = 0; k <= per; k++) {
            const double f = (double)k / per - 0.5;
            const double u = side < 2 ? f : side == 2 ? -0.5 : 0.5, v = side < 2 ? (side ? 0.5 : -0.5) : f;
            const double x = cx + u * (m->nx) * m->spacing[0], y = cy + v * (m->ny) * m->spacing[1];
            double lat, lon;
            if (vsv_proj_inverse(&m->proj, x, y, &lat, &lon))
                continue;
            lon = clon + remainder(lon - clon, 360);
            *s = fmin(*s, lat), *n = fmax(*n, lat), *w = fmin(*w, lon), *e = fmax(*e, lon);
        }
    if (!(*s <= *n))
        return VSV_EUNSUPPORTED;
    const double pad = 1;
    *s -= pad, *n += pad, *w -= pad, *e += pad;
    for (int pole = -1; pole <= 1; pole += 2) { /* a pole inside the grid */
        double x, y;
        if (vsv_proj_forward(&m->proj, 90.0 * pole, clon, &x, &y) == 0 && fabs(x - cx) < 0.5 * m->nx * m->spacing[0] &&
            fabs(y - cy) < 0.5 * m->ny * m->spacing[1]) {
            *w = clon - 180, *e = clon + 180;
            if (pole < 0)
                *s = -90;
            else
                *n = 90;
        }
    }
    if (*e - *w > 360)
        *w = clon - 180, *e = clon + 180;
    *s = fmax(*s, -90), *n = fmin(*n, 90);
    return 0;
}

static int add_point(vsv_outlines *o, double x, double y)
{
    if (o->npts == o->ptcap) {
        const size_t nc = o->ptcap ? 2 * o->ptcap : 4096;
        double *p = realloc(o->xy, nc * 2 * sizeof *p);
        if (!p)
            return VSV_ENOMEM;
        o->xy = p;
        o->ptcap = nc;
    }
    o->xy[2 * o->npts] = x;
    o->xy[2 * o->npts + 1] = y;
    o->npts++;
    return 0;
}

static int end_line(vsv_outlines *o, int kind, size_t first)
{
    if (o->npts - first < 2) {
        o->npts = first;
        return 0;
    }
    if (o->nlines == o->cap) {
        const int nc = o->cap ? 2 * o->cap : 256;
        line *l = realloc(o->lines, (size_t)nc * sizeof *l);
        if (!l)
            return VSV_ENOMEM;
        o->lines = l;
        o->cap = nc;
    }
    o->lines[o->nlines++] = (line){kind, (int)first, (int)(o->npts - first)};
    return 0;
}

/* The grid's x of longitude lon: for a latitude/longitude grid the copy of
 * lon (lon + k 360) inside its span, else the projection's. */
static int project(const vsv_meta *m, double lat, double lon, double x0, double *x, double *y)
{
    if (m->proj.kind == VSV_PROJ_LATLON)
        lon = x0 + fmod(fmod(lon - x0, 360) + 360, 360);
    return vsv_scene_world(m, lat, lon, x, y);
}

typedef struct reader {
    int nc;
    int bin_nx, bsize_min, nbins;
    int *first_seg;
    short *nseg;
    const char *path;
} reader;

static int nc_fail(const char *path, int rc, const char *what, char *msg, size_t cap)
{
    snprintf(msg, cap, "%s: %s: %s", path, what, nc_strerror(rc));
    return VSV_ECORRUPT;
}

#define NCTRY(call, what)                                                                                              \
    do {                                                                                                               \
        const int nc_rc_ = (call);                                                                                     \
        if (nc_rc_ != NC_NOERR) {                                                                                      \
            rc = nc_fail(path, nc_rc_, what, msg, cap);                                                                \
            goto fail;                                                                                                 \
        }                                                                                                              \
    } while (0)

static int get_int(int nc, const char *name, int *v)
{
    int id;
    const size_t at = 0;
    int rc = nc_inq_varid(nc, name, &id);
    return rc ? rc : nc_get_var1_int(nc, id, &at, v);
}

static int get_ints(int nc, const char *name, size_t start, size_t count, int *v)
{
    int id;
    int rc = nc_inq_varid(nc, name, &id);
    return rc ? rc : count ? nc_get_vara_int(nc, id, &start, &count, v) : 0;
}

static int get_shorts(int nc, const char *name, size_t start, size_t count, short *v)
{
    int id;
    int rc = nc_inq_varid(nc, name, &id);
    return rc ? rc : count ? nc_get_vara_short(nc, id, &start, &count, v) : 0;
}

/* Reads one binned file (border = 0: shorelines, 1: borders) and adds the
 * segments of the bins that meet [s, n] x [w, e]. */
static int read_binned(vsv_outlines *o, const vsv_meta *m, const char *path, int border, const double box[4], char *msg,
                       size_t cap)
{
    int rc = 0, nc = -1, nsegs = 0, npts = 0;
    int *first = NULL, *sfirst = NULL, *sinfo = NULL;
    short *nseg = NULL, *slev = NULL, *sn = NULL, *dx = NULL, *dy = NULL;
    NCTRY(nc_open(path, NC_NOWRITE, &nc), "cannot open");
    int bsize, bin_nx, bin_ny, nbins;
    NCTRY(get_int(nc, "Bin_size_in_minutes", &bsize), "Bin_size_in_minutes");
    NCTRY(get_int(nc, "N_bins_in_360_longitude_range", &bin_nx), "N_bins_in_360_longitude_range");
    NCTRY(get_int(nc, "N_bins_in_180_degree_latitude_range", &bin_ny), "N_bins_in_180_degree_latitude_range");
    NCTRY(get_int(nc, "N_bins_in_file", &nbins), "N_bins_in_file");
    NCTRY(get_int(nc, "N_segments_in_file", &nsegs), "N_segments_in_file");
    NCTRY(get_int(nc, "N_points_in_file", &npts), "N_points_in_file");
    if (bsize <= 0 || bsize > 10800 || bin_nx * bsize != 21600 || bin_ny * bsize != 10800 || nbins != bin_nx * bin_ny ||
        nsegs < 0 || npts < 0 || nsegs > 100000000 || npts > 500000000) {
        snprintf(msg, cap, "%s: not a GSHHG binned file (bins %d x %d of %d minutes)", path, bin_nx, bin_ny, bsize);
        rc = VSV_ECORRUPT;
        goto fail;
    }
    first = malloc((size_t)nbins * sizeof *first);
    nseg = malloc((size_t)nbins * sizeof *nseg);
    sfirst = malloc(((size_t)nsegs + 1) * sizeof *sfirst);
    sinfo = malloc(((size_t)nsegs + 1) * sizeof *sinfo);
    slev = malloc(((size_t)nsegs + 1) * sizeof *slev);
    sn = malloc(((size_t)nsegs + 1) * sizeof *sn);
    dx = malloc(((size_t)npts + 1) * sizeof *dx);
    dy = malloc(((size_t)npts + 1) * sizeof *dy);
    if (!first || !nseg || !sfirst || !sinfo || !slev || !sn || !dx || !dy) {
        snprintf(msg, cap, "out of memory");
        rc = VSV_ENOMEM;
        goto fail;
    }
    NCTRY(get_ints(nc, "Id_of_first_segment_in_a_bin", 0, (size_t)nbins, first), "Id_of_first_segment_in_a_bin");
    NCTRY(get_shorts(nc, "N_segments_in_a_bin", 0, (size_t)nbins, nseg), "N_segments_in_a_bin");
    NCTRY(get_ints(nc, "Id_of_first_point_in_a_segment", 0, (size_t)nsegs, sfirst), "Id_of_first_point_in_a_segment");
    if (border) {
        NCTRY(get_shorts(nc, "N_points_for_a_segment", 0, (size_t)nsegs, sn), "N_points_for_a_segment");
        NCTRY(get_shorts(nc, "Hierarchial_level_of_a_segment", 0, (size_t)nsegs, slev),
              "Hierarchial_level_of_a_segment");
    } else {
        NCTRY(get_ints(nc, "Embedded_npts_levels_exit_entry_for_a_segment", 0, (size_t)nsegs, sinfo),
              "Embedded_npts_levels_exit_entry_for_a_segment");
    }
    NCTRY(get_shorts(nc, "Relative_longitude_from_SW_corner_of_bin", 0, (size_t)npts, dx),
          "Relative_longitude_from_SW_corner_of_bin");
    NCTRY(get_shorts(nc, "Relative_latitude_from_SW_corner_of_bin", 0, (size_t)npts, dy),
          "Relative_latitude_from_SW_corner_of_bin");
    const double size = bsize / 60.0, scale = size / 65535.0;
    const double x0 = m->origin[0] - 0.5 * m->spacing[0]; /* a latitude/longitude grid's west edge */
    double ux, uy;
    vsv_scene_units(m, &ux, &uy);
    const double half_turn = m->proj.kind == VSV_PROJ_LATLON ? 180 * ux : INFINITY;
    for (int b = 0; b < nbins; b++) {
        const double lon_sw = (b % bin_nx) * size, lat_sw = 90 - (b / bin_nx + 1) * size;
        if (lat_sw > box[1] || lat_sw + size < box[0])
            continue;
        /* the bin's copy nearest the box in longitude */
        const double lw = box[2] + fmod(fmod(lon_sw - box[2], 360) + 360, 360);
        if (lw > box[3] && lw + size - 360 < box[2])
            continue;
        if (nseg[b] < 0 || first[b] < 0 || first[b] + nseg[b] > nsegs) {
            snprintf(msg, cap, "%s: bin %d: segments %d..%d outside the file's %d", path, b, first[b],
                     first[b] + nseg[b], nsegs);
            rc = VSV_ECORRUPT;
            goto fail;
        }
        for (int k = first[b]; k < first[b] + nseg[b]; k++) {
            int level, count;
            if (border) {
                level = slev[k];
                count = sn[k];
            } else {
                level = (sinfo[k] >> 6) & 7;
                count = (int)((unsigned)sinfo[k] >> 9);
            }
            int kind;
            if (border)
                kind = level == 1 ? VSV_OUTLINE_BORDER : level == 2 ? VSV_OUTLINE_STATE : 0;
            else /* level 5, 6: Antarctica's grounding line, drawn as its ice front (level 1) */
                kind = level == 1 ? VSV_OUTLINE_COAST : level >= 2 && level <= 4 ? VSV_OUTLINE_LAKE : 0;
            if (!kind)
                continue;
            if (count < 0 || sfirst[k] < 0 || (int64_t)sfirst[k] + count > npts) {
                snprintf(msg, cap, "%s: segment %d: points %d..%lld outside the file's %d", path, k, sfirst[k],
                         (long long)sfirst[k] + count, npts);
                rc = VSV_ECORRUPT;
                goto fail;
            }
            size_t start = o->npts;
            for (int p = sfirst[k]; p < sfirst[k] + count; p++) {
                const double lon = lon_sw + (unsigned short)dx[p] * scale, lat = lat_sw + (unsigned short)dy[p] * scale;
                double x, y;
                const int ok = !project(m, lat, lon, x0, &x, &y) && isfinite(x) && isfinite(y);
                /* a latitude/longitude grid's seam: the line leaves on one
                 * side and comes back on the other */
                const int seam = ok && o->npts > start && fabs(x - o->xy[2 * o->npts - 2]) > half_turn;
                if (seam) {
                    if ((rc = end_line(o, kind, start)))
                        goto oom;
                    start = o->npts;
                }
                if (!ok) {
                    if ((rc = end_line(o, kind, start)))
                        goto oom;
                    start = o->npts;
                    continue;
                }
                if ((rc = add_point(o, x, y)))
                    goto oom;
            }
            if ((rc = end_line(o, kind, start)))
                goto oom;
        }
    }
    goto done;
oom:
    snprintf(msg, cap, "out of memory");
fail:
done:
    if (nc >= 0)
        nc_close(nc);
    free(first), free(nseg), free(sfirst), free(sinfo), free(slev), free(sn), free(dx), free(dy);
    return rc;
}

int vsv_outlines_load(const vsv_meta *grid, const char *dir, char res, vsv_outlines **out, char *msg, size_t cap)
{
    const vsv_meta span = vsv_meta_span(grid), *m = &span; /* a moving nest: every place it stands */
    *out = NULL;
    if (!dir || !*dir)
        dir = getenv("VSV_GSHHG");
    if (!dir || !*dir)
        dir = VSV_GSHHG_DIR;
    if (res != 'c' && res != 'l' && res != 'i') {
        snprintf(msg, cap, "GSHHG resolution '%c': c, l or i", res);
        return VSV_EINVAL;
    }
    double box[4];
    if (m->proj.kind == VSV_PROJ_NONE || vsv_grid_latlon_box(m, box)) {
        snprintf(msg, cap, "the grid has no map projection: no coastlines");
        return VSV_EUNSUPPORTED;
    }
    char shore[4096], border[4096];
    snprintf(shore, sizeof shore, "%s/binned_GSHHS_%c.nc", dir, res);
    snprintf(border, sizeof border, "%s/binned_border_%c.nc", dir, res);
    if (access(shore, R_OK)) {
        snprintf(msg, cap, "%s: not found: no coast or border outlines (apt-get install gmt-gshhg-low)", shore);
        return VSV_ENOTFOUND;
    }
    vsv_outlines *o = calloc(1, sizeof *o);
    if (!o) {
        snprintf(msg, cap, "out of memory");
        return VSV_ENOMEM;
    }
    o->res = res;
    int rc = read_binned(o, m, shore, 0, box, msg, cap);
    if (!rc && !access(border, R_OK))
        rc = read_binned(o, m, border, 1, box, msg, cap);
    if (rc) {
        vsv_outlines_free(o);
        return rc;
    }
    *out = o;
    return 0;
}

char vsv_outlines_resolution(double km)
{
    /* GSHHG's resolutions keep features of about 25 (c), 5 (l) and 1 km (i) */
    return km > 12 ? 'c' : km > 2.5 ? 'l' : 'i';
}

void vsv_outlines_free(vsv_outlines *o)
{
    if (!o)
        return;
    free(o->lines);
    free(o->xy);
    free(o);
}

int vsv_outlines_count(const vsv_outlines *o) { return o ? o->nlines : 0; }

const double *vsv_outlines_line(const vsv_outlines *o, int i, int *kind, int *n)
{
    if (!o || i < 0 || i >= o->nlines)
        return NULL;
    *kind = o->lines[i].kind;
    *n = o->lines[i].n;
    return o->xy + 2 * (size_t)o->lines[i].first;
}
