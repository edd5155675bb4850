/* wind_file.c — writes a small .vsv with a known wind (synth_wind_write):
 *   windfile OUT east    a Lambert grid (true at 30 and 60 N), 60 x 60 x 5
 *                        cells of 4 km centred on 40N 100W, levels 50 m +
 *                        100 m k, 10 m/s east everywhere, hourly
 *                        2020-01-01T00Z..06Z (tests/cli_traj.sh)
 *   windfile OUT flat    the same on projection "none"
 *   windfile OUT nowind  the Lambert grid with ozone only
 *   windfile OUT uniform E N U [novector]
 *                        synth_wind_uniform's grid (tests/cli_flow.sh,
 *                        cli_freevr_room.sh): CLW and a wind of E, N, U m/s;
 *                        novector: the wind species without the attribute
 *                        that makes them the vector species wind */
#include "vsv_synth.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char **argv)
{
    const char *kind = argc > 2 ? argv[2] : "";
    synth_wind w;
    if (argc == 3 && (!strcmp(kind, "east") || !strcmp(kind, "flat") || !strcmp(kind, "nowind"))) {
        w = (synth_wind){.nx = 60,
                         .ny = 60,
                         .nz = 5,
                         .nsteps = 7,
                         .dxy = 4000,
                         .dz = 100,
                         .x0 = -118000,
                         .y0 = -118000,
                         .z0 = 50,
                         .lat1 = 30,
                         .lat2 = 60,
                         .flat = !strcmp(kind, "flat"),
                         .t0 = vsv_time_from_civil(2020, 1, 1, 0, 0, 0),
                         .wind = {10, 0, 0},
                         .vector = 1};
        if (!strcmp(kind, "nowind"))
            w.vector = -1, w.scalar = "O3", w.units = "ppb";
    } else if ((argc == 6 || (argc == 7 && !strcmp(argv[6], "novector"))) && !strcmp(kind, "uniform")) {
        synth_wind_uniform(&w, strtof(argv[3], NULL), strtof(argv[4], NULL), strtof(argv[5], NULL));
        w.vector = argc == 6;
    } else {
        fprintf(stderr, "usage: windfile OUT east|flat|nowind, or windfile OUT uniform E N U [novector]\n");
        return 2;
    }
    char err[512];
    if (synth_wind_write(argv[1], &w, err, sizeof err)) {
        fprintf(stderr, "windfile: %s\n", err);
        return 1;
    }
    return 0;
}
