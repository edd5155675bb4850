/* vsv_testlib.h — a tiny test library: named checks that count, print
 * "PASS name" / "FAIL name: why" / "SKIP name: why" lines that tests/run.sh
 * tallies. */
#ifndef VSV_TESTLIB_H
#define VSV_TESTLIB_H

#include <stdint.h>
#include <stdio.h>

extern int vsv_test_failures;

/* Records one named check; returns cond. */
int vsv_test_check(int cond, const char *name, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
#define CHECK(cond, name, ...) vsv_test_check(!!(cond), name, " " __VA_ARGS__)
/* Exit status for main: 1 if any check failed. */
int vsv_test_done(void);

/* Path of a test data file: tests/data/REL (the small real files copied
 * into the repository; tests run from the checkout's root) if it is there,
 * else $SHARED/data/REL (default ../shared: the large files). */
const char *vsv_test_shared(const char *rel);
/* 0 if path can be read; else prints "SKIP what: path absent" (counted by
 * tests/run.sh) and returns 1: the caller skips the checks that need it. */
int vsv_test_absent(const char *path, const char *what);
/* A fresh scratch path under $TMPDIR/vsv-tests-PID/ (created on demand). */
const char *vsv_test_tmp(const char *name);
/* Reads a whole file; caller frees. NULL on error. */
unsigned char *vsv_test_slurp(const char *path, size_t *size);
int vsv_test_write(const char *path, const void *data, size_t size);
/* Deterministic pseudo-random numbers (xorshift64*). */
uint64_t vsv_test_rand(uint64_t *state);

#endif
