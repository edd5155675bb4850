/* vsv_renderer.h — the renderer's state, shared by the frame driver
 * (vsv_render.c), the raycaster (vsv_raycast.c) and its sampling copies
 * (vsv_sampling.c). Private to render/. */
#ifndef VSV_RENDERER_H
#define VSV_RENDERER_H

#include "vsv_pool.h"
#include "vsv_rc.h"
#include "vsv_sw.h"

#define VSV_RC_TILE 16 /* the raycaster's tiles: 16x16 pixels an item */

struct vsv_renderer {
    vsv_render_opts o;
    vsv_pool pool;
    /* the job */
    const vsv_scene *sc;
    const vsv_camera *cam;
    float *rgba, *depth;
    float *f32; /* vsv_render_rgba8 beside the raycaster: its float picture */
    size_t f32_cap;
    vsv_geo g;
    int ntiles, tiles_x;
    /* skipping (vsv_rc_prepare_skip): per block, the skip distances, scratch
     * and per-layer clear flags (allocated when the scene grows, not per
     * frame); kept while skip_key stays the same */
    unsigned char *skip;
    size_t skip_cap;
    uint64_t skip_key;
    int skip_any;
    /* the fine bits (vsv_rc_frame.fine) and the tables' opacity counts */
    uint32_t *fine;
    size_t fine_cap;
    int fine_nb[3];
    int *alpha_cnt;
    size_t alpha_cap;
    /* the visible layers of this frame, as the raycaster reads them */
    vsv_rc_layer *act;
    int act_cap;
    vsv_rc_frame frame;
    /* the sampling copies, one per scene layer (vsv_rc_cells), and those
     * this frame rebuilds */
    vsv_rc_copy *copy, **build;
    int copy_cap, nbuild;
    double copy_seconds;   /* the last rebuild of sampling copies */
    int simd;              /* the CPU has AVX2 and FMA (and VSV_SIMD is not 0) */
    vsv_rc_kernel *kernel; /* sixteen rays at once, or NULL: one at a time */
    vsv_sw *sw;            /* shear-warp state, for VSV_RENDER_SHEARWARP */
    vsv_rays rays;         /* the camera's rays, for this frame */
    /* the ground per pixel, for ground_cam and ground_geo */
    vsv_ground *ground;
    size_t ground_cap;
    vsv_camera ground_cam;
    vsv_geo ground_geo;
    int ground_valid;
    /* the surfaces this frame's rays end on: the ground cache, or with
     * slices the ground merged with them (sliced, redone every frame);
     * NULL: none */
    const vsv_ground *surf_read;
    vsv_ground *surf;
    size_t surf_cap;
    vsv_native native; /* native levels placed at their heights */
    /* opaque meshes (vsv_mesh_draw.c): an extractor per scene iso, kept
     * across frames, and this frame's triangles on the screen */
    vsv_iso *iso[VSV_SCENE_ISO_MAX];
    struct vsv_mesh_frame *meshf;
};

/* Before any renderer's frame: native levels placed at their heights (*psc
 * becomes the scene over the resampled volumes), the geometry (r->g), the
 * rays (r->rays), the ground cache and the slices: the surface each pixel's
 * ray ends on (r->surf_read, NULL: none). 0 or a VSV_E* code. */
int vsv_render_surfaces(vsv_renderer *r, const vsv_scene **psc, const vsv_camera *cam);
/* The raycaster's frame (r->frame, r->act, and with copies the sampling
 * copies to rebuild in r->build) for scene sc; then, with the copies built,
 * its skipping (r->skip, r->frame.skip). */
int vsv_rc_prepare_frame(vsv_renderer *r, const vsv_scene *sc, int copies);
int vsv_rc_prepare_skip(vsv_renderer *r);
/* Layer L's table: per entry, how many entries before it have some
 * opacity (VSV_TF_LUT + 1 counts); and whether L makes every value in
 * [lo, hi] transparent (the entries its lookup may read have none). */
void vsv_rc_alpha_counts(const vsv_rc_layer *L, int *cnt);
int vsv_rc_layer_clear(const vsv_rc_layer *L, const int *cnt, float lo, float hi);
/* Pool jobs on the renderer ctx: one tile of the raycaster; one image row of
 * the ground cache (r->ground); brick item % nbricks of the sampling copy
 * item / nbricks being rebuilt. */
void vsv_rc_tile(void *ctx, int tile, int thread);
void vsv_rc_ground_row(void *ctx, int py, int thread);
void vsv_rc_copy_brick(void *ctx, int item, int thread);
/* Pool job: one image row of r->surf, the ground and the scene's slices
 * (vsv_slice.c), for r->sc, r->cam, r->g and r->rays. */
void vsv_rc_slice_row(void *ctx, int py, int thread);
/* r->surf grown to hold n pixels (kept between frames); 0 or VSV_ENOMEM. */
int vsv_rc_surf_reserve(vsv_renderer *r, size_t n);
/* The scene's opaque meshes (in: the scene as given, before native levels
 * are resampled): its isosurfaces extracted and its lines' tubes built,
 * drawn into r->surf over what it holds (r->surf_read's surfaces, copied
 * first when r->surf does not hold them yet), on the renderer's pool. 0 or
 * a VSV_E* code. */
int vsv_rc_meshes(vsv_renderer *r, const vsv_scene *in, const vsv_camera *cam);
void vsv_rc_meshes_free(vsv_renderer *r);
/* A line's tube and arrowhead (vsv_tube.c): vertices in world metres with
 * z already exaggerated, unit normals, triangles; the arrays grow (kept
 * between lines). */
typedef struct vsv_tube {
    float *pos, *nrm;
    uint32_t *tri;
    int nv, nt, vcap, tcap;
    double *q; /* the line's points kept, exaggerated (scratch) */
    int qcap;
} vsv_tube;
/* Builds line L's tube under exaggeration E into t (replacing what it
 * held). 0, VSV_EINVAL (a point not finite, a radius not positive) or
 * VSV_ENOMEM. */
int vsv_tube_build(vsv_tube *t, const vsv_scene_line *L, double E);
void vsv_tube_free(vsv_tube *t);
/* Runs extractor s on pool (instead of its own threads) from now on. */
void vsv_iso_use_pool(vsv_iso *s, vsv_pool *pool);
/* vsv_slice_range, with *work (when not NULL) set to the values it took:
 * per curtain edge a column per cell it crosses on the grid, whatever the
 * cells' size (for tests). */
int vsv_slice_range_work(const vsv_scene *sc, double *lo, double *hi, int64_t *work);

#endif
