/* bench_rc_peer.c — the Vesuvius raycaster as one peer of bench/bench_peers.py.
 *
 *   bench_rc_peer DIR FILE.vsv STEP SPECIES
 *   bench_rc_peer DIR --f32 FILE NX NY NZ DX DY DZ NAME
 *
 * Loads one species of one step (a .vsv, or a raw float32 volume, x fastest,
 * written first into DIR/volume.vsv through the project's writer, so both
 * kinds of input take the same path; its transfer function's range starts
 * at 0, so that a floor such as gen-plume's haze is seen), and writes for
 * the other peers:
 *   DIR/volume.f32  the decoded volume the raycaster samples (x fastest, row
 *                   j = 0 the southernmost, level k = 0 the lowest)
 *   DIR/scene.txt   its geometry (z exaggerated), the sample step, the early
 *                   termination threshold, the extinction scale, the transfer
 *                   function's table and the views (bench_peers.py reads it)
 * then answers commands on standard input, one line each:
 *   time THREADS SIZE        renders every view at SIZE x SIZE on THREADS
 *                            threads (the first time for THREADS and SIZE,
 *                            once untimed: the sampling copy is built then)
 *                            and prints each frame's seconds on one line
 *   image THREADS SIZE V OUT writes view V as 8-bit RGB (row 0 at the top,
 *                            premultiplied colour over black, no gamma) to
 *                            OUT, prints "ok"
 *   quit
 * Each frame's time is vsv_render() alone: the rays, the sampling, the
 * compositing into the float RGBA image. Early termination is set to VTK's
 * (a ray ends when its transmittance is below 255/32767), the only setting
 * the bench changes from the defaults. */
#include "vsv_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { VIEWS = 8 };
#define TERM (255.0 / 32767.0) /* VTK's fixed-point ray ends below 0xff of 0x7fff */

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static int die(const char *what)
{
    fprintf(stderr, "bench_rc_peer: %s\n", what);
    return 1;
}

/* A raw float32 volume into DIR/volume.vsv (one species, one step, 16-bit). */
static int pack_f32(const char *dir, char **argv, char *out, size_t cap)
{
    const int nx = atoi(argv[1]), ny = atoi(argv[2]), nz = atoi(argv[3]);
    const size_t n = (size_t)nx * ny * nz;
    float *v = malloc(n * sizeof *v);
    FILE *fp = fopen(argv[0], "rb");
    if (!v || !fp || fread(v, sizeof *v, n, fp) != n) {
        if (fp)
            fclose(fp);
        free(v);
        return die("cannot read the raw volume");
    }
    fclose(fp);
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = nx;
    m.ny = ny;
    m.nz = nz;
    m.spacing[0] = atof(argv[4]);
    m.spacing[1] = atof(argv[5]);
    m.spacing[2] = atof(argv[6]);
    m.origin[2] = m.spacing[2] / 2;
    m.vert_kind = VSV_VERT_EVEN;
    snprintf(m.model, sizeof m.model, "gen-plume");
    vsv_meta_add_var(&m, argv[7], "1", "synthetic benchmark volume");
    snprintf(out, cap, "%s/volume.vsv", dir);
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    vsv_writer *w = NULL;
    const float *f[1] = {v};
    int rc = vsv_writer_create(out, &m, &o, &w);
    if (!rc)
        rc = vsv_writer_add_step(w, 0, f);
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    if (rc)
        fprintf(stderr, "bench_rc_peer: %s\n", vsv_writer_error(w));
    vsv_writer_free(w);
    vsv_meta_clear(&m);
    free(v);
    return rc ? 1 : 0;
}

/* What the peer renders: one species of one step, its transfer function, the scene around it and the views. */
typedef struct {
    vsv_file *f;
    vsv_decoder *d;
    vsv_volume *vol;
    const vsv_meta *m;
    int s;
    vsv_tf tf;
    vsv_layer layer;
    vsv_scene sc;
    vsv_camera views[VIEWS];
} peer;

/* Reads the arguments, packs a raw volume first (into path, cap bytes), loads the species and sets up its
 * transfer function and scene; 1 after saying why it cannot. */
