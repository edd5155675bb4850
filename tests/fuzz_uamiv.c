/* fuzz_uamiv.c — fuzz target for the CAMx UAM-IV reader: parse any bytes and,
 * when they parse, read every record. Built for libFuzzer by `make fuzz`;
 * also runs as a regression test over tests/corpus/uamiv (fuzz_main.c). */
#include "vsv_uamiv.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
const char *const fuzz_default_dirs[4] = {"tests/corpus/uamiv", NULL, NULL, NULL};
const char fuzz_label[] = "UAM-IV reader";

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vsv_uamiv *u = NULL;
    if (vsv_uamiv_open_mem(data, size, "fuzz", &u) == 0) {
        const vsv_uamiv_header *h = vsv_uamiv_header_get(u);
        float *plane = malloc((size_t)h->nx * h->ny * sizeof *plane);
        for (int t = 0; plane && t < h->nhours && t < 4; t++)
            for (int s = 0; s < h->nspec && s < 64; s++)
                for (int k = 0; k < h->nz && k < 8; k++)
                    (void)vsv_uamiv_read(u, t, s, k, plane);
        free(plane);
    }
    vsv_uamiv_free(u);
    return 0;
}
