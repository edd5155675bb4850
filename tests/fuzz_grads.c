/* fuzz_grads.c — fuzz target for the GrADS reader: the input is a .ctl
 * text, a NUL byte, then the binary data; they become model.ctl and
 * model.dat in a scratch folder (the seeds' DSET is ^model.dat) and the
 * source is opened and read whole. Built for libFuzzer by `make fuzz`; also
 * runs as a regression test over tests/corpus/grads (fuzz_main.c). */
#include "fuzz_source.h"

#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
const char *const fuzz_default_dirs[4] = {"tests/corpus/grads", NULL, NULL, NULL};
const char fuzz_label[] = "GrADS reader";
const long fuzz_mutations = 1000;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const uint8_t *nul = memchr(data, 0, size);
    const size_t ctl = nul ? (size_t)(nul - data) : size;
    if (!fuzz_put("model.dat", nul ? nul + 1 : data, nul ? size - ctl - 1 : 0))
        return 0;
    const char *path = fuzz_put("model.ctl", data, ctl);
    if (!path)
        return 0;
    vsv_source_opts o;
    vsv_source_opts_init(&o);
    o.vertical = VSV_VERT_NATIVE;
    (void)fuzz_source_read_all(path, &o);
    return 0;
}
