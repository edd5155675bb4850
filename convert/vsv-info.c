/* vsv-info — tells everything about a .vsv file, for people (text) and for
 * scripts (--json, -f FIELD); --stats decodes every step, --check verifies
 * every byte. */
#include "vsv_cli.h"
#include "vsv_convert.h"
#include "vsv_convert_cli.h"
#include "vsv_vdb.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* clang-format off */ /* (the help text as it prints, a line a line) */
static const char usage[] =
    "Usage: vsv-info [OPTIONS] FILE|URL...\n"
    "Describe .vsv files: grid, projection and corner coordinates, times, species\n"
    "with units, ranges and quantisation error, bricks stored, compression ratio.\n"
    "Given a model file instead, describe its own header and fields; it reads,\n"
    "detected from the content (never the name):\n" VSV_CLI_MODEL_FORMATS ",\n"
    "  OpenVDB .vdb (a step a file, as vsv-export --vdb writes them).\n"
    "Writes text, or JSON with --json.\n"
    "\n"
    "  -j, --json           one JSON object per file (a stable contract for scripts)\n"
    "  -f, --field PATH     print one value of the JSON, e.g. grid.nx, times.0,\n"
    "                       species.1.max_abs_error or species.CLW.max_abs_error,\n"
    "                       bricks.stored; repeatable: a line each, in order\n"
    "  -s, --stats          add min/max/mean per species and time over the cells\n"
    "                       with data (decodes all)\n"
    "  -c, --check          verify every checksum and padding byte, decode\n"
    "                       everything; exit 1 naming the damage\n"
    "  -q, --quiet          no progress bar\n"
    VSV_CLI_CACHE_DIR_HELP
    "  -h, --help           this help\n"
    "  -V, --version        print versions\n";
/* clang-format on */

static const char *scale_name(int s) { return s == VSV_SCALE_LOG ? "log" : "linear"; }
static const char *vert_name(int k)
{
    static const char *n[] = {"even", "native", "index", "coordinate"};
    return k >= 0 && k <= 3 ? n[k] : "unknown";
}

typedef struct stat_row {
    double min, max, mean;
} stat_row;

/* min/max/mean over the grid of every (species, step). */
static stat_row *compute_stats(vsv_file *f, const char *path)
{
    const vsv_meta *m = vsv_file_meta(f);
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    const size_t cells = (size_t)m->nx * m->ny * m->nz;
    stat_row *rows = calloc((size_t)m->nvars * info.nsteps, sizeof *rows);
    float *buf = malloc(cells * sizeof *buf);
    vsv_decoder *d = NULL;
    if (!rows || !buf || vsv_decoder_create(f, &d))
        vsv_cli_die(1, "out of memory");
    for (int s = 0; s < m->nvars; s++)
        for (int t = 0; t < info.nsteps; t++) {
            if (vsv_decoder_volume(d, t, s, buf))
                vsv_cli_die(1, "%s", vsv_decoder_error(d));
            double mn = INFINITY, mx = -INFINITY, sum = 0;
            size_t n = 0;
            for (size_t i = 0; i < cells; i++) {
                if (isnan(buf[i]))
                    continue; /* no-data cells */
                mn = buf[i] < mn ? buf[i] : mn;
                mx = buf[i] > mx ? buf[i] : mx;
                sum += buf[i];
                n++;
            }
            rows[(size_t)s * info.nsteps + t] = n ? (stat_row){mn, mx, sum / (double)n} : (stat_row){NAN, NAN, NAN};
            vsv_cli_progress((void *)path, s * info.nsteps + t + 1, m->nvars * info.nsteps);
        }
    vsv_decoder_free(d);
    free(buf);
    return rows;
}

static void corner(const vsv_meta *m, int c, double *x, double *y)
{
    *x = m->origin[0] + (c & 1 ? (m->nx - 1) * m->spacing[0] : 0);
    *y = m->origin[1] + (c & 2 ? (m->ny - 1) * m->spacing[1] : 0);
}

static const char *corner_names[4] = {"SW", "SE", "NW", "NE"};

