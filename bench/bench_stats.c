/* bench_stats.c — median and range of a benchmark's rounds. */
#include "bench_stats.h"

#include <stdlib.h>

static int cmp(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

void bench_stats(double *v, int n, double out[3])
{
    qsort(v, (size_t)n, sizeof *v, cmp);
    out[0] = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    out[1] = v[0];
    out[2] = v[n - 1];
}
