/* vsv-nc-writer.c — the private helper (installed in $(libdir)/vesuvius/,
 * started by vsv_cf_write in vsv_cfwrite.c, never by hand) that writes a
 * netCDF export, so that libhdf5 crashing on a failed write (a full disk)
 * kills this process, not the tool. */
#include "vsv_cf_internal.h"

#include <stdio.h>
#include <unistd.h>

/* In a sanitizer build a memory error inside the library is a crash like
 * any other: abort after the report, so the caller sees a signal. */
__attribute__((visibility("default"), used)) const char *__asan_default_options(void);
const char *__asan_default_options(void) { return "abort_on_error=1:detect_leaks=0"; }

int main(int argc, char **argv)
{
    const int rc = vsv_cf_helper_main(argc, argv);
    if (rc == 2)
        fprintf(stderr, "vsv-nc-writer: a helper of the Vesuvius tools, not run by hand\n");
    /* no exit handlers: libhdf5's would close a file whose write failed
     * (and crash), a leak checker's report would change the status */
    fflush(NULL);
    _exit(rc);
}
