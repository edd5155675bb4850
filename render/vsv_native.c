/* vsv_native.c — native model levels drawn where the model has them: a
 * scene whose file carries per-column heights (SPEC.md "HGTS") is rendered
 * through its volumes resampled onto an even height axis, redone only when a
 * layer's volume changes (a new time step), so both renderers march the
 * same even grid as for a file converted with even heights. */
#include "vsv_geo.h"

#include <stdlib.h>

int vsv_native_scene(vsv_native *n, const vsv_scene *in, const vsv_scene **out)
{
    *out = in;
    const vsv_meta *m = in->meta;
    if (m->vert_kind != VSV_VERT_NATIVE || !m->nheights)
        return 0;
    if (n->m != m || n->cap < in->nlayers) {
        vsv_native_free(n);
        n->rs = calloc((size_t)in->nlayers + 1, sizeof *n->rs);
        n->layers = calloc((size_t)in->nlayers + 1, sizeof *n->layers);
        if (!n->rs || !n->layers)
            return VSV_ENOMEM;
        n->cap = in->nlayers;
        n->m = m;
    }
    const vsv_meta *even = NULL;
    for (int l = 0; l < in->nlayers; l++) {
        n->layers[l] = in->layers[l];
        /* the layers drawn and the one colouring the slices; the others
         * (native levels, not the even grid) are left out */
        if (!in->layers[l].vol || !(in->layers[l].visible || (in->nslices && l == in->slice_layer))) {
            n->layers[l].vol = NULL;
            continue;
        }
        int rc;
        if (!n->rs[l] && (rc = vsv_resampler_create(m, &n->rs[l])))
            return rc;
        if ((rc = vsv_resampler_run(n->rs[l], in->layers[l].vol, &n->layers[l].vol)))
            return rc;
        even = vsv_resampler_meta(n->rs[l]);
    }
    if (!even) { /* nothing visible: any resampler's grid will do */
        if (!n->rs[0] && vsv_resampler_create(m, &n->rs[0]))
            return VSV_ENOMEM;
        even = vsv_resampler_meta(n->rs[0]);
    }
    n->sc = *in;
    n->sc.meta = even;
    n->sc.layers = n->layers;
    *out = &n->sc;
    return 0;
}

void vsv_native_free(vsv_native *n)
{
    if (n->rs) /* cap + 1: the spare one a scene with nothing visible takes */
        for (int l = 0; l <= n->cap; l++)
            vsv_resampler_free(n->rs[l]);
    free(n->rs);
    free(n->layers);
    n->rs = NULL;
    n->layers = NULL;
    n->cap = 0;
    n->m = NULL;
}
