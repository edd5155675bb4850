/* bench_stats.h — the summary the benchmarks print of their rounds. */
#ifndef BENCH_STATS_H
#define BENCH_STATS_H

/* Median, minimum and maximum of n > 0 values into out[0..2] (v is sorted
 * in place). */
void bench_stats(double *v, int n, double out[3]);

#endif
