/* vsv_input.c — opening an input file: only regular files. A FIFO would
 * block open() and read() forever (every tool hung on one), a device or a
 * directory has no size to check reads against; each is refused at open,
 * without blocking (O_NONBLOCK until the type is known). A mapped input is
 * guarded against shrinking while it is read (vsv_mapguard.c). */
#include "vsv_common.h"

#include <stdio.h>

#include <errno.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

const char *vsv_file_kind(unsigned m)
{
    return S_ISFIFO(m)   ? "a FIFO"
           : S_ISDIR(m)  ? "a directory"
           : S_ISCHR(m)  ? "a character device"
           : S_ISBLK(m)  ? "a block device"
           : S_ISSOCK(m) ? "a socket"
                         : "not a regular file";
}

int vsv_input_open(const char *path, char *why, size_t cap)
{
    const int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
    if (fd < 0) {
        snprintf(why, cap, "cannot open: %s", strerror(errno));
        return -1;
    }
    struct stat st;
    if (fstat(fd, &st)) {
        snprintf(why, cap, "cannot open: %s", strerror(errno));
        close(fd);
        return -1;
    }
    if (!S_ISREG(st.st_mode)) {
        snprintf(why, cap, "%s, not a regular file: refused", vsv_file_kind(st.st_mode));
        close(fd);
        errno = EINVAL;
        return -1;
    }
    const int fl = fcntl(fd, F_GETFL);
    if (fl >= 0)
        fcntl(fd, F_SETFL, fl & ~O_NONBLOCK);
    return fd;
}

FILE *vsv_input_fopen(const char *path, const char *mode, char *why, size_t cap)
{
    const int fd = vsv_input_open(path, why, cap);
    if (fd < 0)
        return NULL;
    FILE *fp = fdopen(fd, mode);
    if (!fp) {
        snprintf(why, cap, "cannot open: %s", strerror(errno));
        close(fd);
    }
    return fp;
}

int vsv_input_map(const char *path, size_t min_bytes, vsv_mapped *m, char *why, size_t cap)
{
    m->data = NULL;
    m->n = 0;
    m->fd = m->guard = -1;
    const int fd = vsv_input_open(path, why, cap);
    if (fd < 0)
        return -1;
    const off_t size = lseek(fd, 0, SEEK_END); /* a regular file's size */
    if (size < 0) {
        snprintf(why, cap, "cannot read: %s", strerror(errno));
        close(fd);
        return -1;
    }
    m->n = (size_t)size;
    if (m->n < min_bytes || m->n == 0) {
        close(fd);
        return 1;
    }
    void *p = mmap(NULL, m->n, PROT_READ, MAP_SHARED, fd, 0);
    if (p == MAP_FAILED) {
        snprintf(why, cap, "cannot map: %s", vsv_errno_text(errno));
        close(fd);
        return -1;
    }
    m->data = p;
    m->fd = fd;
    m->guard = vsv_mapguard_add(p, m->n);
    return 0;
}

int vsv_input_cut(const vsv_mapped *m, int look)
{
    if (vsv_mapguard_cut(m->guard))
        return 1;
    struct stat st;
    return look && m->fd >= 0 && !fstat(m->fd, &st) && (uint64_t)st.st_size < (uint64_t)m->n;
}

void vsv_input_unmap(vsv_mapped *m)
{
    vsv_mapguard_remove(m->guard);
    if (m->data)
        munmap((void *)m->data, m->n);
    if (m->fd >= 0)
        close(m->fd);
    m->data = NULL;
    m->fd = m->guard = -1;
}

FILE *vsv_input_fopen_stream(const char *path, char *why, size_t cap)
{
    struct stat st;
    /* looked at before the open: opening a device can have effects, and a
     * FIFO's open waits for its writer, which is right for a stream */
    if (stat(path, &st)) {
        snprintf(why, cap, "cannot open: %s", strerror(errno));
        return NULL;
    }
    if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode)) {
        snprintf(why, cap, "%s, not a regular file or a pipe: refused", vsv_file_kind(st.st_mode));
        errno = EINVAL;
        return NULL;
    }
    FILE *fp = fopen(path, "rbe");
    if (!fp) {
        snprintf(why, cap, "cannot open: %s", strerror(errno));
        return NULL;
    }
    if (fstat(fileno(fp), &st) || (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode))) { /* replaced meanwhile */
        snprintf(why, cap, "%s, not a regular file or a pipe: refused", vsv_file_kind(st.st_mode));
        fclose(fp);
        errno = EINVAL;
        return NULL;
    }
    return fp;
}
