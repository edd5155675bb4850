/* bench_camx.c — conversion of a synthetic continental CAMx run: writes a
 * UAM-IV AVERAGE file (NX x NY cells, NZ layers, NSPEC species, HOURS hours;
 * smooth plumes over a background, like ozone and PM), then prints its size;
 * the shell script times vsv-convert and the peers on it. Usage:
 *   bench_camx OUT.avrg [HOURS] [NX NY NZ NSPEC] */
#include "vsv_uamiv.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct ctx {
    int nx, ny;
} ctx;

static void fill(void *p, int hour, int spec, int layer, float *plane)
{
    const ctx *c = p;
    const double decay = exp(-0.15 * layer), phase = 0.26 * hour + 0.7 * spec;
    for (int j = 0; j < c->ny; j++)
        for (int i = 0; i < c->nx; i++) {
            const double x = (double)i / c->nx, y = (double)j / c->ny;
            double v = 0.02 + 0.01 * sin(6 * x + phase) * cos(5 * y);
            for (int s = 0; s < 4; s++) {
                const double cx = 0.2 + 0.2 * s + 0.01 * hour, cy = 0.3 + 0.1 * s,
                             r2 = ((x - cx) * (x - cx) + (y - cy) * (y - cy)) / 0.002;
                if (r2 < 20)
                    v += 0.08 * exp(-r2) * decay;
            }
            plane[j * c->nx + i] = (float)(v * (1 + 0.05 * spec));
        }
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_camx OUT.avrg [HOURS] [NX NY NZ NSPEC]\n");
        return 2;
    }
    vsv_uamiv_header h;
    memset(&h, 0, sizeof h);
    h.nhours = argc > 2 ? atoi(argv[2]) : 24;
    h.nx = argc > 6 ? atoi(argv[3]) : 200;
    h.ny = argc > 6 ? atoi(argv[4]) : 200;
    h.nz = argc > 6 ? atoi(argv[5]) : 25;
    h.nspec = argc > 6 ? atoi(argv[6]) : 40;
    snprintf(h.name, sizeof h.name, "AVERAGE");
    snprintf(h.note, sizeof h.note, "Vesuvius benchmark: synthetic continental run");
    h.nseg_or_tz = 0;
    h.bdate = 16182;
    h.edate = 16183;
    h.ehour = 0;
    h.xorg = -2400000;
    h.yorg = -1800000;
    h.dx = h.dy = 12000;
    h.iproj = 2;
    h.plon = -97;
    h.plat = 40;
    h.tlat1 = 33;
    h.tlat2 = 45;
    h.rec3[0] = h.rec3[1] = 1;
    h.rec3[2] = h.nx;
    h.rec3[3] = h.ny;
    h.species = calloc((size_t)h.nspec, sizeof *h.species);
    int *dates = malloc(2 * sizeof(int) * (size_t)h.nhours);
    float *hours = malloc(2 * sizeof(float) * (size_t)h.nhours);
    for (int s = 0; s < h.nspec; s++)
        snprintf(h.species[s], sizeof h.species[s], s < 30 ? "GAS%02d" : "PM%02d", s % 100);
    for (int t = 0; t < h.nhours; t++) {
        dates[2 * t] = dates[2 * t + 1] = 16182 + t / 24;
        hours[2 * t] = (float)(t % 24);
        hours[2 * t + 1] = (float)(t % 24 + 1);
    }
    ctx c = {h.nx, h.ny};
    int rc = vsv_uamiv_write(argv[1], &h, 0, dates, hours, fill, &c);
    free(h.species);
    free(dates);
    free(hours);
    return rc ? 1 : 0;
}
