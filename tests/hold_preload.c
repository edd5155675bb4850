/* hold_preload.c — a test shim (LD_PRELOAD) that stops a program right after
 * it has made its temporary output, so a test can signal it there without
 * any timing: when the program sets the mode of a file whose path contains
 * $VSV_TEST_HOLD (as /proc/self/fd shows it), the shim writes its process
 * id into the file $VSV_TEST_HOLD_MARK and waits for a signal, forever. Both ways a tool
 * makes its temporary (mkstemp then fchmod, or vsv_output_temp's open then
 * fchmod) pass through fchmod. */
#include <dlfcn.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int fchmod(int fd, mode_t mode)
{
    static int (*real)(int, mode_t);
    if (!real)
        *(void **)&real = dlsym(RTLD_NEXT, "fchmod");
    const int rc = real(fd, mode);
    const char *want = getenv("VSV_TEST_HOLD"), *mark = getenv("VSV_TEST_HOLD_MARK");
    if (want && mark && *want) {
        char link[64], target[4096];
        snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
        const ssize_t n = readlink(link, target, sizeof target - 1);
        if (n > 0) {
            target[n] = 0;
            if (strstr(target, want)) {
                char tmp[4200], pid[32];
                snprintf(tmp, sizeof tmp, "%s.part", mark);
                const int m = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
                const int len = snprintf(pid, sizeof pid, "%ld\n", (long)getpid());
                if (m >= 0 && write(m, pid, (size_t)len) == len && !close(m))
                    rename(tmp, mark); /* whole, or not there */
                for (;;)
                    pause();
            }
        }
    }
    return rc;
}