/* The grid: its size, origin, spacing, vertical coordinate, terrain and land use. */
static vsv_json *json_grid(const vsv_meta *m)
{
    vsv_json *grid = vsv_json_object();
    vsv_json_set(grid, "nx", vsv_json_int(m->nx));
    vsv_json_set(grid, "ny", vsv_json_int(m->ny));
    vsv_json_set(grid, "nz", vsv_json_int(m->nz));
    vsv_json *o = vsv_json_array(), *sp = vsv_json_array();
    for (int i = 0; i < 3; i++) {
        vsv_json_push(o, vsv_json_number(m->origin[i]));
        vsv_json_push(sp, vsv_json_number(m->spacing[i]));
    }
    vsv_json_set(grid, "origin", o);
    vsv_json_set(grid, "spacing", sp);
    vsv_json *vert = vsv_json_object();
    vsv_json_set(vert, "kind", vsv_json_string(vert_name(m->vert_kind)));
    vsv_json_set(vert, "units",
                 vsv_json_string(m->vert_kind == VSV_VERT_INDEX ? "layer index"
                                 : m->vert_units[0]             ? m->vert_units
                                                                : "m"));
    if (m->levels) {
        vsv_json *lv = vsv_json_array();
        for (int k = 0; k < m->nz; k++)
            vsv_json_push(lv, vsv_json_number(m->levels[k]));
        vsv_json_set(vert, "levels", lv);
    }
    vsv_json_set(vert, "column_heights", vsv_json_number(m->nheights));
    vsv_json_set(grid, "vertical", vert);
    vsv_json_set(grid, "terrain", vsv_json_bool(m->terrain != NULL));
    vsv_json_set(grid, "landuse", vsv_json_bool(m->landuse != NULL));
    return grid;
}

/* The projection and the four corners' latitudes and longitudes (null without a projection). */
static void json_set_projection(vsv_json *root, const vsv_meta *m)
{
    vsv_json *proj = vsv_json_object();
    vsv_json_set(proj, "name", vsv_json_string(vsv_proj_name(m->proj.kind)));
    if (m->proj.kind >= VSV_PROJ_LCC) {
        vsv_json_set(proj, "lat0", vsv_json_number(m->proj.lat0));
        vsv_json_set(proj, "lon0", vsv_json_number(m->proj.lon0));
        vsv_json_set(proj, "lat1", vsv_json_number(m->proj.lat1));
        vsv_json_set(proj, "lat2", vsv_json_number(m->proj.lat2));
        vsv_json_set(proj, "radius", vsv_json_number(m->proj.radius > 0 ? m->proj.radius : 6370000.0));
    }
    vsv_json_set(root, "projection", proj);

    vsv_json *corners = vsv_json_array();
    for (int c = 0; c < 4; c++) {
        double x, y, lat, lon;
        corner(m, c, &x, &y);
        vsv_json *cj = vsv_json_object();
        vsv_json_set(cj, "name", vsv_json_string(corner_names[c]));
        if (m->proj.kind != VSV_PROJ_NONE && !vsv_proj_inverse(&m->proj, x, y, &lat, &lon)) {
            vsv_json_set(cj, "lat", vsv_json_number(lat));
            vsv_json_set(cj, "lon", vsv_json_number(lon));
        } else {
            vsv_json_set(cj, "lat", vsv_json_null());
            vsv_json_set(cj, "lon", vsv_json_null());
        }
        vsv_json_push(corners, cj);
    }
    vsv_json_set(root, "corners", corners);
}

/* The source (model and run), the grid, the projection and the corners. */
static void json_set_place(vsv_json *root, const vsv_meta *m)
{
    vsv_json *src = vsv_json_object();
    vsv_json_set(src, "model", vsv_json_string(m->model));
    vsv_json_set(src, "run", vsv_json_string(m->run));
    vsv_json_set(root, "source", src);
    vsv_json_set(root, "grid", json_grid(m));
    json_set_projection(root, m);
}

/* A moving nest's placements after the first (SPEC.md "MOVE"): from when,
 * its south-west corner, and how many cells it moved from GRID's place. */
static void json_set_moves(vsv_json *root, const vsv_meta *m)
{
    vsv_json *moves = vsv_json_array();
    for (int i = 0; i < m->nmoves; i++) {
        const vsv_move *v = &m->moves[i];
        char iso[40];
        double lat, lon;
        vsv_cal_format(vsv_meta_calendar(m), v->time, iso, sizeof iso);
        vsv_json *mj = vsv_json_object();
        vsv_json_set(mj, "time", vsv_json_string(iso));
        vsv_json_set(mj, "x", vsv_json_number(v->origin[0]));
        vsv_json_set(mj, "y", vsv_json_number(v->origin[1]));
        const int ok =
            m->proj.kind != VSV_PROJ_NONE && !vsv_proj_inverse(&m->proj, v->origin[0], v->origin[1], &lat, &lon);
        vsv_json_set(mj, "sw_lat", ok ? vsv_json_number(lat) : vsv_json_null());
        vsv_json_set(mj, "sw_lon", ok ? vsv_json_number(lon) : vsv_json_null());
        vsv_json_push(moves, mj);
    }
    vsv_json_set(root, "moves", moves);
}

