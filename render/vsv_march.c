/* vsv_march.c — the raycaster's frame for marchers outside this library
 * (vsv_render.h, "marchers"): the same set-up vsv_render does before the
 * raycaster's tiles, handed over as plain info. */
#include "vsv_renderer.h"

#include <string.h>

int vsv_render_march(vsv_renderer *r, const vsv_scene *sc, const vsv_camera *cam, vsv_march *m)
{
    memset(m, 0, sizeof *m);
    int rc = vsv_render_surfaces(r, &sc, cam);
    if (rc || (rc = vsv_rc_prepare_frame(r, sc, 0)))
        return rc;
    const vsv_rc_frame *F = &r->frame;
    m->width = cam->width, m->height = cam->height;
    m->x0 = r->rays.x0, m->x1 = r->rays.x1, m->y0 = r->rays.y0, m->y1 = r->rays.y1;
    m->surface = r->surf_read;
    if (F->nlayers > VSV_MARCH_MAX)
        return VSV_EUNSUPPORTED;
    m->nlayers = F->nlayers;
    for (int l = 0, k = 0; l < sc->nlayers && k < F->nlayers; l++) /* the visible layers, in order */
        if (sc->layers[l].vol == F->layer[k].vol && sc->layers[l].visible && sc->layers[l].opacity > 0) {
            const vsv_rc_layer *L = &F->layer[k];
            m->layer[k] = (vsv_march_layer){L->vol, l, L->lut, L->lo, L->inv, L->off, L->log, L->sigma, L->inv_span};
            k++;
        }
    if (!F->nlayers)
        return 0;
    const vsv_volume *V = F->layer[0].vol;
    m->n[0] = V->nx, m->n[1] = V->ny, m->n[2] = V->nz;
    for (int a = 0; a < 3; a++) {
        m->hi[a] = F->hi[a];
        m->last[a] = F->last[a];
        m->bdim[a] = V->bdim[a];
        m->o[a] = F->cam.o[a], m->f[a] = F->cam.f[a], m->r[a] = F->cam.r[a], m->u[a] = F->cam.u[a];
        m->bmin[a] = F->cam.bmin[a], m->bmax[a] = F->cam.bmax[a];
        m->light_dir[a] = F->light.dir[a];
        m->inv_cell[a] = F->light.inv_cell[a];
    }
    m->brick = F->brick, m->shift = F->shift;
    m->st = F->st;
    m->term = F->term;
    m->sx0 = F->cam.sx0, m->sxk = F->cam.sxk, m->sy0 = F->cam.sy0, m->syk = F->cam.syk;
    m->snear = F->cam.snear, m->sfar = F->cam.sfar;
    m->persp = F->cam.persp;
    m->light = F->light.on;
    return 0;
}

void vsv_march_brick(const vsv_volume *v, int b, float *dst) { vsv_rc_copy_fill(v, b, dst); }

int vsv_march_brick_empty(const vsv_volume *v, int b) { return !vsv_rc_copy_has_data(v, b); }

static vsv_rc_layer as_rc(const vsv_march_layer *L)
{
    vsv_rc_layer l;
    memset(&l, 0, sizeof l);
    l.lut = L->lut, l.lo = L->lo, l.inv = L->inv, l.off = L->off, l.log = L->log;
    return l;
}

void vsv_march_counts(const vsv_march_layer *L, int cnt[VSV_TF_LUT + 1])
{
    const vsv_rc_layer l = as_rc(L);
    vsv_rc_alpha_counts(&l, cnt);
}

int vsv_march_clear(const vsv_march_layer *L, const int *cnt, float lo, float hi)
{
    const vsv_rc_layer l = as_rc(L);
    return vsv_rc_layer_clear(&l, cnt, lo, hi);
}
