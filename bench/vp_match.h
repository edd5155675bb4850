/* vp_match.h — VolPack (Debian libvolpack1-dev) and Vesuvius's shear-warp
 * set up to draw the same picture, shared by bench_volpack and
 * bench_classify.
 *
 * Both sides see the same 8-bit volume of each step (a species quantised to
 * 0..255 over the series' range: VolPack's density, and on our side the
 * float values it stands for), in cubic cells. Opacity is matched per unit
 * length: our transfer function's opacity curve o(t) (colour map viridis, 16
 * samples of o(t) = -ln(1 - 0.95 t) / 3, linear between) makes a cell of
 * length 1 as opaque as 1 - e^(-3 o) (VSV_SIGMA_PER_CELL = 3), and VolPack,
 * which composites one sample per voxel step, gets exactly that per voxel
 * (and the same colour, VolPack in 3-channel colour: its shading table
 * gives red, green and blue) from a table built by evaluating our transfer function
 * at each of the 256 levels (VolPack corrects a voxel's opacity a to
 * 1 - (1 - a)^L for the length L of the ray in a slice, voxels as unit, as
 * we do). Ray termination 0.998 on both; VolPack skips voxels of opacity
 * below 1/255. No lighting on either side. Image 512x512, parallel
 * projection, 1.5 times the longest side across; view v from azimuth
 * 225 + 45 v (clockwise from north), 30 degrees up, looking at the middle
 * of the volume. VolPack's conventions that differ from ours (its rotations'
 * sense, image rows from the bottom, left-handed image space, voxel and
 * pixel positions at corners) are undone in vp_setup, vp_view and vp_psnr;
 * the closed-form box of vp_write_box checks them (bench_volpack --box). */
#ifndef VP_MATCH_H
#define VP_MATCH_H

#include "vsv_render.h"

#include <volpack.h>

enum { VP_SIZE = 512, VP_MAXSTEPS = 4 };

/* A series: nsteps volumes of one species of a .vsv. */
typedef struct vp_series {
    const char *name;
    vsv_file *f;
    vsv_decoder *d;
    vsv_meta iso; /* the file's grid in cubic cells, as VolPack sees it */
    int nsteps;
    vsv_volume *vol[VP_MAXSTEPS];
    unsigned char *vox[VP_MAXSTEPS]; /* VolPack's voxels {u16 shade index, u8 density, pad} */
    double lo, hi;
    vsv_tf tf; /* the matched transfer function */
} vp_series;

/* Opens steps first .. first + n - 1 of species in path; 0 or -1 (told on
 * stderr). */
int vp_series_open(vp_series *S, const char *name, const char *path, const char *species, int first, int n);
void vp_series_free(vp_series *S);
/* VolPack on step 0 with the matched tables, rendering into image
 * (VP_SIZE^2 RGBA pixels, 4 bytes each). */
vpContext *vp_setup(const vp_series *S, unsigned char *image);
/* Loads step t's voxels into VolPack (raw; classify after). */
void vp_step(vpContext *vpc, const vp_series *S, int t);
/* VolPack's model matrix for view v. */
void vp_view(vpContext *vpc, int v);
/* Exits 1 with VolPack's message unless rc is VP_OK. */
void vp_check(vpContext *vpc, int rc);
/* Our scene for layer (whose volume and transfer function the caller sets)
 * and the camera of view v. */
void vp_scene(const vp_series *S, vsv_layer *layer, vsv_scene *sc);
void vp_camera(const vsv_scene *sc, int v, vsv_camera *cam);
/* PSNR (dB, 8-bit scale) between VolPack's premultiplied RGBA image and
 * ours (premultiplied RGBA floats), over the four channels; INFINITY when
 * equal. */
double vp_psnr(const unsigned char *vp, const float *ours);
/* The same against ours as premultiplied 8-bit RGBA (vsv_render_rgba8). */
double vp_psnr8(const unsigned char *vp, const unsigned char *ours);
/* Writes a closed-form volume to path: species "box", one step, an
 * off-centre box of values rising along x in an otherwise empty grid of
 * three different lengths (a swapped, mirrored or shifted axis shows in
 * the PSNR). 0 or -1 (told on stderr). */
int vp_write_box(const char *path);
/* gen-plume's raw 256x256x64 float32 steps (names[0..n-1] in dir, its
 * plume.info beside them) written to out as a .vsv of species "plume" (16
 * bits, range 0 to gen-plume's maximum); a name of plume_t1.f32 with "haze"
 * in out gets gen-plume's haze floor (8/255 of the maximum). 0 or -1. */
int vp_write_plume(const char *dir, const char *out, const char *const *names, int n);
/* Writes both pictures side by side (VolPack's left) as a PNG; 0 or -1. */
int vp_dump(const char *path, const unsigned char *vp, const float *ours);

#endif
