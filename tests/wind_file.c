/* wind_file.c — writes a small .vsv with a known wind for the CLI tests of
 * vsv-query --trajectory (tests/cli_traj.sh), until vsv-convert stores the
 * models' own:
 *   windfile OUT KIND   KIND: east (a Lambert grid, 60 x 60 x 5 cells of
 *                       4 km centred on 40N 100W, levels 50 m + 100 m k,
 *                       10 m/s east everywhere, hourly 2020-01-01T00Z..06Z),
 *                       flat (the same on projection "none"), nowind (the
 *                       Lambert grid with ozone only). */
#include "vsv_format.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char **argv)
{
    if (argc != 3 || (strcmp(argv[2], "east") && strcmp(argv[2], "flat") && strcmp(argv[2], "nowind"))) {
        fprintf(stderr, "usage: windfile OUT east|flat|nowind\n");
        return 2;
    }
    const int wind = strcmp(argv[2], "nowind") != 0;
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = m.ny = 60, m.nz = 5;
    m.spacing[0] = m.spacing[1] = 4000, m.spacing[2] = 100;
    m.origin[0] = m.origin[1] = -118000, m.origin[2] = 50;
    m.vert_kind = VSV_VERT_EVEN;
    if (strcmp(argv[2], "flat"))
        m.proj = (vsv_proj){VSV_PROJ_LCC, 40, -100, 30, 60, 0};
    snprintf(m.model, sizeof m.model, "test");
    if (wind) {
        vsv_meta_add_var(&m, VSV_WIND_EAST, "m s-1", "eastward wind");
        vsv_meta_add_var(&m, VSV_WIND_NORTH, "m s-1", "northward wind");
        vsv_meta_add_var(&m, VSV_WIND_UP, "m s-1", "upward wind");
        vsv_meta_add_attr(&m, VSV_VECTOR_ATTR VSV_WIND, VSV_WIND_EAST " " VSV_WIND_NORTH " " VSV_WIND_UP);
    } else {
        vsv_meta_add_var(&m, "O3", "ppb", "ozone");
    }
    const size_t cells = (size_t)m.nx * m.ny * m.nz;
    float *v[3];
    for (int c = 0; c < 3; c++)
        if (!(v[c] = calloc(cells, sizeof(float))))
            return 1;
    for (size_t i = 0; i < cells; i++)
        v[0][i] = 10;
    vsv_writer *w = NULL;
    const float *fields[3] = {v[0], v[1], v[2]};
    const int64_t t0 = vsv_time_from_civil(2020, 1, 1, 0, 0, 0);
    int rc = vsv_writer_create(argv[1], &m, NULL, &w);
    for (int s = 0; s <= 6 && !rc; s++)
        rc = vsv_writer_add_step(w, t0 + 3600 * s, fields);
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    if (rc)
        fprintf(stderr, "windfile: %s: %s\n", argv[1], w ? vsv_writer_error(w) : vsv_strerror(rc));
    vsv_writer_free(w);
    vsv_meta_clear(&m);
    for (int c = 0; c < 3; c++)
        free(v[c]);
    return rc ? 1 : 0;
}
