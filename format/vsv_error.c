/* vsv_error.c — error texts of the VSV_E* codes (vsv_strerror). */
#include "vsv_format_internal.h"

const char *vsv_strerror(int code)
{
    switch (code) {
    case VSV_OK: return "success";
    case VSV_EIO: return "I/O error";
    case VSV_ENOMEM: return "out of memory";
    case VSV_ENOTVSV: return "not a .vsv file";
    case VSV_EVERSION: return "unsupported format version";
    case VSV_ECORRUPT: return "corrupt data";
    case VSV_ETRUNC: return "truncated";
    case VSV_EINVAL: return "invalid argument";
    case VSV_ERANGE: return "index out of range";
    case VSV_ECODEC: return "payload does not decode";
    case VSV_ENOTFOUND: return "not found";
    case VSV_EUNSUPPORTED: return "not supported";
    case VSV_EAGAIN: return "not ready yet";
    default: return "unknown error";
    }
}
