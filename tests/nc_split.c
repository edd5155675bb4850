/* nc_split.c — copies records FIRST..FIRST+COUNT-1 of a netCDF file's
 * unlimited dimension (or of the dimension Time) with every dimension, variable and
 * attribute into a new netCDF-4 file (float variables deflated), so the
 * tests can cut one real WRF run into a multi-file run:
 *   ncsplit IN OUT FIRST COUNT */
#include <netcdf.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TRY(call)                                                                                                      \
    do {                                                                                                               \
        int rc_ = (call);                                                                                              \
        if (rc_) {                                                                                                     \
            fprintf(stderr, "ncsplit: %s: %s\n", #call, nc_strerror(rc_));                                             \
            exit(1);                                                                                                   \
        }                                                                                                              \
    } while (0)

static void copy_atts(int in, int vin, int out, int vout, int natts)
{
    for (int a = 0; a < natts; a++) {
        char name[NC_MAX_NAME + 1];
        TRY(nc_inq_attname(in, vin, a, name));
        TRY(nc_copy_att(in, vin, name, out, vout));
    }
}

int main(int argc, char **argv)
{
    if (argc != 5) {
        fprintf(stderr, "usage: ncsplit IN OUT FIRST COUNT\n");
        return 2;
    }
    const size_t first = (size_t)atol(argv[3]), count = (size_t)atol(argv[4]);
    int in, out, ndims, nvars, ngatts, unlim;
    TRY(nc_open(argv[1], NC_NOWRITE, &in));
    TRY(nc_inq(in, &ndims, &nvars, &ngatts, &unlim));
    if (unlim < 0 && nc_inq_dimid(in, "Time", &unlim))
        unlim = -1; /* a fixed Time dimension (netCDF-4 files may have one) */
    size_t nrec = 0;
    if (unlim >= 0)
        TRY(nc_inq_dimlen(in, unlim, &nrec));
    if (unlim < 0 || count < 1 || first + count > nrec) {
        fprintf(stderr, "ncsplit: %s: records %zu..%zu of %zu\n", argv[1], first, first + count - 1, nrec);
        return 2;
    }
    TRY(nc_create(argv[2], NC_NETCDF4 | NC_CLOBBER, &out));
    for (int d = 0; d < ndims; d++) {
        char name[NC_MAX_NAME + 1];
        size_t len;
        int id;
        TRY(nc_inq_dim(in, d, name, &len));
        TRY(nc_def_dim(out, name, d == unlim ? NC_UNLIMITED : len, &id));
    }
    copy_atts(in, NC_GLOBAL, out, NC_GLOBAL, ngatts);
    for (int v = 0; v < nvars; v++) {
        char name[NC_MAX_NAME + 1];
        nc_type type;
        int nd, dims[NC_MAX_VAR_DIMS], natts, id;
        TRY(nc_inq_var(in, v, name, &type, &nd, dims, &natts));
        TRY(nc_def_var(out, name, type, nd, dims, &id));
        if (type == NC_FLOAT && nd >= 2)
            TRY(nc_def_var_deflate(out, id, 1, 1, 4));
        copy_atts(in, v, out, id, natts);
    }
    TRY(nc_enddef(out));
    for (int v = 0; v < nvars; v++) {
        nc_type type;
        int nd, dims[NC_MAX_VAR_DIMS];
        TRY(nc_inq_var(in, v, NULL, &type, &nd, dims, NULL));
        size_t start[NC_MAX_VAR_DIMS] = {0}, cnt[NC_MAX_VAR_DIMS], ostart[NC_MAX_VAR_DIMS] = {0}, size, n = 1;
        for (int d = 0; d < nd; d++) {
            TRY(nc_inq_dimlen(in, dims[d], &cnt[d]));
            if (dims[d] == unlim) {
                start[d] = first;
                cnt[d] = count;
            }
            n *= cnt[d];
        }
        TRY(nc_inq_type(in, type, NULL, &size));
        void *buf = malloc(n * size + 1);
        TRY(nc_get_vara(in, v, start, cnt, buf));
        TRY(nc_put_vara(out, v, ostart, cnt, buf));
        free(buf);
    }
    TRY(nc_close(out));
    TRY(nc_close(in));
    return 0;
}
