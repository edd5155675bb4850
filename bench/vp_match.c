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
        fprintf(stderr, "%s: %s: %s\n", program_invocation_short_name, path,
                S->f ? vsv_file_error(S->f) : "cannot open");
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
    int k = snprintf(text, sizeof text, "colormap viridis\nrange %.9g %.9g\nopacity", S->lo, S->hi);
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
    S->iso.nmoves = 0; /* a moving nest: the grid where it is, not every place it stands */
    S->iso.moves = NULL;
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
    static float ramp[256], shade[256][3];
    for (int i = 0; i < 256; i++) {
        float rgba[4];
        vsv_tf_eval(&S->tf, (float)(S->lo + (S->hi - S->lo) * i / 255.0), rgba);
        ramp[i] = (float)(1 - exp(-3.0 * rgba[3]));
        for (int c = 0; c < 3; c++)
            shade[i][c] = 255 * rgba[c]; /* VolPack's colours run 0..255: three channels */
    }
    vpSetClassifierTable(vpc, 0, 1, ramp, sizeof ramp);
    vp_check(vpc, vpSetLookupShader(vpc, 3, 1, 0, &shade[0][0], sizeof shade, 0, NULL, 0));
    vpSetd(vpc, VP_MIN_VOXEL_OPACITY, 1.0 / 255);
    vpSetd(vpc, VP_MAX_RAY_OPACITY, 0.998);
    vpSetImage(vpc, image, VP_SIZE, VP_SIZE, VP_SIZE * 4, VP_RGBA);
    vpCurrentMatrix(vpc, VP_PROJECT);
    vpIdentityMatrix(vpc);
    /* 1.5 times the volume's longest side across, as our camera; moved by
     * half a pixel, since VolPack's pixel (x, y) is the point its window
     * maps to x, y and ours the middle of the pixel */
    const double hp = 0.5 * 1.5 / VP_SIZE;
    vpWindow(vpc, VP_PARALLEL, -0.75 + hp, 0.75 + hp, -0.75 + hp, 0.75 + hp, -0.75, 0.75);
    return vpc;
}

void vp_view(vpContext *vpc, int v)
{
    /* VolPack's conventions (its manual pages and vp_view.c): a rotation by
     * d degrees turns clockwise looking along the positive axis (the
     * transpose of the usual matrix); its object space puts voxel i of n at
     * (i - n/2) / max(n) (ours: the middle of cell i at i + 1/2 - n/2); its
     * viewport flips depth into left-handed image coordinates, so a
     * right-handed volume is handed over mirrored in z (without the mirror
     * the silhouettes agree but it composites the far side first: a box
     * brighter at the top came out as if seen from below). So: our cells'
     * middles (half a voxel along each axis), the mirror, then the turn
     * about the vertical (view v: our azimuth 225 + 45 v, clockwise from
     * north) and the tilt (30 degrees up), in VolPack's sense of rotation. */
    int n[3];
    vpGeti(vpc, VP_XLEN, &n[0]);
    vpGeti(vpc, VP_YLEN, &n[1]);
    vpGeti(vpc, VP_ZLEN, &n[2]);
    const double half = 0.5 / fmax(fmax(n[0], n[1]), n[2]);
    vpCurrentMatrix(vpc, VP_MODEL);
    vpIdentityMatrix(vpc);
    vpSeti(vpc, VP_CONCAT_MODE, VP_CONCAT_RIGHT); /* M = M * R: the last call acts first */
    vpRotate(vpc, VP_X_AXIS, -60.0);
    vpRotate(vpc, VP_Z_AXIS, -45.0 * (v + 1));
    vpScale(vpc, 1, 1, -1);
    vpTranslate(vpc, half, half, half);
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
    /* VolPack looks at the middle of the volume; the orbit at 30 % of its
     * height: the eye moved so that it looks at the middle (parallel rays:
     * only the line through the middle matters) */
    double len = 0;
    for (int a = 0; a < 3; a++)
        len += cam->dir[a] * cam->dir[a];
    len = sqrt(len);
    for (int a = 0; a < 3; a++)
        cam->pos[a] = 0.5 * (mn[a] + mx[a]) - 4 * cam->ortho_height * cam->dir[a] / len;
}

/* VolPack's image has its row 0 at the bottom (its viewport maps the eye's
 * y = -1 to row 0); ours at the top. */
static const unsigned char *vp_row(const unsigned char *vp, int y)
{
    return vp + 4 * (size_t)(VP_SIZE - 1 - y) * VP_SIZE;
}

/* ours as floats (f) or bytes (b) */
static double psnr(const unsigned char *vp, const float *f, const unsigned char *b)
{
    double se = 0;
    for (int y = 0; y < VP_SIZE; y++)
        for (int x = 0; x < VP_SIZE; x++) {
            const unsigned char *a = vp_row(vp, y) + 4 * x;
            const size_t i = 4 * ((size_t)y * VP_SIZE + x);
            for (int c = 0; c < 4; c++) {
                const double d = a[c] - (f ? 255.0 * fmin(1, f[i + c]) : b[i + c]);
                se += d * d;
            }
        }
    const double mse = se / (4.0 * VP_SIZE * VP_SIZE);
    return mse > 0 ? 10 * log10(255.0 * 255.0 / mse) : INFINITY;
}

double vp_psnr(const unsigned char *vp, const float *ours) { return psnr(vp, ours, NULL); }

double vp_psnr8(const unsigned char *vp, const unsigned char *ours) { return psnr(vp, NULL, ours); }

