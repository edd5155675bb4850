/* fuzz_vsv.c — fuzz target for the .vsv reader: open any bytes, and when
 * they open, check and decode everything. Built for libFuzzer by `make fuzz`;
 * fuzz_main.c runs it as a plain regression test over tests/corpus/ and
 * deterministic mutations of the golden file. */
#include "vsv_format.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
const char *const fuzz_default_dirs[2] = {"tests/golden", "tests/golden/bad"};
const char fuzz_label[] = ".vsv reader";

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vsv_file *f = NULL;
    if (vsv_file_open_mem(data, size, "fuzz", &f) == 0) {
        const vsv_meta *m = vsv_file_meta(f);
        vsv_file_info info;
        vsv_file_info_get(f, &info);
        const size_t cells = (size_t)m->nx * m->ny * m->nz;
        if (cells <= ((size_t)1 << 20) && (size_t)info.nsteps * info.nspecies <= 4096) {
            (void)vsv_file_check(f, NULL, NULL);
            float *vol = malloc(cells * sizeof *vol);
            vsv_decoder *d = NULL;
            if (vol && vsv_decoder_create(f, &d) == 0)
                for (int t = 0; t < info.nsteps; t++)
                    for (int s = 0; s < info.nspecies; s++)
                        (void)vsv_decoder_volume(d, t, s, vol);
            vsv_decoder_free(d);
            free(vol);
        }
    }
    vsv_file_free(f);
    return 0;
}
