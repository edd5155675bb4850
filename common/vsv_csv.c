/* vsv_csv.c — one CSV field as RFC 4180 has it: as it is, or in double
 * quotes (inner quotes doubled) when it holds a comma, a quote or a line
 * break, so names from a file (a species "b (1,\"2\")") keep their column. */
#include "vsv_common.h"

#include <stdio.h>

void vsv_csv_field(FILE *fp, const char *s)
{
    if (!s[strcspn(s, ",\"\r\n")]) {
        fputs(s, fp);
        return;
    }
    putc('"', fp);
    for (; *s; s++) {
        if (*s == '"')
            putc('"', fp);
        putc(*s, fp);
    }
    putc('"', fp);
}
