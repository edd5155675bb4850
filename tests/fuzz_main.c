/* fuzz_main.c — runs the fuzz target as a regression test: every file under
 * the given directories, then N deterministic mutations (bit flips, byte
 * runs, splices, truncations) of each. Reports PASS/FAIL lines; a crash is
 * a failure that run.sh reports. */
#include "vsv_testlib.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size);
/* The target's corpus directories and label (defined beside the target). */
extern const char *const fuzz_default_dirs[2];
extern const char fuzz_label[];

int main(int argc, char **argv)
{
    int files = 0;
    long mutations = argc > 1 ? atol(argv[1]) : 3000;
    uint64_t rs = 12345;
    const int ndirs = argc > 2 ? argc - 2 : 2;
    for (int a = 0; a < ndirs; a++) {
        const char *dir = argc > 2 ? argv[a + 2] : fuzz_default_dirs[a];
        if (!dir)
            continue;
        DIR *dp = opendir(dir);
        struct dirent *e;
        while (dp && (e = readdir(dp))) {
            if (e->d_name[0] == '.' || !strcmp(e->d_name, "EXPECTED") || strstr(e->d_name, ".py"))
                continue;
            char path[2048];
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
            size_t n;
            unsigned char *d = vsv_test_slurp(path, &n);
            if (!d)
                continue;
            LLVMFuzzerTestOneInput(d, n);
            files++;
            unsigned char *m = malloc(n + 64);
            for (long k = 0; k < mutations && n > 0; k++) {
                memcpy(m, d, n);
                size_t len = n;
                switch (vsv_test_rand(&rs) % 4) {
                case 0: m[vsv_test_rand(&rs) % n] ^= (unsigned char)(1u << (vsv_test_rand(&rs) % 8)); break;
                case 1: {
                    size_t at = vsv_test_rand(&rs) % n, run = 1 + vsv_test_rand(&rs) % 16;
                    for (size_t i = at; i < at + run && i < n; i++)
                        m[i] = (unsigned char)vsv_test_rand(&rs);
                    break;
                }
                case 2: len = vsv_test_rand(&rs) % n; break;
                default: {
                    size_t from = vsv_test_rand(&rs) % n, to = vsv_test_rand(&rs) % n, run = 1 + vsv_test_rand(&rs) % 64;
                    for (size_t i = 0; i < run && from + i < n && to + i < n; i++)
                        m[to + i] = d[from + i];
                }
                }
                LLVMFuzzerTestOneInput(m, len);
            }
            free(m);
            free(d);
        }
        if (dp)
            closedir(dp);
    }
    char name[128];
    snprintf(name, sizeof name, "%s fuzz regression corpus ran without a crash", fuzz_label);
    CHECK(files > 0, name, "no corpus files");
    printf("  %d corpus files, %ld mutations each\n", files, mutations);
    return vsv_test_done();
}