int vp_dump(const char *path, const unsigned char *vp, const float *ours)
{
    /* left VolPack's picture, right ours (colour over black), each row
     * of both the same row of the image */
    unsigned char *rgb = malloc((size_t)VP_SIZE * 2 * VP_SIZE * 3);
    if (!rgb)
        return -1;
    for (int y = 0; y < VP_SIZE; y++)
        for (int x = 0; x < VP_SIZE; x++) {
            unsigned char *l = rgb + 3 * ((size_t)y * 2 * VP_SIZE + x), *r = l + 3 * VP_SIZE;
            for (int c = 0; c < 3; c++) {
                l[c] = vp_row(vp, y)[4 * x + c];
                r[c] = (unsigned char)lrintf(255 * fmin(1, ours[4 * ((size_t)y * VP_SIZE + x) + c]));
            }
        }
    char err[256];
    const int rc = vsv_png_write(path, rgb, 2 * VP_SIZE, VP_SIZE, err, sizeof err);
    if (rc)
        fprintf(stderr, "%s: %s\n", program_invocation_short_name, err);
    free(rgb);
    return rc;
}

/* A writer of m's one variable quantised over [0, hi], the library's
 * defaults otherwise. */
static int writer_open(const char *path, const vsv_meta *m, float hi, vsv_writer **w)
{
    vsv_pack_var pv;
    vsv_pack_var_init(&pv);
    pv.lo = 0;
    pv.hi = hi;
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.vars = &pv;
    return vsv_writer_create(path, m, &o, w);
}

/* Finishes w unless rc already failed, says any failure on stderr, frees w:
 * the result. */
static int writer_close(vsv_writer *w, const char *path, int rc)
{
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    if (rc)
        fprintf(stderr, "%s: %s: %s\n", program_invocation_short_name, path, w ? vsv_writer_error(w) : "cannot create");
    vsv_writer_free(w);
    return rc;
}

int vp_write_box(const char *path)
{
    /* 64 x 48 x 16 cells (three different lengths, so a swapped axis shows);
     * a box off the middle, [8, 40) x [6, 22) x [2, 12), whose values rise
     * along x from a quarter to all of the range (so a mirrored axis shows);
     * 0 elsewhere */
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = 64, m.ny = 48, m.nz = 16;
    m.spacing[0] = m.spacing[1] = m.spacing[2] = 1000;
    vsv_meta_add_var(&m, "box", "1", "a box");
    const size_t nv = (size_t)m.nx * m.ny * m.nz;
    float *buf = calloc(nv, sizeof *buf);
    for (int k = 2; k < 12; k++)
        for (int j = 6; j < 22; j++)
            for (int i = 8; i < 40; i++)
                buf[((size_t)k * m.ny + j) * m.nx + i] = 0.25f + 0.75f * (i - 8) / 31.0f;
    vsv_writer *w = NULL;
    const float *fields[1] = {buf};
    int rc = buf ? writer_open(path, &m, 1, &w) : -1;
    if (!rc)
        rc = vsv_writer_add_step(w, 0, fields);
    rc = writer_close(w, path, rc);
    vsv_meta_clear(&m);
    free(buf);
    return rc;
}

/* gen-plume's raw 256x256x64 float32 steps written as a .vsv (16 bits,
 * the library's defaults). */
int vp_write_plume(const char *dir, const char *out, const char *const *names, int n)
{
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = 256, m.ny = 256, m.nz = 64;
    m.spacing[0] = m.spacing[1] = m.spacing[2] = 1000;
    vsv_meta_add_var(&m, "plume", "1", "gen-plume");
    const size_t nv = (size_t)m.nx * m.ny * m.nz;
    float *buf = malloc(nv * 4);
    /* the range from 0 to the maximum of gen-plume (its plume.info), as its
     * 8-bit files: the haze's floor is not empty */
    float vmax = 0;
    char path[1024];
    snprintf(path, sizeof path, "%s/plume.info", dir);
    FILE *fi = fopen(path, "r");
    if (!fi || fscanf(fi, "nx=%*d ny=%*d nz=%*d vmax=%f", &vmax) != 1 || !(vmax > 0)) {
        fprintf(stderr, "%s: %s: no vmax\n", program_invocation_short_name, path);
        if (fi)
            fclose(fi);
        return -1;
    }
    fclose(fi);
    vsv_writer *w = NULL;
    int rc = writer_open(out, &m, vmax, &w);
    for (int t = 0; t < n && !rc; t++) {
        snprintf(path, sizeof path, "%s/%s", dir, names[t]);
        FILE *fp = fopen(path, "rb");
        if (!fp || fread(buf, 4, nv, fp) != nv) {
            fprintf(stderr, "%s: %s: cannot read %zu floats\n", program_invocation_short_name, path, nv);
            rc = -1;
        }
        if (fp)
            fclose(fp);
        if (!rc && !strcmp(names[t], "plume_t1.f32") && strstr(out, "haze")) {
            /* gen-plume's haze rule on the next step: a floor of 8/255 of the
             * maximum */
            for (size_t i = 0; i < nv; i++)
                buf[i] = fmaxf(buf[i], 8.0f / 255.0f * vmax);
        }
        const float *fields[1] = {buf};
        if (!rc)
            rc = vsv_writer_add_step(w, 3600 * (int64_t)t, fields);
    }
    rc = writer_close(w, out, rc);
    vsv_meta_clear(&m);
    free(buf);
    return rc;
}
