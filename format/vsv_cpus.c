/* vsv_cpus.c — the number of CPUs online, the default thread count of the
 * writer, the pager and the renderers. */
#include "vsv_format_internal.h"

#include <unistd.h>

int vsv_ncpus(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : (int)n;
}
