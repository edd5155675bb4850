/* vsv-gshhg.c — the private helper (installed in $(libdir)/vesuvius/,
 * started by vsv_outlines.c, never by hand) that reads the segments of a
 * GSHHG binned netCDF file (Debian's gmt-gshhg-low: binned_GSHHS_R.nc,
 * binned_border_R.nc) whose bins meet a latitude/longitude box, so that
 * libhdf5 failing under it (a damaged file, or an address-space limit it
 * does not survive: it dereferences a failed allocation) kills this
 * process, not the tool that draws the map.
 *
 * Usage: vsv-gshhg FILE BORDER S N W E SECONDS (BORDER 0 shorelines, 1
 * borders; the box in degrees, W..E possibly past 180). On stdout, in this
 * machine's byte order, one record per segment drawn: i32 kind
 * (VSV_OUTLINE_*), i32 n, f64 longitude and f64 latitude of its bin's
 * south-west corner, f64 degrees per unit, then n u16 longitude and n u16
 * latitude offsets; the end as i32 0, i32 -1; or, on an error, i32 -1, i32
 * length and that many bytes of message saying where, exit 1. A crash or
 * SIGALRM (SECONDS of wall clock) is seen by the caller as a signal.
 *
 * Both files cut the world into square bins (Bin_size_in_minutes; bin b has
 * its south-west corner at longitude (b mod nx) * size, latitude 90 -
 * (b / nx + 1) * size); a bin lists its segments, a segment its points as
 * unsigned 16-bit offsets from that corner in 1/65535 of the bin size. A
 * shore segment's Embedded_npts_levels_exit_entry word holds its point count
 * (bits 9 up) and level (bits 6-8). */
#include "vsv_render.h"

#include <math.h>
#include <netcdf.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* In a sanitizer build a memory error inside the library is a crash like
 * any other: abort after the report, so the caller sees a signal. */
__attribute__((visibility("default"), used)) const char *__asan_default_options(void);
const char *__asan_default_options(void) { return "abort_on_error=1:detect_leaks=0"; }

static char out[1 << 16];
static size_t nout;

static void put(const void *p, size_t n)
{
    const char *c = p;
    while (n) {
        if (nout == sizeof out) {
            for (size_t d = 0; d < nout;) {
                const ssize_t w = write(1, out + d, nout - d);
                if (w <= 0)
                    _exit(3); /* the caller went away */
                d += (size_t)w;
            }
            nout = 0;
        }
        size_t k = sizeof out - nout < n ? sizeof out - nout : n;
        memcpy(out + nout, c, k);
        nout += k, c += k, n -= k;
    }
}

static void flush_out(void)
{
    for (size_t d = 0; d < nout;) {
        const ssize_t w = write(1, out + d, nout - d);
        if (w <= 0)
            _exit(3);
        d += (size_t)w;
    }
    nout = 0;
}

/* An error record, then exit 1 (no exit handlers: a leak checker's report
 * would change the status). */
static void die(const char *path, const char *what, int nc_rc)
{
    char msg[600];
    const int n =
        snprintf(msg, sizeof msg, "%s: %s%s%s", path, what, nc_rc ? ": " : "", nc_rc ? nc_strerror(nc_rc) : "");
    const int32_t head[2] = {-1, n < (int)sizeof msg ? n : (int)sizeof msg - 1};
    put(head, sizeof head);
    put(msg, (size_t)head[1]);
    flush_out();
    _exit(1);
}

static void *grab(size_t n, size_t size, const char *path)
{
    void *p = malloc((n + 1) * size);
    if (!p)
        die(path, "out of memory", 0);
    return p;
}

static int get_int(int nc, const char *name, int *v)
{
    int id;
    const size_t at = 0;
    int rc = nc_inq_varid(nc, name, &id);
    return rc ? rc : nc_get_var1_int(nc, id, &at, v);
}

static void get_ints(int nc, const char *path, const char *name, size_t count, int *v)
{
    int id, rc = nc_inq_varid(nc, name, &id);
    const size_t start = 0;
    if (rc || (count && (rc = nc_get_vara_int(nc, id, &start, &count, v))))
        die(path, name, rc);
}

static void get_shorts(int nc, const char *path, const char *name, size_t count, short *v)
{
    int id, rc = nc_inq_varid(nc, name, &id);
    const size_t start = 0;
    if (rc || (count && (rc = nc_get_vara_short(nc, id, &start, &count, v))))
        die(path, name, rc);
}

/* The kind a segment is drawn as (0: not drawn) and its point count. */
static int segment(int border, const int *sinfo, const short *slev, const short *sn, int k, int *count)
{
    if (border) {
        *count = sn[k];
        return slev[k] == 1 ? VSV_OUTLINE_BORDER : slev[k] == 2 ? VSV_OUTLINE_STATE : 0;
    }
    const int level = (sinfo[k] >> 6) & 7; /* 5, 6: Antarctica's grounding line, drawn as its ice front (1) */
    *count = (int)((unsigned)sinfo[k] >> 9);
    return level == 1 ? VSV_OUTLINE_COAST : level >= 2 && level <= 4 ? VSV_OUTLINE_LAKE : 0;
}

