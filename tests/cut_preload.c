/* cut_preload.c — a test shim (LD_PRELOAD) that truncates a file right after
 * the program maps it: "a file truncated while a tool reads it", without any
 * timing. VSV_TEST_CUT names the file (as /proc/self/fd shows it: absolute),
 * VSV_TEST_CUT_TO the length to leave (default: a third of what was mapped). */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

void *mmap(void *addr, size_t len, int prot, int flags, int fd, off_t off)
{
    static void *(*real)(void *, size_t, int, int, int, off_t);
    if (!real)
        *(void **)&real = dlsym(RTLD_NEXT, "mmap");
    void *p = real(addr, len, prot, flags, fd, off);
    const char *want = getenv("VSV_TEST_CUT");
    if (want && fd >= 0 && p != MAP_FAILED) {
        char link[64], target[4096];
        snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
        const ssize_t n = readlink(link, target, sizeof target - 1);
        if (n > 0) {
            target[n] = 0;
            const char *to = getenv("VSV_TEST_CUT_TO");
            if (!strcmp(target, want) && truncate(want, to ? atoll(to) : (long long)(len / 3)) == 0)
                unsetenv("VSV_TEST_CUT"); /* once */
        }
    }
    return p;
}
