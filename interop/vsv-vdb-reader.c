/* vsv-vdb-reader.c — the private helper (installed in $(libdir)/vesuvius/,
 * started by vsv_vdb_isolate.cc, never by hand) that reads and writes .vdb
 * files, the one program that loads OpenVDB: a damaged file crashing it
 * kills this process, not the tool, and no tool loads its logging library
 * (which aborts before main under a small address-space limit). */
#include "vsv_vdb_internal.h"

#include <stdio.h>
#include <unistd.h>

/* In a sanitizer build a memory error inside the library is a crash like
 * any other: abort after the report, so the caller sees a signal. */
__attribute__((visibility("default"), used)) const char *__asan_default_options(void);
const char *__asan_default_options(void) { return "abort_on_error=1:detect_leaks=0"; }

int main(int argc, char **argv)
{
    const int rc = vsv_vdb_helper_main(argc, argv);
    if (rc == 2)
        fprintf(stderr, "vsv-vdb-reader: a helper of the Vesuvius tools, not run by hand\n");
    /* no exit handlers: a leak checker's report would change the status */
    fflush(NULL);
    _exit(rc);
}
