/* vsv_cli_http.c — the URL options of the tools that read a .vsv (their
 * own object, so the tools that never read URLs do not link libcurl). */
#include "vsv_cli.h"

vsv_http_opts vsv_cli_http = {NULL, 0, -1, 0, 0};

void vsv_cli_cache_dir(const char *dir)
{
    char why[4200];
    if (vsv_http_cache_dir_make(dir, why, sizeof why))
        vsv_cli_die(1, "--cache-dir %s: %s", dir, why);
    vsv_cli_http.cache_dir = dir;
}
