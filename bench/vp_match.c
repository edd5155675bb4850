/* vp_match.c — VolPack and the shear-warp set up alike (vp_match.h). */
#include "vp_match.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int vp_series_open(vp_series *S, const char *name, const char *path, const char *species, int first, int n)
{
    memset(S, 0, sizeof *S);
    S->name = name;
    if (n < 1 || n > VP_MAXSTEPS || vsv_file_open(path, &S->f) || vsv_decoder_create(S->f, &S->d)) {
        fprintf(stderr, "%s: %s: %s\n", program_invocation_short_name, path, S->f ? vsv_file_error(S->f) : "cannot open");
        return -1;
    }
    const vsv_meta *m = vsv_file_meta(S->f);
    const int s = vsv_meta_find_var(m, species);
    if (s < 0) {
        fprintf(stderr, "%s: %s: no species %s\n", program_invocation_short_name, path, species);
        return -1;
    }
    const vsv_quant *q = vsv_file_quant(S->f, s);
    S->lo = q->lo;
    S->hi = q->hi > q->lo ? q->hi : q->lo + 1;
    /* the matched opacity curve over the 8-bit range */
    char text[512], msg[128];
    int k = snprintf(text, sizeof text, "colormap greys\nrange %.9g %.9g\nopacity", S->lo, S->hi);
    for (int i = 0; i < 16; i++)
        k += snprintf(text + k, sizeof text - (size_t)k, " %.6f", -log(1 - 0.95 * i / 15.0) / 3);
    snprintf(text + k, sizeof text - (size_t)k, "\n");
    if (vsv_tf_parse(&S->tf, text, msg, sizeof msg)) {
        fprintf(stderr, "%s: %s\n", program_invocation_short_name, msg);
        return -1;
    }
    S->nsteps = n;
    const size_t nv = (size_t)m->nx * m->ny * m->nz;
    for (int t = 0; t < n; t++) {
        if (vsv_volume_create(S->f, &S->vol[t]) || vsv_volume_load(S->vol[t], S->d, first + t, s)) {
            fprintf(stderr, "%s: %s: step %d: %s\n", program_invocation_short_name, path, first + t,
                    vsv_file_error(S->f));
            return -1;
        }
        S->vox[t] = calloc(nv, 4);
        if (!S->vox[t])
            return -1;
        for (int kz = 0; kz < m->nz; kz++)
            for (int j = 0; j < m->ny; j++)
                for (int i = 0; i < m->nx; i++) {
                    const float v = vsv_volume_at(S->vol[t], i, j, kz);
                    const double u = v == v ? (v - S->lo) / (S->hi - S->lo) : 0;
                    const unsigned char dv = (unsigned char)lrint(255 * fmin(1, fmax(0, u)));
                    const uint16_t si = dv;
                    unsigned char *p = S->vox[t] + 4 * (((size_t)kz * m->ny + j) * m->nx + i);
                    memcpy(p, &si, 2);
                    p[2] = dv;
                }
    }
    S->iso = *m; /* cubic cells, as VolPack sees them */
    S->iso.spacing[0] = S->iso.spacing[1] = S->iso.spacing[2] = 1000;
    S->iso.vert_kind = VSV_VERT_EVEN;
    S->iso.levels = NULL;
    S->iso.terrain = NULL;
    S->iso.landuse = NULL;
    S->iso.nheights = 0;
    S->iso.heights = NULL;
    return 0;
}

void vp_series_free(vp_series *S)
{
    for (int t = 0; t < S->nsteps; t++) {
        vsv_volume_free(S->vol[t]);
        free(S->vox[t]);
    }
    vsv_decoder_free(S->d);
    vsv_file_free(S->f);
}

void vp_check(vpContext *vpc, int rc)
{
    if (rc != VP_OK) {
        fprintf(stderr, "%s: VolPack: %s\n", program_invocation_short_name, vpGetErrorString(vpGetError(vpc)));
        exit(1);
    }
}

void vp_step(vpContext *vpc, const vp_series *S, int t)
{
    const vsv_meta *m = &S->iso;
    vpSetRawVoxels(vpc, S->vox[t], (int)((size_t)m->nx * m->ny * m->nz * 4), 4, 4 * m->nx, 4 * m->nx * m->ny);
}

