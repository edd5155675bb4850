/* fuzz_mm5.c — fuzz target for the MM5 v3 reader: index any bytes and, when
 * they index, read every field. Built for libFuzzer by `make fuzz`; also runs
 * as a regression test over tests/corpus/mm5 (fuzz_main.c). */
#include "vsv_mm5.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
const char *const fuzz_default_dirs[4] = {"tests/corpus/mm5", NULL, NULL, NULL};
const char fuzz_label[] = "MM5 reader";

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vsv_mm5 *m = NULL;
    if (vsv_mm5_open_mem(data, size, "fuzz", &m) == 0) {
        for (int i = 0; i < vsv_mm5_nfields(m); i++) {
            const vsv_mm5_field *f = vsv_mm5_field_at(m, i);
            float *buf = malloc(f->bytes ? f->bytes : 4);
            if (buf)
                vsv_mm5_read(m, f, buf);
            free(buf);
        }
        (void)vsv_mm5_bhi(m, 16, 1);
    }
    vsv_mm5_free(m);
    return 0;
}
