/* test_input_cut.c — model inputs truncated while they are read (another
 * program cuts the file after it was mapped; issue 33: SIGBUS in
 * vsv_mm5_read). Every mapped model reader gives VSV_ETRUNC with "PATH:
 * truncated while reading", never a crash and never zeros as values: the
 * MM5 reader and the MM5 source past the cut (a SIGBUS the guard turns into
 * zeros), a small field in the rest of the page at the new end (zeros
 * without a signal: the file's size says so), the CAMx UAM-IV reader and a
 * CAMx met file (files under a page); and the netCDF sources (WRF, IOAPI,
 * CF; classic and netCDF-4), which libnetcdf reads. No timing: each file is
 * cut in process, between the open and the read. */
#include "vsv_convert.h"
#include "vsv_mm5.h"
#include "vsv_testlib.h"
#include "vsv_uamiv.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char MM5[] = "samples/mm5/MMOUT_DOMAIN1_CROP";
static const char CUT[] = "truncated while reading (the file shrank after it was opened)";

/* A scratch copy of a test input (src: a path from the checkout's root);
 * NULL (a SKIP printed) when it is absent. */
static const char *copy_of(const char *src, const char *name, size_t *size)
{
    if (vsv_test_absent(src, src))
        return NULL;
    unsigned char *b = vsv_test_slurp(src, size);
    const char *dst = vsv_test_tmp(name);
    const int ok = b && !vsv_test_write(dst, b, *size);
    free(b);
    return ok ? dst : NULL;
}

/* 1 when msg is "path: " followed by the truncation text. */
static int says_cut(const char *msg, const char *path)
{
    const size_t n = strlen(path);
    return !strncmp(msg, path, n) && !strncmp(msg + n, ": ", 2) && !strcmp(msg + n + 2, CUT);
}

static void test_mm5(void)
{
    size_t size;
    const char *path = copy_of(MM5, "cut.mm5", &size);
    if (!path)
        return;
    vsv_mm5 *m = NULL;
    if (!CHECK(vsv_mm5_open(path, &m) == 0, "MM5: open the copy", "%s", vsv_mm5_error(m)))
        goto done;
    const vsv_mm5_field *last = vsv_mm5_field_at(m, vsv_mm5_nfields(m) - 1);
    float *buf = malloc(last->bytes);
    if (!CHECK(buf && truncate(path, (off_t)(size / 3)) == 0, "MM5: cut it to a third"))
        goto done_buf;
    const int rc = vsv_mm5_read(m, last, buf);
    CHECK(rc == VSV_ETRUNC, "MM5: a field past the cut is VSV_ETRUNC (it was SIGBUS)", "rc %d", rc);
done_buf:
    free(buf);
done:
    vsv_mm5_free(m);
}

/* A field that fits in the rest of a page, the file cut at its first byte:
 * its bytes read zeros with no signal, and only the file's size tells. */
static void test_mm5_page_tail(void)
{
    size_t size;
    const char *path = copy_of(MM5, "tail.mm5", &size);
    if (!path)
        return;
    vsv_mm5 *m = NULL;
    const long page = sysconf(_SC_PAGESIZE);
    const vsv_mm5_field *f = NULL;
    if (!CHECK(vsv_mm5_open(path, &m) == 0, "MM5: open a second copy", "%s", vsv_mm5_error(m)))
        goto done;
    for (int i = 0; i < vsv_mm5_nfields(m) && !f; i++) {
        const vsv_mm5_field *g = vsv_mm5_field_at(m, i);
        if (g->offset % (uint64_t)page && g->offset % (uint64_t)page + g->bytes <= (uint64_t)page)
            f = g;
    }
    if (!CHECK(f, "MM5: a field inside one page"))
        goto done;
    float buf[1024];
    if (!CHECK(f->bytes <= sizeof buf && truncate(path, (off_t)f->offset) == 0, "MM5: cut at that field",
               "%s, %llu bytes", f->name, (unsigned long long)f->bytes))
        goto done;
    const int rc = vsv_mm5_read(m, f, buf);
    CHECK(rc == VSV_ETRUNC, "MM5: a field in the page's tail past the cut is VSV_ETRUNC (it was zeros)", "rc %d (%s)",
          rc, f->name);
done:
    vsv_mm5_free(m);
}