/* The same as text: one line a placement. */
static void print_moves(const vsv_meta *m)
{
    if (!m->nmoves)
        return;
    printf("  moves       a moving nest: %d more placement%s\n", m->nmoves, m->nmoves == 1 ? "" : "s");
    for (int i = 0; i < m->nmoves; i++) {
        const vsv_move *v = &m->moves[i];
        char iso[40];
        double lat, lon;
        vsv_cal_format(vsv_meta_calendar(m), v->time, iso, sizeof iso);
        printf("              from %s", iso);
        if (m->proj.kind != VSV_PROJ_NONE && !vsv_proj_inverse(&m->proj, v->origin[0], v->origin[1], &lat, &lon))
            printf("  SW %.3f%c %.3f%c", fabs(lat), lat < 0 ? 'S' : 'N', fabs(lon), lon < 0 ? 'W' : 'E');
        printf("  (%+.0f, %+.0f cells)\n", (v->origin[0] - m->origin[0]) / m->spacing[0],
               (v->origin[1] - m->origin[1]) / m->spacing[1]);
    }
}

/* The steps' times (time(h, t) for t < nsteps, on m's calendar) and the
 * interval between them: of a .vsv file or of a model file. */
static void json_set_times(vsv_json *root, const vsv_meta *m, int64_t (*time)(const void *, int), const void *h,
                           int nsteps)
{
    char buf[64];
    vsv_json *times = vsv_json_array();
    for (int t = 0; t < nsteps; t++) {
        vsv_cal_format(vsv_meta_calendar(m), time(h, t), buf, sizeof buf);
        vsv_json_push(times, vsv_json_string(buf));
    }
    vsv_json_set(root, "times", times);
    /* the interval of regular steps, null when irregular or a single step */
    /* (differences checked: a file's times may lie anywhere in int64) */
    int64_t step = 0, d;
    if (nsteps > 1 && __builtin_sub_overflow(time(h, 1), time(h, 0), &step))
        step = 0;
    for (int t = 2; t < nsteps && step; t++)
        if (__builtin_sub_overflow(time(h, t), time(h, t - 1), &d) || d != step)
            step = 0;
    vsv_json_set(root, "time_step", step ? vsv_json_int(step) : vsv_json_null());
}

static int64_t file_time(const void *f, int t) { return vsv_file_time(f, t); }
static int64_t source_time(const void *s, int t) { return vsv_source_time(s, t); }

/* The vectors of m (SPEC.md §4 "Vectors"): to json (an object NAME: [east,
 * north, up], up null for a horizontal one) or printed when json is NULL. */
static void vectors(const vsv_meta *m, vsv_json *json)
{
    const size_t n = strlen(VSV_VECTOR_ATTR);
    for (int a = 0; a < m->nattrs; a++) {
        int idx[3];
        const char *name = m->attr_keys[a] + n;
        if (strncmp(m->attr_keys[a], VSV_VECTOR_ATTR, n) || vsv_meta_vector(m, name, idx))
            continue;
        if (json) {
            vsv_json *c = vsv_json_array();
            for (int d = 0; d < 3; d++)
                vsv_json_push(c, idx[d] < 0 ? vsv_json_null() : vsv_json_string(m->vars[idx[d]].name));
            vsv_json_set(json, name, c);
            continue;
        }
        printf("  vector      %s: %s %s%s%s (east, north%s; earth-relative)\n", name, m->vars[idx[0]].name,
               m->vars[idx[1]].name, idx[2] < 0 ? "" : " ", idx[2] < 0 ? "" : m->vars[idx[2]].name,
               idx[2] < 0 ? ": horizontal" : ", up");
    }
}

