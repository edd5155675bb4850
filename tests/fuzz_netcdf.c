/* fuzz_netcdf.c — fuzz target for the netCDF model readers (WRF, IOAPI for
 * CMAQ and CAMx, CF): the bytes become a file that vsv_source_open detects
 * and reads whole, with native and with even levels. Inputs in netCDF-4
 * (HDF5) form are skipped: their damage crashes inside libhdf5 itself (a
 * library the project does not own; the tools open them in a bounded child
 * process), so the seeds are the real files converted to netCDF classic.
 * Classic inputs whose header declares more bytes than the file holds
 * reach libnetcdf no more: the reader walks the header first
 * (convert/vsv_nc_header.c), since libnetcdf allocates and copies such an
 * attribute before it finds the file short (found by this target and by
 * the damage sweep: gigabytes and a minute per input, tests/FUZZING.md).
 * Built for libFuzzer by `make fuzz`; also runs as a regression test over
 * tests/corpus/netcdf (fuzz_main.c). */
#include "fuzz_source.h"

#include <netcdf.h>
#include <netcdf_mem.h>
#include <stdio.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
const char *const fuzz_default_dirs[4] = {"tests/corpus/netcdf", NULL, NULL, NULL};
const char fuzz_label[] = "netCDF readers (WRF, IOAPI, CF)";
const long fuzz_mutations = 300;

static int hdf5(const uint8_t *d, size_t n)
{
    for (size_t at = 0; at + 8 <= n; at = at ? 2 * at : 512)
        if (!memcmp(d + at, "\x89HDF\r\n\x1a\n", 8))
            return 1;
    return 0;
}

static long n_runs, n_opened;

int fuzz_report(char *msg, size_t cap);
int fuzz_report(char *msg, size_t cap)
{
    snprintf(msg, cap, "%ld classic inputs, %ld opened", n_runs, n_opened);
    return n_opened * 10 > n_runs ? 0 : -1;
}

/* libnetcdf callocs its table of open files (512 KiB) at an open when no
 * file is open and frees it at the last close: a quarter of this target's
 * time went to that, under AddressSanitizer. One empty classic file held
 * open in memory for the whole process keeps the table. */
static void hold_table(void)
{
    static int held;
    static unsigned char empty[32] = {'C', 'D', 'F', 1}; /* no records, dimensions, attributes or variables */
    int id;
    if (!held && nc_open_mem("fuzz-hold", NC_NOWRITE, sizeof empty, empty, &id) == NC_NOERR)
        held = 1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hold_table();
    if (size < 4 || hdf5(data, size))
        return 0;
    n_runs++;
    const char *path = fuzz_put("in.nc", data, size);
    if (!path)
        return 0;
    vsv_source_opts o;
    vsv_source_opts_init(&o);
    o.vertical = VSV_VERT_NATIVE;
    if (fuzz_source_read_all(path, &o) >= 0)
        n_opened++;
    o.vertical = VSV_VERT_EVEN;
    o.nz = 8;
    (void)fuzz_source_read_all(path, &o);
    return 0;
}