static void read_binned(const char *path, int border, const double box[4])
{
    int nc, rc, nsegs = 0, npts = 0, bsize = 0, bin_nx = 0, bin_ny = 0, nbins = 0;
    if ((rc = nc_open(path, NC_NOWRITE, &nc)))
        die(path, "cannot open", rc);
    if ((rc = get_int(nc, "Bin_size_in_minutes", &bsize)) ||
        (rc = get_int(nc, "N_bins_in_360_longitude_range", &bin_nx)) ||
        (rc = get_int(nc, "N_bins_in_180_degree_latitude_range", &bin_ny)) ||
        (rc = get_int(nc, "N_bins_in_file", &nbins)) || (rc = get_int(nc, "N_segments_in_file", &nsegs)) ||
        (rc = get_int(nc, "N_points_in_file", &npts)))
        die(path, "not a GSHHG binned file (its sizes)", rc);
    if (bsize <= 0 || bsize > 10800 || bin_nx * bsize != 21600 || bin_ny * bsize != 10800 || nbins != bin_nx * bin_ny ||
        nsegs < 0 || npts < 0 || nsegs > 100000000 || npts > 500000000)
        die(path, "not a GSHHG binned file (its bins)", 0);
    int *first = grab((size_t)nbins, sizeof(int), path), *sfirst = grab((size_t)nsegs, sizeof(int), path);
    short *nseg = grab((size_t)nbins, sizeof(short), path);
    int *sinfo = border ? NULL : grab((size_t)nsegs, sizeof(int), path);
    short *slev = border ? grab((size_t)nsegs, sizeof(short), path) : NULL;
    short *sn = border ? grab((size_t)nsegs, sizeof(short), path) : NULL;
    short *dx = grab((size_t)npts, sizeof(short), path), *dy = grab((size_t)npts, sizeof(short), path);
    get_ints(nc, path, "Id_of_first_segment_in_a_bin", (size_t)nbins, first);
    get_shorts(nc, path, "N_segments_in_a_bin", (size_t)nbins, nseg);
    get_ints(nc, path, "Id_of_first_point_in_a_segment", (size_t)nsegs, sfirst);
    if (border) {
        get_shorts(nc, path, "N_points_for_a_segment", (size_t)nsegs, sn);
        get_shorts(nc, path, "Hierarchial_level_of_a_segment", (size_t)nsegs, slev);
    } else
        get_ints(nc, path, "Embedded_npts_levels_exit_entry_for_a_segment", (size_t)nsegs, sinfo);
    get_shorts(nc, path, "Relative_longitude_from_SW_corner_of_bin", (size_t)npts, dx);
    get_shorts(nc, path, "Relative_latitude_from_SW_corner_of_bin", (size_t)npts, dy);
    const double size = bsize / 60.0, scale = size / 65535.0;
    for (int b = 0; b < nbins; b++) {
        const double lon_sw = (b % bin_nx) * size, lat_sw = 90 - (b / bin_nx + 1) * size;
        if (lat_sw > box[1] || lat_sw + size < box[0])
            continue;
        /* the bin's copy nearest the box in longitude */
        const double lw = box[2] + fmod(fmod(lon_sw - box[2], 360) + 360, 360);
        if (lw > box[3] && lw + size - 360 < box[2])
            continue;
        char where[160];
        if (nseg[b] < 0 || first[b] < 0 || first[b] + nseg[b] > nsegs) {
            snprintf(where, sizeof where, "bin %d: segments %d..%d outside the file's %d", b, first[b],
                     first[b] + nseg[b], nsegs);
            die(path, where, 0);
        }
        for (int k = first[b]; k < first[b] + nseg[b]; k++) {
            int count;
            const int kind = segment(border, sinfo, slev, sn, k, &count);
            if (!kind)
                continue;
            if (count < 0 || sfirst[k] < 0 || (int64_t)sfirst[k] + count > npts) {
                snprintf(where, sizeof where, "segment %d: points %d..%lld outside the file's %d", k, sfirst[k],
                         (long long)sfirst[k] + count, npts);
                die(path, where, 0);
            }
            const int32_t head[2] = {kind, count};
            const double corner[3] = {lon_sw, lat_sw, scale};
            put(head, sizeof head);
            put(corner, sizeof corner);
            put(dx + sfirst[k], (size_t)count * sizeof *dx);
            put(dy + sfirst[k], (size_t)count * sizeof *dy);
        }
    }
    const int32_t end[2] = {0, -1};
    put(end, sizeof end);
    flush_out();
}

int main(int argc, char **argv)
{
    double box[4];
    char *end;
    if (argc != 8) {
        fprintf(stderr, "vsv-gshhg: a helper of the Vesuvius tools, not run by hand\n");
        return 2;
    }
    for (int i = 0; i < 4; i++)
        if (box[i] = strtod(argv[3 + i], &end), *end || !isfinite(box[i]))
            return 2;
    /* a crash must end this process by its signal (the caller reports it),
     * whatever a sanitizer installed at start */
    static const int sigs[] = {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL, SIGALRM};
    for (size_t i = 0; i < sizeof sigs / sizeof *sigs; i++)
        signal(sigs[i], SIG_DFL);
    alarm((unsigned)atoi(argv[7]));
    read_binned(argv[1], atoi(argv[2]) != 0, box);
    _exit(0);
}