/* Each species: names, units, range and quantisation. */
static vsv_json *json_species(vsv_file *f)
{
    const vsv_meta *m = vsv_file_meta(f);
    vsv_json *species = vsv_json_array();
    for (int s = 0; s < m->nvars; s++) {
        const vsv_quant *q = vsv_file_quant(f, s);
        vsv_json *sj = vsv_json_object();
        vsv_json_set(sj, "name", vsv_json_string(m->vars[s].name));
        vsv_json_set(sj, "units", vsv_json_string(m->vars[s].units));
        vsv_json_set(sj, "description", vsv_json_string(m->vars[s].description));
        vsv_json_set(sj, "min_max_of", vsv_json_string(vsv_meta_attr(m, VSV_ATTR_RESAMPLED) ? "resampled" : "data"));
        vsv_json_set(sj, "min", vsv_json_number(q->data_min));
        vsv_json_set(sj, "max", vsv_json_number(q->data_max));
        vsv_json_set(sj, "bits", vsv_json_int(q->bits));
        vsv_json_set(sj, "scale", vsv_json_string(scale_name(q->scale)));
        vsv_json_set(sj, "max_abs_error", vsv_json_number(q->max_abs_error));
        vsv_json_set(sj, "no_data", vsv_json_bool(q->missing));
        vsv_json_set(sj, "range_lo", vsv_json_number(q->lo));
        vsv_json_set(sj, "range_hi", vsv_json_number(q->hi));
        if (m->tf && m->tf[s])
            vsv_json_set(sj, "transfer_function", vsv_json_string(m->tf[s]));
        vsv_json_push(species, sj);
    }
    return species;
}

/* --stats: min, max and mean of every (species, step), species by species. */
static vsv_json *json_stats(vsv_file *f, int nsteps, const stat_row *stats)
{
    const vsv_meta *m = vsv_file_meta(f);
    char buf[64];
    vsv_json *st = vsv_json_array();
    for (int s = 0; s < m->nvars; s++)
        for (int t = 0; t < nsteps; t++) {
            const stat_row *r = &stats[(size_t)s * nsteps + t];
            vsv_json *rj = vsv_json_object();
            vsv_json_set(rj, "species", vsv_json_string(m->vars[s].name));
            vsv_cal_format(vsv_meta_calendar(vsv_file_meta(f)), vsv_file_time(f, t), buf, sizeof buf);
            vsv_json_set(rj, "time", vsv_json_string(buf));
            vsv_json_set(rj, "min", vsv_json_number(r->min));
            vsv_json_set(rj, "max", vsv_json_number(r->max));
            vsv_json_set(rj, "mean", vsv_json_number(r->mean));
            vsv_json_push(st, rj);
        }
    return st;
}

static vsv_json *build_json(vsv_file *f, const char *path, const stat_row *stats)
{
    const vsv_meta *m = vsv_file_meta(f);
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    vsv_file_counts cnt;
    vsv_file_count(f, &cnt);
    vsv_json *root = vsv_json_object();
    char buf[64];
    vsv_json_set(root, "file", vsv_json_string(path));
    snprintf(buf, sizeof buf, "%d.%d", info.major, info.minor);
    vsv_json_set(root, "format_version", vsv_json_string(buf));
    json_set_place(root, m);
    json_set_moves(root, m);
    json_set_times(root, m, file_time, f, info.nsteps);
    vsv_json_set(root, "species", json_species(f));
    vsv_json *vec = vsv_json_object();
    vectors(m, vec);
    vsv_json_set(root, "vectors", vec);

    vsv_json *bricks = vsv_json_object();
    vsv_json_set(bricks, "size", vsv_json_int(info.brick));
    vsv_json *bd = vsv_json_array();
    for (int a = 0; a < 3; a++)
        vsv_json_push(bd, vsv_json_int(info.bricks[a]));
    vsv_json_set(bricks, "grid", bd);
    const long long total = (long long)info.nbricks * info.nspecies * info.nsteps;
    vsv_json_set(bricks, "stored", vsv_json_int((long long)cnt.stored_bricks));
    vsv_json_set(bricks, "rice_coded", vsv_json_int((long long)cnt.rice_bricks));
    vsv_json_set(bricks, "nonempty", vsv_json_int((long long)cnt.nonempty_bricks));
    vsv_json_set(bricks, "total", vsv_json_int(total));
    vsv_json_set(bricks, "octree_levels", vsv_json_int(info.octree_levels));
    vsv_json_set(root, "bricks", bricks);
    vsv_json_set(root, "keyframe_interval", vsv_json_int(info.keyframe));
    vsv_json_set(root, "codec", vsv_json_string(info.codec == VSV_CODEC_ZSTD ? "zstd" : "none"));
    vsv_json_set(root, "bytes", vsv_json_int((long long)info.file_bytes));
    /* up to 2^34 cells x 4 bytes x 1024 species x 10^7 steps: past int64, so
     * checked (and then null) */
    long long raw = (long long)m->nx * m->ny * m->nz * 4LL;
    const int raw_ok = !__builtin_mul_overflow(raw, (long long)m->nvars, &raw) &&
                       !__builtin_mul_overflow(raw, (long long)info.nsteps, &raw);
    vsv_json_set(root, "raw_bytes", raw_ok ? vsv_json_int(raw) : vsv_json_null());
    const double rawd = (double)m->nx * m->ny * m->nz * 4.0 * m->nvars * info.nsteps;
    vsv_json_set(root, "compression_ratio", vsv_json_number(round(rawd / (double)info.file_bytes * 100) / 100));
    if (m->nattrs) {
        vsv_json *attrs = vsv_json_object();
        for (int i = 0; i < m->nattrs; i++)
            vsv_json_set(attrs, m->attr_keys[i], vsv_json_string(m->attr_values[i]));
        vsv_json_set(root, "attributes", attrs);
    }
    if (stats)
        vsv_json_set(root, "stats", json_stats(f, info.nsteps, stats));
    return root;
}