static int peer_load(peer *p, int argc, char **argv, char *path, size_t cap)
{
    if (argc < 5 || (!strcmp(argv[2], "--f32") && argc < 11))
        return die("usage: bench_rc_peer DIR FILE.vsv STEP SPECIES | DIR --f32 FILE NX NY NZ DX DY DZ NAME");
    const char *dir = argv[1], *file = argv[2], *species = argv[4];
    int step = atoi(argv[3]);
    if (!strcmp(argv[2], "--f32")) {
        if (pack_f32(dir, argv + 3, path, cap))
            return 1;
        file = path;
        step = 0;
        species = argv[10];
    }
    if (vsv_file_open(file, &p->f) || vsv_decoder_create(p->f, &p->d) || vsv_volume_create(p->f, &p->vol))
        return die(p->f ? vsv_file_error(p->f) : "cannot open the volume");
    const vsv_meta *m = p->m = vsv_file_meta(p->f);
    const int s = p->s = vsv_meta_find_var(m, species);
    char text[512], msg[128];
    vsv_tf *tf = &p->tf;
    if (s < 0 || vsv_volume_load(p->vol, p->d, step, s))
        return die("no such species or step");
    vsv_tf_default(m->vars[s].name, vsv_file_quant(p->f, s), text, sizeof text);
    if (vsv_tf_parse(tf, text, msg, sizeof msg))
        return die(msg);
    if (file == path && tf->scale == VSV_SCALE_LINEAR && tf->lo > 0) {
        tf->lo = 0; /* a raw volume's colours from 0: gen-plume's haze floor is seen */
        if (vsv_tf_prepare(tf))
            return die("bad transfer function");
    }
    p->layer = (vsv_layer){p->vol, tf, 1, 1};
    p->sc = (vsv_scene){.meta = m, .layers = &p->layer, .nlayers = 1, .exaggeration = 1};
    p->sc.exaggeration = vsv_scene_default_exaggeration(&p->sc);
    return 0;
}

/* the decoded volume, as the raycaster samples it (no data: 0, as VTK has none), into DIR/volume.f32 */
static int write_volume(const peer *p, const char *dir)
{
    const vsv_meta *m = p->m;
    char path[4096];
    snprintf(path, sizeof path, "%s/volume.f32", dir);
    FILE *fp = fopen(path, "wb");
    if (!fp)
        return die("cannot write volume.f32");
    for (int k = 0; k < m->nz; k++)
        for (int j = 0; j < m->ny; j++)
            for (int i = 0; i < m->nx; i++) {
                float v = vsv_volume_at(p->vol, i, j, k);
                v = v == v ? v : 0;
                fwrite(&v, sizeof v, 1, fp);
            }
    if (fclose(fp))
        return die("cannot write volume.f32");
    return 0;
}

/* the scene for the other peers, into DIR/scene.txt; sets the views */
static int write_scene(peer *p, const char *dir, const vsv_render_opts *o)
{
    const vsv_meta *m = p->m;
    const vsv_tf *tf = &p->tf;
    const double E = p->sc.exaggeration, dx = m->spacing[0], dy = m->spacing[1], dz = m->spacing[2] * E;
    char path[4096];
    snprintf(path, sizeof path, "%s/scene.txt", dir);
    FILE *fp = fopen(path, "w");
    if (!fp)
        return die("cannot write scene.txt");
    fprintf(fp, "species %s\ndims %d %d %d\n", m->vars[p->s].name, m->nx, m->ny, m->nz);
    fprintf(fp, "origin %.17g %.17g %.17g\nspacing %.17g %.17g %.17g\n", m->origin[0], m->origin[1], m->origin[2] * E,
            dx, dy, dz);
    fprintf(fp, "step %.17g\nterm %.17g\n", o->step_cells * fmin(fmin(dx, dy), dz), TERM);
    /* extinction per world unit of opacity-curve value 1 (vsv_raycast.c: the
     * slider, 1 here, times VSV_SIGMA_PER_CELL = 3 over the smaller cell edge) */
    fprintf(fp, "sigma %.17g\nunit %.17g\n", 3.0 / fmin(dx, dy), fmin(dx, dy));
    fprintf(fp, "lut %d\n", VSV_TF_LUT);
    for (int i = 0; i < VSV_TF_LUT; i++) {
        const double x = tf->base + i / tf->inv;
        fprintf(fp, "%.9g %.7g %.7g %.7g %.7g\n", tf->scale == VSV_SCALE_LOG ? exp(x) : x, tf->lut[i][0], tf->lut[i][1],
                tf->lut[i][2], tf->lut[i][3]);
    }
    fprintf(fp, "lo %.9g\nviews %d\n", tf->lo, VIEWS);
    for (int k = 0; k < VIEWS; k++) {
        vsv_camera_orbit(&p->views[k], &p->sc, 225 + 45 * k, 30, 0, 512, 512);
        const vsv_camera *c = &p->views[k];
        fprintf(fp, "%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", c->pos[0], c->pos[1], c->pos[2],
                c->dir[0], c->dir[1], c->dir[2], c->up[0], c->up[1], c->up[2], c->fov_deg);
    }
    if (fclose(fp))
        return die("cannot write scene.txt");
    return 0;
}

