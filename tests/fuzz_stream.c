/* fuzz_stream.c — fuzz target for the field stream reader (SPEC.md §13):
 * read any bytes as a stream (fmemopen) and, when the header reads, every
 * frame up to the end marker. Built for libFuzzer by `make fuzz`; also runs
 * as a regression test over tests/corpus/stream (fuzz_main.c). */
#include "vsv_format.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
const char *const fuzz_default_dirs[4] = {"tests/corpus/stream", NULL, NULL, NULL};
const char fuzz_label[] = "field stream reader";

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!size)
        return 0;
    FILE *fp = fmemopen((void *)data, size, "rb");
    if (!fp)
        return 0;
    vsv_stream_reader *r = NULL;
    if (vsv_stream_reader_open(fp, "fuzz", &r) == 0) {
        const vsv_meta *m = vsv_stream_reader_meta(r);
        const size_t cells = (size_t)m->nx * m->ny * m->nz;
        if (m->nvars > 0 && m->nvars <= 64 && cells <= ((size_t)1 << 18)) {
            float *buf = malloc(cells * (size_t)m->nvars * sizeof *buf);
            float *fields[64];
            for (int v = 0; buf && v < m->nvars; v++)
                fields[v] = buf + (size_t)v * cells;
            int64_t t;
            for (int frame = 0; buf && frame < 64 && vsv_stream_reader_next(r, &t, fields) == 1; frame++)
                ;
            free(buf);
        }
    }
    vsv_stream_reader_free(r);
    fclose(fp);
    return 0;
}