static void human_bytes(double b, char *out, size_t cap)
{
    const char *u[] = {"B", "kB", "MB", "GB", "TB"};
    int i = 0;
    while (b >= 1000 && i < 4) {
        b /= 1000;
        i++;
    }
    snprintf(out, cap, i ? "%.1f %s" : "%.0f %s", b, u[i]);
}

static void print_human(vsv_file *f, const char *path, const stat_row *stats)
{
    const vsv_meta *m = vsv_file_meta(f);
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    vsv_file_counts cnt;
    vsv_file_count(f, &cnt);
    char a[64], b[64];
    human_bytes((double)info.file_bytes, a, sizeof a);
    printf("%s: .vsv format %d.%d, %s\n", path, info.major, info.minor, a);
    if (m->model[0] || m->run[0])
        printf("  source      %s%s%s\n", m->model, m->model[0] && m->run[0] ? " — " : "", m->run);
    printf("  grid        %d x %d x %d cells (x, y, z)\n", m->nx, m->ny, m->nz);
    const char *hu = m->proj.kind == VSV_PROJ_LATLON ? "deg" : "m";
    printf("  origin      x %.6g %s, y %.6g %s, z %.6g m (centre of the first cell)\n", m->origin[0], hu, m->origin[1],
           hu, m->origin[2]);
    printf("  spacing     dx %.6g %s, dy %.6g %s", m->spacing[0], hu, m->spacing[1], hu);
    if (m->vert_kind == VSV_VERT_EVEN)
        printf(", dz %.6g m\n", m->spacing[2]);
    else
        printf("\n");
    if (m->vert_kind == VSV_VERT_INDEX) {
        printf("  vertical    layer index (no heights: layers drawn evenly stacked)\n");
    } else if (m->levels) {
        printf("  vertical    %s levels (%s):", vert_name(m->vert_kind), m->vert_units[0] ? m->vert_units : "m");
        for (int k = 0; k < m->nz && k < 12; k++)
            printf(" %.6g", m->levels[k]);
        printf(m->nz > 12 ? " …\n" : "\n");
        if (m->nheights) {
            int enz;
            double z0, dz;
            vsv_heights_axis(m, &enz, &z0, &dz);
            printf("              per-column heights %s%s, %d record%s; drawn on %d even levels of %.0f m\n",
                   m->heights[0].form == VSV_HEIGHTS_MM5 ? "from MM5's formula over the terrain" : "stored",
                   m->nheights > 1 ? " (moving in time)" : "", m->nheights, m->nheights > 1 ? "s" : "", enz, dz);
        } else if (m->vert_kind == VSV_VERT_NATIVE) {
            printf("              mean heights only (format 1.0): drawn evenly stacked\n");
        }
    } else {
        printf("  vertical    even heights %.6g..%.6g m\n", m->origin[2], m->origin[2] + (m->nz - 1) * m->spacing[2]);
    }
    if (m->vert_kind == VSV_VERT_EVEN || m->vert_kind == VSV_VERT_NATIVE) {
        printf("              heights count from %s\n",
               vsv_meta_above_ground(m) ? "the ground (the model's, with no terrain under them)" : "sea level");
    }
    printf("  projection  %s", vsv_proj_name(m->proj.kind));
    if (m->proj.kind == VSV_PROJ_TMERC)
        printf(" (lat0 %.6g, central meridian %.6g, scale %.6g, R %.0f m)", m->proj.lat0, m->proj.lon0, m->proj.lat1,
               m->proj.radius > 0 ? m->proj.radius : 6370000.0);
    else if (m->proj.kind >= VSV_PROJ_LCC)
        printf(" (lat0 %.6g, lon0 %.6g, true lat %.6g/%.6g, R %.0f m)", m->proj.lat0, m->proj.lon0, m->proj.lat1,
               m->proj.lat2, m->proj.radius > 0 ? m->proj.radius : 6370000.0);
    printf("\n");
    if (m->proj.kind != VSV_PROJ_NONE) {
        printf("  corners    ");
        for (int c = 0; c < 4; c++) {
            double x, y, lat, lon;
            corner(m, c, &x, &y);
            if (!vsv_proj_inverse(&m->proj, x, y, &lat, &lon))
                printf(" %s %.3f%c %.3f%c", corner_names[c], fabs(lat), lat < 0 ? 'S' : 'N', fabs(lon),
                       lon < 0 ? 'W' : 'E');
        }
        printf("\n");
    }
    print_moves(m);
    if (m->terrain || m->landuse)
        printf("  surface     %s%s%s\n", m->terrain ? "terrain height" : "", m->terrain && m->landuse ? ", " : "",
               m->landuse ? "land use" : "");
    vsv_cal_format(vsv_meta_calendar(vsv_file_meta(f)), vsv_file_time(f, 0), a, sizeof a);
    vsv_cal_format(vsv_meta_calendar(vsv_file_meta(f)), vsv_file_time(f, info.nsteps - 1), b, sizeof b);
    printf("  times       %d step%s, %s", info.nsteps, info.nsteps == 1 ? "" : "s", a);
    if (info.nsteps > 1) {
        printf(" .. %s", b);
        int64_t dt = vsv_file_time(f, 1) - vsv_file_time(f, 0);
        int even = 1;
        for (int t = 2; t < info.nsteps && even; t++)
            even = vsv_file_time(f, t) - vsv_file_time(f, t - 1) == dt;
        char d[32];
        vsv_duration_format(dt, d, sizeof d);
        if (even)
            printf(", every %lld s (%s)", (long long)dt, d);
        else
            printf(", irregular steps");
    }
    printf("\n  species     %d\n", m->nvars);
    printf("    %-10s %-12s %12s %12s %5s %7s %12s  %s\n", "name", "units", "min", "max", "bits", "scale", "max error",
           "description");
    for (int s = 0; s < m->nvars; s++) {
        const vsv_quant *q = vsv_file_quant(f, s);
        char mn[32] = "no value", mx[32] = "no value"; /* (no finite value seen: every cell no data) */
        if (q->data_min <= q->data_max)
            snprintf(mn, sizeof mn, "%.5g", q->data_min), snprintf(mx, sizeof mx, "%.5g", q->data_max);
        printf("    %-10s %-12s %12s %12s %5d %7s %12.3g  %s\n", m->vars[s].name, m->vars[s].units, mn, mx, q->bits,
               scale_name(q->scale), q->max_abs_error, m->vars[s].description);
    }
    if (vsv_meta_attr(m, VSV_ATTR_RESAMPLED))
        printf("              min and max are of the values resampled onto even heights, not the model's own\n");
    vectors(m, NULL);
    const long long total = (long long)info.nbricks * info.nspecies * info.nsteps;
    printf("  bricks      %d^3, %d x %d x %d per step and species, %d octree levels\n", info.brick, info.bricks[0],
           info.bricks[1], info.bricks[2], info.octree_levels);
    printf("              %llu non-empty of %lld (%.1f %%); %llu payloads stored",
           (unsigned long long)cnt.nonempty_bricks, total,
           total ? 100.0 * (double)cnt.nonempty_bricks / (double)total : 0, (unsigned long long)cnt.stored_bricks);
    if (info.major >= 4)
        printf(", %llu of them Rice-coded", (unsigned long long)cnt.rice_bricks);
    printf("\n");
    printf("  keyframes   every %d steps; codec %s\n", info.keyframe, info.codec == VSV_CODEC_ZSTD ? "zstd" : "none");
    const double raw = (double)m->nx * m->ny * m->nz * 4.0 * m->nvars * info.nsteps;
    human_bytes(raw, a, sizeof a);
    human_bytes((double)info.file_bytes, b, sizeof b);
    printf("  size        %s of %s raw float32 (ratio %.2f)\n", b, a, raw / (double)info.file_bytes);
    for (int i = 0; i < m->nattrs; i++)
        printf("  %-11s %s\n", m->attr_keys[i], m->attr_values[i]);
    if (stats) {
        printf("  statistics\n    %-10s %-20s %12s %12s %12s\n", "species", "time", "min", "max", "mean");
        for (int s = 0; s < m->nvars; s++)
            for (int t = 0; t < info.nsteps; t++) {
                const stat_row *r = &stats[(size_t)s * info.nsteps + t];
                vsv_cal_format(vsv_meta_calendar(vsv_file_meta(f)), vsv_file_time(f, t), a, sizeof a);
                printf("    %-10s %-20s %12.5g %12.5g %12.5g\n", m->vars[s].name, a, r->min, r->max, r->mean);
            }
    }
}

