/* vsv_testlib.c — see vsv_testlib.h. */
#include "vsv_testlib.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int vsv_test_failures;

int vsv_test_check(int cond, const char *name, const char *fmt, ...)
{
    if (cond) {
        printf("PASS %s\n", name);
    } else {
        vsv_test_failures++;
        printf("FAIL %s", name);
        if (fmt && fmt[0] && fmt[1]) {
            va_list ap;
            va_start(ap, fmt);
            fputs(": ", stdout);
            vprintf(fmt, ap);
            va_end(ap);
        }
        putchar('\n');
    }
    fflush(stdout);
    return cond;
}

int vsv_test_done(void) { return vsv_test_failures ? 1 : 0; }

const char *vsv_test_shared(const char *rel)
{
    static char buf[8][1024];
    static int i;
    const char *root = getenv("SHARED");
    char *b = buf[i++ % 8];
    snprintf(b, 1024, "tests/data/%s", rel);
    if (access(b, F_OK) == 0)
        return b;
    snprintf(b, 1024, "%s/data/%s", root && *root ? root : "../shared", rel);
    return b;
}

int vsv_test_absent(const char *path, const char *what)
{
    if (access(path, R_OK) == 0)
        return 0;
    printf("SKIP %s: %s absent\n", what, path);
    fflush(stdout);
    return 1;
}

const char *vsv_test_tmp(const char *name)
{
    static char dir[512], buf[8][1024];
    static int i;
    if (!dir[0]) {
        const char *t = getenv("TMPDIR");
        snprintf(dir, sizeof dir, "%s/vsv-tests-%d", t && *t ? t : "/tmp", (int)getpid());
        mkdir(dir, 0700);
    }
    char *b = buf[i++ % 8];
    snprintf(b, 1024, "%s/%s", dir, name);
    return b;
}

unsigned char *vsv_test_slurp(const char *path, size_t *size)
{
    struct stat st;
    if (stat(path, &st) || !S_ISREG(st.st_mode))
        return NULL;
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return NULL;
    fseek(fp, 0, SEEK_END);
    long n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    unsigned char *p = malloc(n > 0 ? (size_t)n : 1);
    if (p && fread(p, 1, (size_t)n, fp) != (size_t)n) {
        free(p);
        p = NULL;
    }
    fclose(fp);
    *size = (size_t)n;
    return p;
}

int vsv_test_write(const char *path, const void *data, size_t size)
{
    FILE *fp = fopen(path, "wb");
    if (!fp)
        return -1;
    int ok = fwrite(data, 1, size, fp) == size;
    return fclose(fp) == 0 && ok ? 0 : -1;
}

uint64_t vsv_test_rand(uint64_t *s)
{
    uint64_t x = *s ? *s : 0x9E3779B97F4A7C15ull;
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    *s = x;
    return x * 0x2545F4914F6CDD1Dull;
}
