/* vsv_fdio.c — writing a whole buffer to a descriptor: write(2) or
 * pwrite(2) again after a short write or an interrupted call, in pieces of
 * at most 1 GiB (Linux writes at most 0x7ffff000 bytes a call). */
#include "vsv_common.h"

#include <errno.h>
#include <unistd.h>

int vsv_write_full(int fd, const void *p, size_t n, int64_t off)
{
    const unsigned char *c = p;
    while (n) {
        const size_t part = n > ((size_t)1 << 30) ? (size_t)1 << 30 : n;
        const ssize_t k = off < 0 ? write(fd, c, part) : pwrite(fd, c, part, (off_t)off);
        if (k < 0) {
            if (errno == EINTR)
                continue;
            return -1;
        }
        c += k;
        n -= (size_t)k;
        if (off >= 0)
            off += k;
    }
    return 0;
}
