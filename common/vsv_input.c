/* vsv_input.c — opening an input file: only regular files. A FIFO would
 * block open() and read() forever (every tool hung on one), a device or a
 * directory has no size to check reads against; each is refused at open,
 * without blocking (O_NONBLOCK until the type is known). */
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

int vsv_input_map(const char *path, size_t min_bytes, const unsigned char **data, size_t *n, char *why, size_t cap)
{
    *data = NULL;
    *n = 0;
    const int fd = vsv_input_open(path, why, cap);
    if (fd < 0)
        return -1;
    const off_t size = lseek(fd, 0, SEEK_END); /* a regular file's size */
    if (size < 0) {
        snprintf(why, cap, "cannot read: %s", strerror(errno));
        close(fd);
        return -1;
    }
    *n = (size_t)size;
    if (*n < min_bytes || *n == 0) {
        close(fd);
        return 1;
    }
    void *p = mmap(NULL, *n, PROT_READ, MAP_SHARED, fd, 0);
    close(fd);
    if (p == MAP_FAILED) {
        snprintf(why, cap, "cannot map: %s", strerror(errno));
        return -1;
    }
    *data = p;
    return 0;
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
