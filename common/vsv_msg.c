/* vsv_msg.c — the messages handles keep ("path: what, where"), into fixed
 * buffers (vsv_common.h). */
#include "vsv_common.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>

const char *vsv_errno_text(int e) { return e == ENOMEM ? "out of memory" : strerror(e); }

void vsv_msg(char *buf, size_t cap, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, cap, fmt, ap);
    va_end(ap);
}

void vsv_vmsg_path(char *buf, size_t cap, const char *path, const char *fmt, va_list ap)
{
    char m[512];
    vsnprintf(m, sizeof m, fmt, ap);
    snprintf(buf, cap, "%s: %s", path, m);
}
