/* vsv_output.c — outputs written whole or not at all. Every output file is
 * written under a temporary name in its destination's directory (so the
 * final rename is atomic), synced, and renamed only when complete. Each
 * temporary is listed in one process-wide registry, so a program's
 * SIGINT/SIGTERM/SIGHUP handler can remove them all before it re-raises the
 * signal (as zstd's programs do): nothing half-written is left behind. The
 * registry is blocks of fixed slots, never freed, that a signal handler can
 * walk without locks. The mode of a new file is 0666 less the umask, read
 * once from /proc (never by toggling the process umask, which races with
 * other threads creating files). */
#include "vsv_common.h"

#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

enum { SLOT_PATH = 1024, BLOCK_SLOTS = 64 };

typedef struct block {
    struct block *next;
    struct {
        int used;
        char path[SLOT_PATH];
    } slot[BLOCK_SLOTS];
} block;

static block *head;
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;

/* ------------------------------------------------------------ the umask */

static pthread_once_t mode_once = PTHREAD_ONCE_INIT;
static unsigned file_mode = 0644;

static void read_umask(void)
{
    FILE *fp = fopen("/proc/self/status", "re");
    unsigned um = 0;
    int found = 0;
    if (fp) {
        char line[256];
        while (!found && fgets(line, sizeof line, fp))
            found = sscanf(line, "Umask: %o", &um) == 1;
        fclose(fp);
    }
    if (!found) {
        /* no /proc (Linux before 4.7): once, at first use */
        const mode_t m = umask(022);
        umask(m);
        um = m;
    }
    file_mode = 0666u & ~um;
}

unsigned vsv_output_mode(void)
{
    pthread_once(&mode_once, read_umask);
    return file_mode;
}

/* ------------------------------------------------------------- registry */

static void remember(const char *tmp)
{
    if (strlen(tmp) >= SLOT_PATH)
        return; /* not listed: removed on errors, but not on a signal */
    pthread_mutex_lock(&lock);
    block **bp = &head;
    for (;;) {
        block *b = *bp;
        if (!b) {
            b = calloc(1, sizeof *b);
            if (!b)
                break;
            __atomic_store_n(bp, b, __ATOMIC_RELEASE);
        }
        for (int i = 0; i < BLOCK_SLOTS; i++)
            if (!b->slot[i].used) {
                memcpy(b->slot[i].path, tmp, strlen(tmp) + 1);
                __atomic_store_n(&b->slot[i].used, 1, __ATOMIC_RELEASE);
                pthread_mutex_unlock(&lock);
                return;
            }
        bp = &b->next;
    }
    pthread_mutex_unlock(&lock);
}

void vsv_output_claim(const char *tmp) { remember(tmp); }

void vsv_output_forget(const char *tmp)
{
    pthread_mutex_lock(&lock);
    for (block *b = head; b; b = b->next)
        for (int i = 0; i < BLOCK_SLOTS; i++)
            if (b->slot[i].used && !strcmp(b->slot[i].path, tmp)) {
                __atomic_store_n(&b->slot[i].used, 0, __ATOMIC_RELEASE);
                pthread_mutex_unlock(&lock);
                return;
            }
    pthread_mutex_unlock(&lock);
}

void vsv_output_cleanup(void)
{
    for (block *b = __atomic_load_n(&head, __ATOMIC_ACQUIRE); b; b = __atomic_load_n(&b->next, __ATOMIC_ACQUIRE))
        for (int i = 0; i < BLOCK_SLOTS; i++)
            if (__atomic_load_n(&b->slot[i].used, __ATOMIC_ACQUIRE))
                unlink(b->slot[i].path);
}

/* ---------------------------------------------------------- temporaries */

int vsv_output_temp(const char *path, const char *suffix, char *tmp, size_t cap)
{
    /* the rename at the end replaces what is at path: a directory, device,
     * FIFO or socket (/dev/null, /dev/stdout as root) is never replaced */
    struct stat st;
    if (!stat(path, &st) && !S_ISREG(st.st_mode)) {
        errno = S_ISDIR(st.st_mode) ? EISDIR : EEXIST;
        return -1;
    }
    const unsigned mode = vsv_output_mode();
    /* name.tmp.PID.N[suffix]: unique in the process, and O_EXCL against
     * others; a name too long for that (a file name has 255 bytes at most)
     * gets .vsv-tmp.PID.N[suffix] beside it instead */
    static unsigned serial;
    const char *slash = strrchr(path, '/');
    const size_t dirlen = slash ? (size_t)(slash - path + 1) : 0, base = strlen(path) - dirlen;
    const int short_name = base + 32 + (suffix ? strlen(suffix) : 0) > 255;
    for (int tries = 0; tries < 100; tries++) {
        const unsigned n = __atomic_fetch_add(&serial, 1, __ATOMIC_RELAXED);
        const int len = short_name
                            ? snprintf(tmp, cap, "%.*s.vsv-tmp.%ld.%u%s", (int)dirlen, path, (long)getpid(), n,
                                       suffix ? suffix : "")
                            : snprintf(tmp, cap, "%s.tmp.%ld.%u%s", path, (long)getpid(), n, suffix ? suffix : "");
        if (len < 0 || (size_t)len >= cap) {
            errno = ENAMETOOLONG;
            return -1;
        }
        /* listed before it exists: a signal between the two leaves nothing */
        remember(tmp);
        const int fd = open(tmp, O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, mode);
        if (fd >= 0) {
            /* exactly the mode a plain create gives (open applies the
             * umask too; this is for a default ACL that would not) */
            if (fchmod(fd, mode)) {
                const int e = errno;
                close(fd);
                unlink(tmp);
                vsv_output_forget(tmp);
                errno = e;
                return -1;
            }
            return fd;
        }
        const int e = errno;
        vsv_output_forget(tmp);
        if (e != EEXIST) {
            errno = e;
            return -1;
        }
    }
    errno = EEXIST;
    return -1;
}

void vsv_output_discard(const char *tmp)
{
    unlink(tmp);
    vsv_output_forget(tmp);
}

int vsv_output_seal(int fd)
{
    int rc = fsync(fd);
    const int e = errno;
    if (close(fd) && !rc)
        return -1;
    errno = e;
    return rc;
}

int vsv_output_publish(const char *tmp, const char *path)
{
    if (rename(tmp, path))
        return -1;
    vsv_output_forget(tmp);
    /* the directory entry, durably */
    char dir[4200];
    snprintf(dir, sizeof dir, "%s", path);
    const int dfd = open(dirname(dir), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        fsync(dfd);
        close(dfd);
    }
    return 0;
}

int vsv_output_commit(int fd, const char *tmp, const char *path)
{
    if ((fd >= 0 && vsv_output_seal(fd)) || vsv_output_publish(tmp, path)) {
        const int e = errno;
        vsv_output_discard(tmp);
        errno = e;
        return -1;
    }
    return 0;
}