static void test_uamiv(void)
{
    size_t size;
    const char *path = copy_of(vsv_test_shared("camx/test.uamiv"), "cut.uamiv", &size);
    if (!path)
        return;
    vsv_uamiv *u = NULL;
    if (!CHECK(vsv_uamiv_open(path, &u) == 0, "UAM-IV: open", "%s", vsv_uamiv_error(u)))
        goto done;
    const vsv_uamiv_header *h = vsv_uamiv_header_get(u);
    float *plane = malloc((size_t)h->nx * h->ny * sizeof *plane);
    if (!CHECK(plane && truncate(path, (off_t)(size / 3)) == 0, "UAM-IV: cut it to a third"))
        goto done_plane;
    const int rc = vsv_uamiv_read(u, h->nhours - 1, h->nspec - 1, h->nz - 1, plane);
    CHECK(rc == VSV_ETRUNC && says_cut(vsv_uamiv_error(u), path),
          "UAM-IV: the last plane past the cut is VSV_ETRUNC, named", "rc %d: %s", rc, vsv_uamiv_error(u));
done_plane:
    free(plane);
done:
    vsv_uamiv_free(u);
}

static void test_camxmet(void)
{
    size_t size;
    const char *path = copy_of(vsv_test_shared("camx/test.height_pressure"), "cut.height_pressure", &size);
    if (!path)
        return;
    vsv_camxmet *m = NULL;
    float h[5 * 4 * 3];
    if (!CHECK(vsv_camxmet_open(path, VSV_MET_ZP, 5, 4, 3, "the average file", &m) == 0, "CAMx met: open", "%s",
               vsv_camxmet_error(m)))
        goto done;
    if (!CHECK(truncate(path, (off_t)(size / 3)) == 0, "CAMx met: cut it to a third"))
        goto done;
    const int rc = vsv_camxmet_heights(m, vsv_camxmet_nhours(m) - 1, h);
    CHECK(rc == VSV_ETRUNC && says_cut(vsv_camxmet_error(m), path),
          "CAMx met: the last hour's heights past the cut are VSV_ETRUNC, named", "rc %d: %s", rc,
          vsv_camxmet_error(m));
done:
    vsv_camxmet_free(m);
}

/* A model source (src: a path from the checkout's root) opened, cut to
 * 1/part of its size, then its first field's last time read: VSV_ETRUNC,
 * "PATH: " then the truncation text, or (what non-NULL) "PATH: " what ...
 * the truncation text. */
static void test_source(const char *src, const char *name, int part, const char *what)
{
    size_t size;
    const char *path = copy_of(src, name, &size);
    if (!path)
        return;
    vsv_source_opts o;
    vsv_source_opts_init(&o);
    vsv_source *s = NULL;
    float *vol = NULL;
    if (!CHECK(vsv_source_open(path, &o, &s) == 0, "source: open", "%s: %s", name, vsv_source_error(s)))
        goto done;
    const vsv_meta *g = vsv_source_grid(s);
    vol = malloc((size_t)g->nx * g->ny * g->nz * sizeof *vol);
    if (!CHECK(vol && truncate(path, (off_t)(size / (size_t)part)) == 0, "source: cut it", "%s", name))
        goto done;
    const int rc = vsv_source_read(s, 0, vsv_source_ntimes(s) - 1, vol);
    const char *e = vsv_source_error(s);
    const size_t n = strlen(path), ne = strlen(e), nc = strlen(CUT);
    const int ok = what ? !strncmp(e, path, n) && !strncmp(e + n, ": ", 2) && !strncmp(e + n + 2, what, strlen(what)) &&
                              ne > nc && !strcmp(e + ne - nc, CUT)
                        : says_cut(e, path);
    CHECK(rc == VSV_ETRUNC && ok, "source: the last time after the cut is VSV_ETRUNC, named (netCDF: it was zeros)",
          "%s: rc %d: %s", name, rc, e);
done:
    free(vol);
    vsv_source_free(s);
}

int main(void)
{
    test_mm5();
    test_mm5_page_tail();
    test_source(MM5, "src.mm5", 2, NULL);
    test_uamiv();
    test_camxmet();
    /* libnetcdf: WRF, IOAPI and CF classic files, a netCDF-4 WRF file */
    test_source("tests/corpus/netcdf/wrf-crop.nc", "cut-wrf.nc", 3, "reading variable ");
    test_source("tests/corpus/netcdf/ioapi-cmaq.nc", "cut-ioapi.nc", 3, "reading variable ");
    test_source("tests/corpus/netcdf/contour-crop.nc", "cut-cf.nc", 3, "reading variable ");
    test_source(vsv_test_shared("wrf/katrina_ci_test_file.nc"), "cut-katrina.nc", 3, "reading variable ");
    return vsv_test_done();
}