/* Each of the n fields of root, a line each, when all are there; else
 * none, and the first missing. */
static const char *print_fields(const vsv_json *root, const char *const *fields, int n)
{
    for (int i = 0; i < n; i++)
        if (!vsv_json_path(root, fields[i]))
            return fields[i];
    for (int i = 0; i < n; i++)
        vsv_json_print_plain(stdout, vsv_json_path(root, fields[i]));
    return NULL;
}

/* A model file's JSON: its format, grid, projection, times and fields (the
 * keys of a .vsv file's where they mean the same), and its summary text. */
static vsv_json *model_json(const vsv_source *src, const char *path, const char *text)
{
    const vsv_meta *m = vsv_source_grid(src);
    vsv_json *root = vsv_json_object();
    vsv_json_set(root, "file", vsv_json_string(path));
    vsv_json_set(root, "format", vsv_json_string(vsv_source_format(src)));
    json_set_place(root, m);
    json_set_times(root, m, source_time, src, vsv_source_ntimes(src));
    vsv_json *fields = vsv_json_array();
    for (int i = 0; i < vsv_source_nfields(src); i++) {
        const vsv_field_info *fi = vsv_source_field(src, i);
        vsv_json *fj = vsv_json_object();
        vsv_json_set(fj, "name", vsv_json_string(fi->name));
        vsv_json_set(fj, "units", vsv_json_string(fi->units));
        vsv_json_set(fj, "description", vsv_json_string(fi->description));
        vsv_json_set(fj, "levels", vsv_json_int(fi->nlevels));
        vsv_json_set(fj, "volume", vsv_json_bool(fi->is_volume));
        vsv_json_set(fj, "default", vsv_json_bool(fi->is_default));
        vsv_json_set(fj, "role", fi->role[0] ? vsv_json_string(fi->role) : vsv_json_null());
        vsv_json_push(fields, fj);
    }
    vsv_json_set(root, "fields", fields);
    vsv_json_set(root, "summary", vsv_json_string(text ? text : ""));
    return root;
}

