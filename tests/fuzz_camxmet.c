/* fuzz_camxmet.c — fuzz target for the CAMx met companions (height/pressure,
 * wind, temperature, humidity, Kv, cloud/rain; INPUT-FORMATS.md §2.1b): the
 * bytes become a file opened against the grid of the real samples (5 x 4
 * cells, 3 layers), its kind detected, and every field, hour and layer read,
 * with the heights. Built for libFuzzer by `make fuzz`; also runs as a
 * regression test over tests/corpus/camxmet (fuzz_main.c). */
#include "fuzz_source.h"
#include "vsv_uamiv.h"

#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
const char *const fuzz_default_dirs[4] = {"tests/corpus/camxmet", NULL, NULL, NULL};
const char fuzz_label[] = "CAMx met companion reader";
const long fuzz_mutations = 300;

enum { NX = 5, NY = 4, NZ = 3 };

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_put("met", data, size);
    if (!path)
        return 0;
    vsv_camxmet *m = NULL;
    if (vsv_camxmet_open(path, -1, NX, NY, NZ, "fuzz.avrg", &m) == 0) {
        float plane[NX * NY], heights[NX * NY * NZ];
        for (int h = 0; h < vsv_camxmet_nhours(m) && h < 8; h++) {
            int date;
            float hhmm;
            vsv_camxmet_stamp(m, h, &date, &hhmm);
            for (int f = 0; f < vsv_camxmet_nfields(m); f++)
                for (int k = 0; k < NZ; k++)
                    (void)vsv_camxmet_read(m, h, f, k, plane);
            if (vsv_camxmet_kind(m) == VSV_MET_ZP)
                (void)vsv_camxmet_heights(m, h, heights);
        }
    }
    vsv_camxmet_free(m);
    return 0;
}
