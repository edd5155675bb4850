/* vsv-nc-check.c — the private helper (installed in $(libdir)/vesuvius/,
 * started by vsv_nc_guard.c, never by hand) that opens a netCDF-4/HDF5 file
 * and reads every variable, so that a damaged file crashing libhdf5 kills
 * this process, not the tool. Usage: vsv-nc-check FILE SECONDS. Exit 0 when
 * everything read; 1 with the library's error, saying where, on stdout; a
 * crash or SIGALRM (SECONDS of wall clock) is seen by the caller as a
 * signal. */
#include <netcdf.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* In a sanitizer build a memory error inside the library is a crash like
 * any other: abort after the report, so the caller sees a signal. */
__attribute__((visibility("default"), used)) const char *__asan_default_options(void);
const char *__asan_default_options(void) { return "abort_on_error=1:detect_leaks=0"; }

/* A slab larger than this is not read by the check (its metadata still is). */
#define SLAB_MAX ((size_t)256 << 20)

/* Opens path and reads every variable slab by slab along its first
 * dimension. 0, or an error in msg saying where. */
static int read_all(const char *path, char *msg, size_t cap)
{
    int nc, rc = nc_open(path, NC_NOWRITE, &nc);
    if (rc) {
        snprintf(msg, cap, "netCDF: %s (opening it)", nc_strerror(rc));
        return 1;
    }
    int nvars = 0;
    if ((rc = nc_inq_nvars(nc, &nvars))) {
        snprintf(msg, cap, "netCDF: %s (listing its variables)", nc_strerror(rc));
        return 1;
    }
    for (int v = 0; v < nvars; v++) {
        char name[NC_MAX_NAME + 1] = "?";
        int nd = 0, dims[NC_MAX_VAR_DIMS];
        nc_type type;
        size_t esize = 0;
        if ((rc = nc_inq_var(nc, v, name, &type, &nd, dims, NULL)) || (rc = nc_inq_type(nc, type, NULL, &esize))) {
            snprintf(msg, cap, "netCDF: %s (variable %d %s)", nc_strerror(rc), v, name);
            return 1;
        }
        if (type > NC_MAX_ATOMIC_TYPE || type == NC_STRING || nd > 32)
            continue; /* user-defined and string types: metadata only */
        size_t len[32], start[32] = {0}, count[32], slab = esize;
        for (int d = 0; d < nd; d++) {
            if ((rc = nc_inq_dimlen(nc, dims[d], &len[d]))) {
                snprintf(msg, cap, "netCDF: %s (variable %s, dimension %d)", nc_strerror(rc), name, d);
                return 1;
            }
            count[d] = d ? len[d] : 1;
            if (d)
                slab = len[d] && slab > SLAB_MAX / len[d] ? SLAB_MAX + 1 : slab * len[d];
        }
        const size_t nslabs = nd ? len[0] : 1;
        if (slab > SLAB_MAX || slab == 0)
            continue;
        void *buf = malloc(slab);
        if (!buf) {
            snprintf(msg, cap, "out of memory (variable %s)", name);
            return 1;
        }
        for (size_t i = 0; i < nslabs; i++) {
            start[0] = i;
            rc = nd ? nc_get_vara(nc, v, start, count, buf) : nc_get_var(nc, v, buf);
            if (rc) {
                snprintf(msg, cap, "netCDF: %s (variable %s, record %zu)", nc_strerror(rc), name, i);
                free(buf);
                return 1;
            }
        }
        free(buf);
    }
    nc_close(nc);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "vsv-nc-check: a helper of the Vesuvius tools, not run by hand\n");
        return 2;
    }
    /* a crash must end this process by its signal (the caller reports it),
     * whatever a sanitizer installed at start */
    static const int sigs[] = {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL, SIGALRM};
    for (size_t i = 0; i < sizeof sigs / sizeof *sigs; i++)
        signal(sigs[i], SIG_DFL);
    alarm((unsigned)atoi(argv[2]));
    char msg[400] = "";
    const int bad = read_all(argv[1], msg, sizeof msg);
    if (bad) {
        const ssize_t w = write(1, msg, strlen(msg));
        (void)w;
    }
    /* no exit handlers: a leak checker's report would change the status */
    _exit(bad);
}