/* path, not a .vsv file, as a model file: 1 when described (2 when a
 * field of -f is missing), -1 when said why not (a damaged model file, or
 * a file of no format known), 0 when the caller's to say (unreadable). */
static int model_file(const char *path, int json, const char *const *fields, int nfields)
{
    vsv_source *src = NULL;
    const int src_rc = vsv_source_open(path, NULL, &src);
    int r = 0;
    if (src_rc == 0) {
        char *text = vsv_source_summary(src);
        r = 1;
        if (json || nfields) {
            vsv_json *root = model_json(src, path, text);
            const char *none = nfields ? print_fields(root, fields, nfields) : NULL;
            if (!nfields)
                vsv_json_print(stdout, root, 1);
            else if (none) {
                fprintf(stderr, "vsv-info: -f %s: no such field (see vsv-info --json %s)\n", none, path);
                r = 2;
            }
            vsv_json_free(root);
        } else if (text) {
            printf("%s: %s", path, text);
        } else { /* a reader without a summary of its own */
            printf("%s: %s (vsv-extract --list shows its fields and times)\n", path, vsv_source_format(src));
        }
        free(text);
    } else if (src_rc != VSV_EIO) {
        /* a model file, damaged (its reader's message, not ".vsv"), or neither: both readers' words */
        const char *e = vsv_source_error(src);
        const size_t pl = strlen(path);
        if (src_rc == VSV_ENOTVSV && !strncmp(e, path, pl) && !strncmp(e + pl, ": ", 2))
            e += pl + 2;
        fflush(stdout);
        if (src_rc == VSV_ENOTVSV)
            fprintf(stderr, "vsv-info: %s: not a .vsv file; %s\n", path, e);
        else
            fprintf(stderr, "vsv-info: %s\n", e);
        r = -1;
    }
    vsv_source_free(src);
    return r;
}

