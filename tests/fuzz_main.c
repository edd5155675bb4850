/* fuzz_main.c — runs a fuzz target as a regression test (`make test`):
 * every file of its corpus directories once, then N deterministic
 * mutations of each: the target's own structure-aware mutator when it has
 * one (LLVMFuzzerCustomMutator, as libFuzzer would call it), else bit flips,
 * byte runs, splices and truncations. A crash is a failure that run.sh
 * reports; a target may also check what its inputs reached (fuzz_report).
 * `make fuzz` links the same targets with libFuzzer instead (tests/FUZZING.md). */
#include "vsv_testlib.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size);
/* Optional in a target: libFuzzer's hooks, and this harness's. */
int LLVMFuzzerInitialize(int *argc, char ***argv) __attribute__((weak));
size_t LLVMFuzzerCustomMutator(unsigned char *data, size_t size, size_t max, unsigned seed) __attribute__((weak));
/* Mutations per corpus file (default 3000). */
extern const long fuzz_mutations __attribute__((weak));
/* After the run: 0, or -1 with what the inputs failed to reach in msg. */
int fuzz_report(char *msg, size_t cap) __attribute__((weak));
/* The target's corpus directories and label (defined beside the target). */
extern const char *const fuzz_default_dirs[4];
extern const char fuzz_label[];

static uint64_t rs = 12345;

/* libFuzzer's raw mutator, which custom mutators call: one random change. */
size_t LLVMFuzzerMutate(unsigned char *m, size_t n, size_t max);
size_t LLVMFuzzerMutate(unsigned char *m, size_t n, size_t max)
{
    if (n == 0)
        return 0;
    switch (vsv_test_rand(&rs) % 4) {
    case 0: m[vsv_test_rand(&rs) % n] ^= (unsigned char)(1u << (vsv_test_rand(&rs) % 8)); break;
    case 1: {
        size_t at = vsv_test_rand(&rs) % n, run = 1 + vsv_test_rand(&rs) % 16;
        for (size_t i = at; i < at + run && i < n; i++)
            m[i] = (unsigned char)vsv_test_rand(&rs);
        break;
    }
    case 2: return 1 + vsv_test_rand(&rs) % n;
    default: {
        size_t from = vsv_test_rand(&rs) % n, to = vsv_test_rand(&rs) % n, run = 1 + vsv_test_rand(&rs) % 64;
        memmove(m + to, m + from, from + run > n || to + run > n ? 0 : run);
    }
    }
    return n <= max ? n : max;
}

int main(int argc, char **argv)
{
    int files = 0;
    long mutations = argc > 1 ? atol(argv[1]) : &fuzz_mutations ? fuzz_mutations : 3000;
    if (LLVMFuzzerInitialize)
        LLVMFuzzerInitialize(&argc, &argv);
    const int ndirs = argc > 2 ? argc - 2 : 4;
    for (int a = 0; a < ndirs; a++) {
        const char *dir = argc > 2 ? argv[a + 2] : fuzz_default_dirs[a];
        if (!dir)
            continue;
        DIR *dp = opendir(dir);
        struct dirent *e;
        while (dp && (e = readdir(dp))) {
            if (e->d_name[0] == '.' || !strcmp(e->d_name, "EXPECTED") || strstr(e->d_name, ".py") ||
                strstr(e->d_name, ".md"))
                continue;
            char path[2048];
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
            size_t n;
            unsigned char *d = vsv_test_slurp(path, &n);
            if (!d)
                continue;
            LLVMFuzzerTestOneInput(d, n);
            files++;
            const size_t max = n + 64;
            unsigned char *m = malloc(max);
            for (long k = 0; k < mutations && n > 0; k++) {
                memcpy(m, d, n);
                size_t len = LLVMFuzzerCustomMutator ? LLVMFuzzerCustomMutator(m, n, max, (unsigned)vsv_test_rand(&rs))
                                                     : LLVMFuzzerMutate(m, n, max);
                LLVMFuzzerTestOneInput(m, len);
            }
            free(m);
            free(d);
        }
        if (dp)
            closedir(dp);
    }
    char name[128], why[512] = "";
    snprintf(name, sizeof name, "%s fuzz regression corpus ran without a crash", fuzz_label);
    CHECK(files > 0, name, "no corpus files");
    printf("  %d corpus files, %ld mutations each%s\n", files, mutations,
           LLVMFuzzerCustomMutator ? " (the target's structure-aware mutator)" : "");
    if (fuzz_report) {
        snprintf(name, sizeof name, "%s fuzz inputs reached the parser beyond its first check", fuzz_label);
        const int ok = fuzz_report(why, sizeof why) == 0;
        printf("  %s\n", why);
        CHECK(ok, name, "(see the line above)");
    }
    return vsv_test_done();
}
