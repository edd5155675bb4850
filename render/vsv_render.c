/* vsv_render.c — the renderer behind vsv_render.h: options, the renderer's
 * life (its pool, its kernels) and the frame driver that runs the ground
 * cache, the shear-warp's phases or the raycaster's tiles on the pool. */
#include "vsv_renderer.h"

#include <cpuid.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

void vsv_render_opts_init(vsv_render_opts *o)
{
    memset(o, 0, sizeof *o);
    o->kind = VSV_RENDER_RAYCAST;
    o->step_cells = 0.5;
    o->term = 1.0 / 512;
}

/* F16C from CPUID (leaf 1, ECX): clang 14 has no __builtin_cpu_supports("f16c") */
static int cpu_f16c(void)
{
    unsigned a, b, c, d;
    return __get_cpuid(1, &a, &b, &c, &d) && (c & bit_F16C);
}

int vsv_renderer_create(const vsv_render_opts *o, vsv_renderer **out)
{
    vsv_renderer *r = *out = calloc(1, sizeof *r);
    if (!r)
        return VSV_ENOMEM;
    vsv_opacity_init();
    if (o)
        r->o = *o;
    else
        vsv_render_opts_init(&r->o);
    if (r->o.kind != VSV_RENDER_RAYCAST && r->o.kind != VSV_RENDER_SHEARWARP)
        return VSV_EUNSUPPORTED;
    const char *simd = getenv("VSV_SIMD");
    __builtin_cpu_init();
    r->simd = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && !(simd && !strcmp(simd, "0"));
    r->kernel = NULL;
    if (r->simd)
        r->kernel = __builtin_cpu_supports("avx512f") && !(simd && !strcmp(simd, "avx2")) ? vsv_raycast16_avx512
                                                                                          : vsv_raycast16;
    if (r->o.kind == VSV_RENDER_SHEARWARP && !(r->sw = vsv_sw_create(VSV_POOL_MAX, r->simd && cpu_f16c())))
        return VSV_ENOMEM;
    if (!(r->o.step_cells > 0))
        r->o.step_cells = 0.5;
    if (!(r->o.term > 0 && r->o.term < 1))
        r->o.term = 1.0 / 512;
    vsv_pool_start(&r->pool, r->o.threads > 0 ? r->o.threads : vsv_ncpus());
    return 0;
}

void vsv_renderer_free(vsv_renderer *r)
{
    if (!r)
        return;
    vsv_pool_stop(&r->pool);
    free(r->skip);
    free(r->fine);
    free(r->alpha_cnt);
    free(r->act);
    for (int l = 0; l < r->copy_cap; l++) {
        free(r->copy[l].store);
        free(r->copy[l].cells);
        free(r->copy[l].mm);
    }
    free(r->copy);
    free(r->build);
    free(r->ground);
    free(r->surf);
    free(r->f32);
    vsv_sw_free(r->sw);
    vsv_native_free(&r->native);
    vsv_rc_meshes_free(r);
    free(r);
}

int vsv_rc_surf_reserve(vsv_renderer *r, size_t n)
{
    if (n <= r->surf_cap)
        return 0;
    vsv_ground *ns = realloc(r->surf, n * sizeof *ns);
    if (!ns)
        return VSV_ENOMEM;
    r->surf = ns;
    r->surf_cap = n;
    return 0;
}

int vsv_render_surfaces(vsv_renderer *r, const vsv_scene **psc, const vsv_camera *cam)
{
    const vsv_scene *sc = *psc, *in = sc;
    if (cam->width < 1 || cam->height < 1 || !sc->meta)
        return VSV_EINVAL;
    int nrc = vsv_native_scene(&r->native, sc, &sc);
    if (nrc)
        return nrc;
    *psc = sc;
    for (int l = 0; l < sc->nlayers; l++) {
        const vsv_volume *v = sc->layers[l].vol;
        if (v && (v->nx != sc->meta->nx || v->ny != sc->meta->ny || v->nz != sc->meta->nz))
            return VSV_EINVAL;
    }
    vsv_scene_geo(sc, &r->g);
    r->cam = cam;
    vsv_rays_init(&r->rays, cam);
    vsv_rays_cull(&r->rays, r->g.bmin, r->g.bmax);
    if (r->g.terrain) { /* the ground: again only when the view or the geometry changed */
        const size_t n = (size_t)cam->width * cam->height;
        if (n > r->ground_cap) {
            vsv_ground *ng = realloc(r->ground, n * sizeof *ng);
            if (!ng)
                return VSV_ENOMEM;
            r->ground = ng;
            r->ground_cap = n;
            r->ground_valid = 0;
        }
        if (!r->ground_valid || memcmp(&r->ground_cam, cam, sizeof *cam) ||
            memcmp(&r->ground_geo, &r->g, sizeof r->g)) {
            vsv_pool_run(&r->pool, vsv_rc_ground_row, r, cam->height);
            r->ground_cam = *cam;
            r->ground_geo = r->g;
            r->ground_valid = 1;
        }
    }
    r->surf_read = r->g.terrain ? r->ground : NULL;
    if (sc->nslices > 0) { /* the slices in front of the ground: every frame (their colours are the data's) */
        if (sc->slice_layer < 0 || sc->slice_layer >= sc->nlayers || !sc->layers[sc->slice_layer].vol ||
            !sc->layers[sc->slice_layer].tf || !sc->slices)
            return VSV_EINVAL;
        if (vsv_rc_surf_reserve(r, (size_t)cam->width * cam->height))
            return VSV_ENOMEM;
        r->sc = sc;
        vsv_pool_run(&r->pool, vsv_rc_slice_row, r, cam->height);
        r->surf_read = r->surf;
    }
    /* the isosurfaces and lines in front of both, from the volumes as
     * given (the file's own heights) */
    return in->nisos > 0 || in->nlines > 0 ? vsv_rc_meshes(r, in, cam) : 0;
}

