/* vsv_nc_guard.c — netCDF-4 files are HDF5 files, and libhdf5 can crash on
 * a damaged one (a one-bit flip can kill nc_open; ncdump dies too). Before a
 * reader opens such a file, the helper program vsv-nc-check (exec'd, so
 * safe in a process with threads: vsv_helper.c) opens it and reads every
 * variable; the caller only learns whether that worked, failed (with the
 * library's error and the variable), crashed, or ran past a time limit. A
 * crash is then an error naming the file, never the death of the tool. The
 * library is deterministic, so bytes the helper read whole the caller reads
 * the same way. */
#include "vsv_source_internal.h"

#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/wait.h>

int vsv_nc_guard(vsv_source *s, int limit_s)
{
    char secs[16], msg[400] = "", why[600] = "";
    snprintf(secs, sizeof secs, "%d", limit_s);
    char *argv[] = {"vsv-nc-check", s->path, secs, NULL};
    int st = 0;
    char where[4200];
    if (vsv_helper_path("vsv-nc-check", where, sizeof where)) /* an incomplete install */
        return vsv_source_fail(s, VSV_EUNSUPPORTED,
                               "cannot check the netCDF-4/HDF5 file: cannot find the helper "
                               "program vsv-nc-check (VSV_HELPER_DIR, beside the program, or its lib/vesuvius/)");
    /* the helper stops itself after limit_s (SIGALRM); the wall-clock limit
     * here is for a helper that cannot */
    const int r = vsv_helper_run("vsv-nc-check", argv, -1, limit_s + 5, msg, sizeof msg, &st, why, sizeof why);
    if (r < 0)
        return vsv_source_fail(s, VSV_EIO, "cannot check the netCDF-4/HDF5 file: %s", why);
    if (r > 0 || (WIFSIGNALED(st) && WTERMSIG(st) == SIGALRM))
        return vsv_source_fail(s, VSV_ECORRUPT, "reading it as netCDF-4/HDF5 took more than %d s: stopped", limit_s);
    if (WIFSIGNALED(st))
        return vsv_source_fail(s, VSV_ECORRUPT, "damaged netCDF-4/HDF5 file: the HDF5 library crashed reading it (%s)",
                               strsignal(WTERMSIG(st)));
    if (!WIFEXITED(st) || WEXITSTATUS(st)) {
        if (msg[0])
            return vsv_source_fail(s, VSV_ECORRUPT, "%s", msg);
        return vsv_source_fail(s, VSV_ECORRUPT,
                               "damaged netCDF-4/HDF5 file: the HDF5 library failed reading it "
                               "(its checker exited with status %d)",
                               WIFEXITED(st) ? WEXITSTATUS(st) : -1);
    }
    return 0;
}