int main(int argc, char **argv)
{
    vsv_cli_init("vsv-info");
    vsv_vdb_source_register(); /* .vdb files too (interop/) */
    /* clang-format off */ /* (a table, laid out by hand) */
    static const struct option longopts[] = {{"json", no_argument, 0, 'j'},  {"field", required_argument, 0, 'f'},
                                             {"stats", no_argument, 0, 's'}, {"check", no_argument, 0, 'c'},
                                             {"quiet", no_argument, 0, 'q'}, {"help", no_argument, 0, 'h'},
                                             {"cache-dir", required_argument, 0, VSV_CLI_CACHE_DIR},
                                             {"version", no_argument, 0, 'V'}, {0, 0, 0, 0}};
    /* clang-format on */
    int json = 0, want_stats = 0, check = 0, c, nfields = 0;
    const char *fields[64], *field = NULL; /* (field: the first, or none) */
    argv[0] = (char *)vsv_cli_tool();      /* getopt's messages name the tool as ours do */
    while ((c = getopt_long(argc, argv, "jf:scqhV", longopts, NULL)) != -1) {
        switch (c) {
        case 'j': json = 1; break;
        case 'f':
            if (nfields == 64)
                vsv_cli_usage_error("-f %s: at most 64 fields", optarg);
            fields[nfields++] = optarg, field = fields[0];
            break;
        case 's': want_stats = 1; break;
        case 'c': check = 1; break;
        case 'q': vsv_cli_set_quiet(1); break;
        case VSV_CLI_CACHE_DIR: vsv_cli_cache_dir(optarg); break;
        case 'h': fputs(usage, stdout); return 0;
        case 'V': vsv_cli_version();
        default: vsv_cli_getopt_failed();
        }
    }
    if (optind >= argc)
        vsv_cli_usage_error("no input file");
    int status = 0;
    for (int i = optind; i < argc; i++) {
        const char *path = argv[i];
        vsv_file *f = NULL;
        int rc = vsv_file_open_any(path, &vsv_cli_http, &f);
        if (rc == VSV_ENOTVSV && !check && !vsv_is_url(path)) {
            const int mrc = model_file(path, json, fields, nfields);
            if (mrc) { /* described, or said why not */
                status = mrc < 0 ? 1 : mrc == 2 ? 2 : status;
                vsv_file_free(f);
                continue;
            }
        }
        if (rc) {
            fflush(stdout);
            fprintf(stderr, "vsv-info: %s\n", vsv_file_error(f));
            vsv_file_free(f);
            status = 1;
            continue;
        }
        if (check) {
            if (vsv_file_check(f, vsv_cli_progress, (void *)path)) {
                fflush(stdout);
                fprintf(stderr, "vsv-info: %s\n", vsv_file_error(f));
                status = 1;
            } else if (!json && !field && !want_stats) {
                vsv_file_info info;
                vsv_file_info_get(f, &info);
                vsv_file_counts cnt;
                vsv_file_count(f, &cnt);
                printf("%s: ok (%d chunks, %llu payloads verified, %llu bytes)\n", path, info.nsteps,
                       (unsigned long long)cnt.stored_bricks, (unsigned long long)info.file_bytes);
            }
            if (status || (!json && !field && !want_stats)) {
                vsv_file_free(f);
                continue;
            }
        }
        vsv_file_info di;
        vsv_file_info_get(f, &di);
        vsv_file_counts dc;
        vsv_file_count(f, &dc);
        if (dc.damaged_chunks) {
            fflush(stdout);
            fprintf(stderr, "vsv-info: %s (%d of %d chunks damaged)\n", vsv_file_error(f), dc.damaged_chunks,
                    di.nsteps);
            vsv_file_free(f);
            status = 1;
            continue;
        }
        stat_row *stats = want_stats ? compute_stats(f, path) : NULL;
        if (json || field) {
            vsv_json *root = build_json(f, path, stats);
            if (!root)
                vsv_cli_die(1, "out of memory");
            if (field) {
                const char *none = print_fields(root, fields, nfields);
                if (none) {
                    vsv_json_free(root);
                    vsv_cli_usage_error("-f %s: no such field (see vsv-info --json)", none);
                }
            } else {
                vsv_json_print(stdout, root, 1);
            }
            vsv_json_free(root);
        } else {
            print_human(f, path, stats);
        }
        free(stats);
        vsv_file_free(f);
    }
    vsv_cli_stdout_done();
    return status;
}