/* vsv_render, into floats or (rgba8) bytes */
static int render(vsv_renderer *r, const vsv_scene *sc, const vsv_camera *cam, float *rgba, unsigned char *rgba8,
                  float *depth)
{
    int rc0 = vsv_render_surfaces(r, &sc, cam);
    if (rc0)
        return rc0;
    const int sliced = sc->nslices > 0 || sc->nisos > 0 || sc->nlines > 0; /* surfaces inside the volume: raycast */
    if (r->o.kind == VSV_RENDER_SHEARWARP && !sliced) {
        int rows = 0, bricks = 0, classify = 0;
        int rc = vsv_sw_begin(r->sw, sc, &r->g, cam, rgba, rgba8, depth, r->ground, &rows, &bricks, &classify);
        if (!rc && classify) {
            struct timespec t0, t1;
            clock_gettime(CLOCK_MONOTONIC, &t0);
            if (bricks)
                vsv_pool_run(&r->pool, vsv_sw_classify_brick, r->sw, bricks);
            vsv_pool_run(&r->pool, vsv_sw_classify_slice, r->sw, classify);
            clock_gettime(CLOCK_MONOTONIC, &t1);
            vsv_sw_classified(r->sw, (t1.tv_sec - t0.tv_sec) + (t1.tv_nsec - t0.tv_nsec) * 1e-9);
        }
        if (!rc) {
            vsv_pool_run(&r->pool, vsv_sw_composite_row, r->sw, rows);
            vsv_pool_run(&r->pool, vsv_sw_warp_rows, r->sw, vsv_sw_warp_jobs(cam->height));
            return 0;
        }
        if (rc != VSV_EUNSUPPORTED)
            return rc;
        /* an eye among the slices has no shear-warp factorisation: raycast this frame */
    }
    int rc = vsv_rc_prepare_frame(r, sc, 1);
    if (rc)
        return rc;
    if (rgba8) { /* the raycaster's floats, then bytes */
        if (vsv_sw_grow((void **)&r->f32, &r->f32_cap, 4 * (size_t)cam->width * cam->height, sizeof(float)))
            return VSV_ENOMEM;
        rgba = r->f32;
    }
    if (r->nbuild) {
        struct timespec t0, t1;
        clock_gettime(CLOCK_MONOTONIC, &t0);
        vsv_pool_run(&r->pool, vsv_rc_copy_brick, r, r->nbuild * r->build[0]->vol->nbricks);
        clock_gettime(CLOCK_MONOTONIC, &t1);
        r->copy_seconds = (t1.tv_sec - t0.tv_sec) + (t1.tv_nsec - t0.tv_nsec) * 1e-9;
    }
    if ((rc = vsv_rc_prepare_skip(r)))
        return rc;
    r->sc = sc;
    r->rgba = rgba;
    r->depth = depth;
    r->tiles_x = (cam->width + VSV_RC_TILE - 1) / VSV_RC_TILE;
    r->ntiles = r->tiles_x * ((cam->height + VSV_RC_TILE - 1) / VSV_RC_TILE);
    vsv_pool_run(&r->pool, vsv_rc_tile, r, r->ntiles);
    if (rgba8)
        vsv_sw_bytes(rgba, 4 * (size_t)cam->width * cam->height, rgba8);
    return 0;
}

int vsv_render(vsv_renderer *r, const vsv_scene *sc, const vsv_camera *cam, float *rgba, float *depth)
{
    return render(r, sc, cam, rgba, NULL, depth);
}

int vsv_render_rgba8(vsv_renderer *r, const vsv_scene *sc, const vsv_camera *cam, unsigned char *rgba, float *depth)
{
    return rgba ? render(r, sc, cam, NULL, rgba, depth) : VSV_EINVAL;
}

double vsv_renderer_rebuild_seconds(const vsv_renderer *r)
{
    return r->o.kind == VSV_RENDER_SHEARWARP ? vsv_sw_build_seconds(r->sw) : r->copy_seconds;
}

int vsv_renderer_rebuild_bricks(const vsv_renderer *r)
{
    return r->o.kind == VSV_RENDER_SHEARWARP ? vsv_sw_build_bricks(r->sw) : 0;
}