/* Answers the commands on standard input until quit or its end; 1 after saying why it cannot. */
static int serve(peer *p, vsv_render_opts *o)
{
    const vsv_scene *sc = &p->sc;
    vsv_renderer *r[3] = {NULL, NULL, NULL};
    int warm[3][2] = {{0}};
    float *img = NULL;
    int cap = 0;
    char line[8192];
    while (fgets(line, sizeof line, stdin)) {
        char cmd[16], out[4096] = "";
        int th = 0, size = 0, view = 0;
        if (sscanf(line, "%15s %d %d %d %4095s", cmd, &th, &size, &view, out) < 1 || !strcmp(cmd, "quit"))
            break;
        if (th < 1 || th > 2 || size < 16 || size > 4096 || view < 0 || view >= VIEWS)
            return die("bad command");
        if (!r[th]) {
            o->threads = th;
            o->term = TERM;
            if (vsv_renderer_create(o, &r[th]))
                return die("cannot start the renderer");
        }
        if (size > cap) {
            free(img);
            img = malloc(sizeof(float) * 4 * (size_t)size * size);
            if (!img)
                return die("out of memory");
            cap = size;
        }
        vsv_camera cam;
        if (!strcmp(cmd, "time")) {
            const int big = size > 512;
            double t[VIEWS];
            for (int k = 0; k < VIEWS; k++) {
                cam = p->views[k];
                cam.width = cam.height = size;
                if (!warm[th][big]) {
                    vsv_render(r[th], sc, &cam, img, NULL);
                    warm[th][big] = 1;
                }
                const double t0 = now();
                if (vsv_render(r[th], sc, &cam, img, NULL))
                    return die("render failed");
                t[k] = now() - t0;
            }
            for (int k = 0; k < VIEWS; k++)
                printf("%.6f%c", t[k], k + 1 < VIEWS ? ' ' : '\n');
        } else if (!strcmp(cmd, "image") && out[0]) {
            cam = p->views[view];
            cam.width = cam.height = size;
            if (vsv_render(r[th], sc, &cam, img, NULL))
                return die("render failed");
            unsigned char *rgb = malloc(3 * (size_t)size * size);
            FILE *op = fopen(out, "wb");
            if (!rgb || !op)
                return die("cannot write the image");
            for (size_t q = 0; q < (size_t)size * size; q++)
                for (int c = 0; c < 3; c++) {
                    const float v = img[4 * q + c] * 255 + 0.5f;
                    rgb[3 * q + c] = (unsigned char)(v < 0 ? 0 : v > 255 ? 255 : v);
                }
            const int bad = fwrite(rgb, 3, (size_t)size * size, op) != (size_t)size * size;
            free(rgb);
            if (fclose(op) || bad)
                return die("cannot write the image");
            printf("ok\n");
        } else {
            return die("bad command");
        }
        fflush(stdout);
    }
    for (int t = 0; t < 3; t++)
        vsv_renderer_free(r[t]);
    free(img);
    return 0;
}

int main(int argc, char **argv)
{
    char path[4096];
    peer p;
    memset(&p, 0, sizeof p);
    if (peer_load(&p, argc, argv, path, sizeof path) || write_volume(&p, argv[1]))
        return 1;
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    if (write_scene(&p, argv[1], &o))
        return 1;
    printf("ready\n");
    fflush(stdout);
    if (serve(&p, &o))
        return 1;
    vsv_volume_free(p.vol);
    vsv_decoder_free(p.d);
    vsv_file_free(p.f);
    return 0;
}