vpContext *vp_setup(const vp_series *S, unsigned char *image)
{
    const vsv_meta *m = &S->iso;
    vpContext *vpc = vpCreateContext();
    vpSetVolumeSize(vpc, m->nx, m->ny, m->nz);
    /* voxel = {uint16 shade index, uint8 density, pad}: VolPack wants the
     * shading field first and two bytes wide */
    vpSetVoxelSize(vpc, 4, 2, 1, 1);
    vpSetVoxelField(vpc, 0, 2, 0, 255);
    vpSetVoxelField(vpc, 1, 1, 2, 255);
    vp_step(vpc, S, 0);
    /* per voxel of level i: our colour and our opacity over one cell */
    static float ramp[256], shade[256];
    for (int i = 0; i < 256; i++) {
        float rgba[4];
        vsv_tf_eval(&S->tf, (float)(S->lo + (S->hi - S->lo) * i / 255.0), rgba);
        ramp[i] = (float)(1 - exp(-3.0 * rgba[3]));
        shade[i] = 255 * rgba[0]; /* VolPack's colours run 0..255 */
    }
    vpSetClassifierTable(vpc, 0, 1, ramp, sizeof ramp);
    vp_check(vpc, vpSetLookupShader(vpc, 1, 1, 0, shade, sizeof shade, 0, NULL, 0));
    vpSetd(vpc, VP_MIN_VOXEL_OPACITY, 1.0 / 255);
    vpSetd(vpc, VP_MAX_RAY_OPACITY, 0.998);
    vpSetImage(vpc, image, VP_SIZE, VP_SIZE, VP_SIZE * 2, VP_LUMINANCEA);
    vpCurrentMatrix(vpc, VP_PROJECT);
    vpIdentityMatrix(vpc);
    vpWindow(vpc, VP_PARALLEL, -0.75, 0.75, -0.75, 0.75, -0.75, 0.75);
    return vpc;
}

void vp_view(vpContext *vpc, int v)
{
    vpCurrentMatrix(vpc, VP_MODEL);
    vpIdentityMatrix(vpc);
    vpSeti(vpc, VP_CONCAT_MODE, VP_CONCAT_LEFT);
    vpRotate(vpc, VP_X_AXIS, -60.0);
    vpSeti(vpc, VP_CONCAT_MODE, VP_CONCAT_RIGHT);
    vpRotate(vpc, VP_Z_AXIS, 45.0 * (v + 1));
}

void vp_scene(const vp_series *S, vsv_layer *layer, vsv_scene *sc)
{
    *layer = (vsv_layer){S->vol[0], &S->tf, 1, 1};
    *sc = (vsv_scene){.meta = &S->iso, .layers = layer, .nlayers = 1, .exaggeration = 1};
}

void vp_camera(const vsv_scene *sc, int v, vsv_camera *cam)
{
    double mn[3], mx[3];
    vsv_scene_bounds(sc, mn, mx);
    vsv_camera_orbit(cam, sc, 225 + 45 * v, 30, 0, VP_SIZE, VP_SIZE);
    cam->fov_deg = 0;
    cam->ortho_height = 1.5 * fmax(fmax(mx[0] - mn[0], mx[1] - mn[1]), mx[2] - mn[2]);
}

double vp_psnr(const unsigned char *vp, const float *ours)
{
    double se = 0;
    for (int y = 0; y < VP_SIZE; y++)
        for (int x = 0; x < VP_SIZE; x++) {
            const unsigned char *a = vp + 2 * ((size_t)y * VP_SIZE + x);
            const float *b = ours + 4 * ((size_t)y * VP_SIZE + x);
            const double dl = a[0] - 255.0 * fmin(1, b[0]), da = a[1] - 255.0 * fmin(1, b[3]);
            se += dl * dl + da * da;
        }
    const double mse = se / (2.0 * VP_SIZE * VP_SIZE);
    return mse > 0 ? 10 * log10(255.0 * 255.0 / mse) : INFINITY;
}
