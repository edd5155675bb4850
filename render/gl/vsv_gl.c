/* vsv_gl.c — the GPU raycaster (vsv_gl.h): the CPU renderer's set-up of
 * the frame (vsv_render_march: surfaces, layers, rays), the bricks made
 * resident (vsv_gl_bricks.c), the transfer functions and surfaces as
 * textures, one full-screen triangle through the marching shader
 * (vsv_gl_shader.c), into an offscreen framebuffer read back, or straight
 * into the caller's framebuffer. */
#include "vsv_gl_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The CPU's set-up of a frame and the surfaces it made, for one eye: two
 * of them, so that the two eyes of a stereo pair (or two views drawn in
 * turn) each keep their ground while their view stays. */
typedef struct eye_state {
    vsv_renderer *cpu; /* the CPU renderer's set-up: surfaces, the frame */
    vsv_camera cam;    /* the view it was used for last */
    uint64_t used;
    GLuint surf; /* its surfaces on the GPU */
    int sw, sh;
    uint64_t surf_key; /* what they hold */
} eye_state;

struct vsv_gl {
    vsv_gl_opts o;
    eye_state eye[2];
    uint64_t frames;
    vsv_gl_prog prog;
    GLuint vao, fbo, tex_rgba, tex_depth, lut;
    int fw, fh; /* the offscreen framebuffer's size */
    int lut_w, lut_h;
    vsv_gl_bricks bricks;
    float *buf; /* surfaces or tables, on their way to the GPU */
    size_t buf_cap;
    char device[256];
    char err[1024];
};

void vsv_gl_opts_init(vsv_gl_opts *o)
{
    memset(o, 0, sizeof *o);
    o->budget = (size_t)512 << 20;
}

int vsv_gl_create(const vsv_gl_opts *o, vsv_gl **out, char *err, size_t cap)
{
    *out = NULL;
    const int ver = epoxy_gl_version();
    const char *glsl = ver >= 20 ? (const char *)glGetString(GL_SHADING_LANGUAGE_VERSION) : NULL;
    int gmaj = 0, gmin = 0;
    if (glsl && sscanf(glsl, "%d.%d", &gmaj, &gmin) != 2) /* (not atof: a locale's comma) */
        gmaj = 0;
    if (ver < 33 || gmaj * 100 + gmin < 330) {
        snprintf(err, cap, "OpenGL %d.%d with GLSL %s; the GPU raycaster needs OpenGL 3.3", ver / 10, ver % 10,
                 glsl ? glsl : "none");
        return VSV_EUNSUPPORTED;
    }
    vsv_gl *g = calloc(1, sizeof *g);
    if (!g) {
        snprintf(err, cap, "out of memory");
        return VSV_ENOMEM;
    }
    if (o)
        g->o = *o;
    else
        vsv_gl_opts_init(&g->o);
    g->bricks.budget = g->o.budget ? g->o.budget : (size_t)512 << 20;
    const char *dev = (const char *)glGetString(GL_RENDERER);
    snprintf(g->device, sizeof g->device, "%s", dev ? dev : "?");
    vsv_render_opts ro;
    vsv_render_opts_init(&ro);
    ro.kind = VSV_RENDER_RAYCAST;
    ro.threads = g->o.threads;
    if (g->o.step_cells > 0)
        ro.step_cells = g->o.step_cells;
    if (g->o.term > 0)
        ro.term = g->o.term;
    if (vsv_renderer_create(&ro, &g->eye[0].cpu) || vsv_renderer_create(&ro, &g->eye[1].cpu)) {
        snprintf(err, cap, "out of memory");
        vsv_gl_free(g);
        return VSV_ENOMEM;
    }
    if (vsv_gl_program(&g->prog, err, cap)) {
        vsv_gl_free(g);
        return VSV_EUNSUPPORTED;
    }
    glGenVertexArrays(1, &g->vao);
    *out = g;
    return 0;
}

void vsv_gl_free(vsv_gl *g)
{
    if (!g)
        return;
    vsv_gl_bricks_free(&g->bricks);
    if (g->prog.id)
        glDeleteProgram(g->prog.id);
    if (g->vao)
        glDeleteVertexArrays(1, &g->vao);
    if (g->fbo)
        glDeleteFramebuffers(1, &g->fbo);
    GLuint tex[5] = {g->tex_rgba, g->tex_depth, g->eye[0].surf, g->eye[1].surf, g->lut};
    for (int i = 0; i < 5; i++)
        if (tex[i])
            glDeleteTextures(1, &tex[i]);
    vsv_renderer_free(g->eye[0].cpu);
    vsv_renderer_free(g->eye[1].cpu);
    free(g->buf);
    free(g);
}

int vsv_gl_context_software(void)
{
    const char *d = epoxy_gl_version() ? (const char *)glGetString(GL_RENDERER) : NULL;
    return d &&
           (strstr(d, "llvmpipe") || strstr(d, "softpipe") || strstr(d, "swrast") || strstr(d, "Software Rasterizer"));
}

const char *vsv_gl_device(const vsv_gl *g) { return g->device; }
const char *vsv_gl_error(const vsv_gl *g) { return g->err; }

void vsv_gl_stats_get(const vsv_gl *g, vsv_gl_stats *st)
{
    const vsv_gl_bricks *b = &g->bricks;
    st->uploads = b->uploads;
    st->last_uploads = b->last_uploads;
    st->last_bricks = b->last_bricks;
    st->slots = b->nslots;
    st->atlas_bytes = (size_t)b->nslots * b->e * b->e * b->e * sizeof(float);
    st->budget = b->budget;
}

static float *buffer(vsv_gl *g, size_t n)
{
    if (n > g->buf_cap) {
        float *p = realloc(g->buf, n * sizeof *p);
        if (!p)
            return NULL;
        g->buf = p;
        g->buf_cap = n;
    }
    return g->buf;
}

/* A 2-D RGBA32F texture of w x h from data (made or resized as needed). */
static void tex2d(GLuint *t, int *tw, int *th, int w, int h, const float *data)
{
    if (!*t) {
        glGenTextures(1, t);
        *tw = *th = 0;
    }
    glBindTexture(GL_TEXTURE_2D, *t);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    if (w != *tw || h != *th) {
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, w, h, 0, GL_RGBA, GL_FLOAT, data);
        *tw = w, *th = h;
    } else {
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, data);
    }
}

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

/* Everything but the drawing: the frame set up, bricks resident, tables
 * and surfaces uploaded, the program's uniforms set. 0 or a VSV_E* code
 * (g->err says why). */
static int prepare(vsv_gl *g, const vsv_scene *sc, const vsv_camera *cam, vsv_march *m)
{
    g->err[0] = 0;
    /* the eye state that drew this view last, else the older one */
    eye_state *es = !memcmp(&g->eye[0].cam, cam, sizeof *cam)   ? &g->eye[0]
                    : !memcmp(&g->eye[1].cam, cam, sizeof *cam) ? &g->eye[1]
                    : g->eye[0].used <= g->eye[1].used          ? &g->eye[0]
                                                                : &g->eye[1];
    es->cam = *cam;
    es->used = ++g->frames;
    int rc = vsv_render_march(es->cpu, sc, cam, m);
    if (rc) {
        snprintf(g->err, sizeof g->err, "%s",
                 rc == VSV_EUNSUPPORTED ? "more layers than the GPU raycaster draws" : vsv_strerror(rc));
        return rc;
    }
    if ((rc = vsv_gl_bricks_frame(&g->bricks, m, g->err, sizeof g->err)))
        return rc;
    const int nl = m->nlayers;
    /* the transfer functions' tables, a row a layer */
    float *t = buffer(g, (size_t)VSV_TF_LUT * 4 * (nl ? nl : 1));
    if (!t) {
        snprintf(g->err, sizeof g->err, "out of memory");
        return VSV_ENOMEM;
    }
    for (int l = 0; l < nl; l++)
        memcpy(t + (size_t)l * VSV_TF_LUT * 4, m->layer[l].lut, (size_t)VSV_TF_LUT * 4 * sizeof(float));
    if (!nl)
        memset(t, 0, (size_t)VSV_TF_LUT * 4 * sizeof(float));
    glActiveTexture(GL_TEXTURE2);
    tex2d(&g->lut, &g->lut_w, &g->lut_h, VSV_TF_LUT, nl ? nl : 1, t);
    glActiveTexture(GL_TEXTURE0);
    /* the surfaces: again only when they may have changed (slices and
     * isosurfaces and lines: every frame; the ground: with the view or the geometry) */
    const int w = cam->width, h = cam->height;
    uint64_t key = fnv(1469598103934665603ull, cam, sizeof *cam);
    key = fnv(key, &sc->exaggeration, sizeof sc->exaggeration);
    key = fnv(key, &sc->show_terrain, sizeof sc->show_terrain);
    key = fnv(key, &sc->meta, sizeof sc->meta);
    const int fresh = sc->nslices > 0 || sc->nisos > 0 || sc->nlines > 0 || key != es->surf_key || !es->surf;
    if (m->surface && fresh) {
        float *s = buffer(g, (size_t)w * h * 4);
        if (!s) {
            snprintf(g->err, sizeof g->err, "out of memory");
            return VSV_ENOMEM;
        }
        for (size_t i = 0; i < (size_t)w * h; i++) {
            const vsv_surface *q = &m->surface[i];
            s[4 * i] = q->rgb[0], s[4 * i + 1] = q->rgb[1], s[4 * i + 2] = q->rgb[2];
            s[4 * i + 3] = q->t < INFINITY ? q->t : -1;
        }
        glActiveTexture(GL_TEXTURE3);
        tex2d(&es->surf, &es->sw, &es->sh, w, h, s);
        glActiveTexture(GL_TEXTURE0);
        es->surf_key = sc->nslices > 0 || sc->nisos > 0 || sc->nlines > 0 ? 0 : key;
    }
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_3D, g->bricks.atlas);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_3D, g->bricks.pages);
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, g->lut);
    glActiveTexture(GL_TEXTURE3);
    glBindTexture(GL_TEXTURE_2D, es->surf);
    glActiveTexture(GL_TEXTURE0);
    /* the uniforms */
    const vsv_gl_prog *p = &g->prog;
    glUseProgram(p->id);
    glUniform1i(p->atlas, 0);
    glUniform1i(p->pages, 1);
    glUniform1i(p->lut, 2);
    glUniform1i(p->surf, 3);
    glUniform1i(p->nl, nl);
    glUniform1i(p->has_surf, m->surface != NULL);
    float par[4 * VSV_GL_MAXL], par2[4 * VSV_GL_MAXL];
    for (int l = 0; l < nl; l++) {
        const vsv_march_layer *L = &m->layer[l];
        const float ev = L->vol->empty_value;
        par[4 * l] = L->lo, par[4 * l + 1] = L->inv, par[4 * l + 2] = L->off, par[4 * l + 3] = (float)L->log;
        par2[4 * l] = L->sigma, par2[4 * l + 1] = L->inv_span, par2[4 * l + 2] = ev != ev,
                 par2[4 * l + 3] = ev == ev ? ev : 0;
    }
    if (nl) {
        glUniform4fv(p->par, nl, par);
        glUniform4fv(p->par2, nl, par2);
    }
    const float big = 3.0e38f;
    glUniform1i(p->persp, m->persp);
    glUniform1i(p->light, m->light);
    glUniform3fv(p->o, 1, m->o);
    glUniform3fv(p->f, 1, m->f);
    glUniform3fv(p->r, 1, m->r);
    glUniform3fv(p->u, 1, m->u);
    glUniform3fv(p->bmin, 1, m->bmin);
    glUniform3fv(p->bmax, 1, m->bmax);
    glUniform3fv(p->hi, 1, m->hi);
    glUniform3fv(p->ldir, 1, m->light_dir);
    glUniform3fv(p->icell, 1, m->inv_cell);
    glUniform1f(p->sx0, m->sx0);
    glUniform1f(p->sxk, m->sxk);
    glUniform1f(p->sy0, m->sy0);
    glUniform1f(p->syk, m->syk);
    glUniform1f(p->snear, m->snear);
    glUniform1f(p->sfar, m->sfar < big ? m->sfar : big);
    glUniform1f(p->st, (float)m->st);
    glUniform1f(p->inv_st, (float)(1 / (m->st > 0 ? m->st : 1)));
    glUniform1f(p->term, m->term);
    glUniform3i(p->last, m->last[0], m->last[1], m->last[2]);
    glUniform3i(p->bdim, m->bdim[0], m->bdim[1], m->bdim[2]);
    glUniform3i(p->slots, g->bricks.sx, g->bricks.sy, g->bricks.sz);
    glUniform1i(p->shift, m->shift);
    glUniform1i(p->mask, m->brick - 1);
    glUniform1i(p->e, m->brick + 1);
    glUniform1i(p->height, h);
    glUniform4i(p->rect, m->x0, m->x1, m->y0, m->y1);
    return 0;
}

/* Draws the full-screen triangle with the program as prepared, and leaves
 * the GL state as the callers' contracts say. */
static void draw(vsv_gl *g)
{
    GLint vao = 0;
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glBindVertexArray(g->vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray((GLuint)vao);
    glUseProgram(0);
    for (int u = 3; u >= 0; u--) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)u);
        glBindTexture(u < 2 ? GL_TEXTURE_3D : GL_TEXTURE_2D, 0);
    }
}

/* The errors OpenGL holds, after a frame: 0, or VSV_ENOMEM (out of
 * memory) or VSV_EUNSUPPORTED (anything else), g->err saying which. */
static int gl_errors(vsv_gl *g)
{
    GLenum e, first = GL_NO_ERROR;
    while ((e = glGetError()) != GL_NO_ERROR)
        first = first == GL_NO_ERROR ? e : first;
    if (first == GL_NO_ERROR)
        return 0;
    snprintf(g->err, sizeof g->err, "OpenGL error 0x%x%s", (unsigned)first,
             first == GL_OUT_OF_MEMORY ? " (out of memory)" : "");
    return first == GL_OUT_OF_MEMORY ? VSV_ENOMEM : VSV_EUNSUPPORTED;
}

/* The offscreen framebuffer of w x h: colour (RGBA32F) and depth (R32F). */
static int framebuffer(vsv_gl *g, int w, int h)
{
    if (g->fbo && g->fw == w && g->fh == h)
        return 0;
    if (!g->fbo) {
        glGenFramebuffers(1, &g->fbo);
        glGenTextures(1, &g->tex_rgba);
        glGenTextures(1, &g->tex_depth);
    }
    glBindTexture(GL_TEXTURE_2D, g->tex_rgba);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, w, h, 0, GL_RGBA, GL_FLOAT, NULL);
    glBindTexture(GL_TEXTURE_2D, g->tex_depth);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, w, h, 0, GL_RED, GL_FLOAT, NULL);
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, g->tex_rgba, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, g->tex_depth, 0);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        snprintf(g->err, sizeof g->err, "no float framebuffer of %d x %d", w, h);
        return VSV_EUNSUPPORTED;
    }
    g->fw = w, g->fh = h;
    return 0;
}

int vsv_gl_render(vsv_gl *g, const vsv_scene *sc, const vsv_camera *cam, float *rgba, float *depth)
{
    if (cam->width < 1 || cam->height < 1)
        return VSV_EINVAL;
    GLint old_fbo = 0, vp[4];
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &old_fbo);
    glGetIntegerv(GL_VIEWPORT, vp);
    int rc = framebuffer(g, cam->width, cam->height);
    vsv_march m;
    if (!rc)
        rc = prepare(g, sc, cam, &m);
    if (rc) {
        glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)old_fbo);
        glUseProgram(0);
        return rc;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, bufs);
    glViewport(0, 0, cam->width, cam->height);
    glUniform1i(g->prog.direct, 0);
    glUniform2i(g->prog.origin, 0, 0);
    draw(g);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    if (rgba) {
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glReadPixels(0, 0, cam->width, cam->height, GL_RGBA, GL_FLOAT, rgba);
    }
    if (depth) {
        glReadBuffer(GL_COLOR_ATTACHMENT1);
        glReadPixels(0, 0, cam->width, cam->height, GL_RED, GL_FLOAT, depth);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)old_fbo);
    glViewport(vp[0], vp[1], vp[2], vp[3]);
    return gl_errors(g);
}

int vsv_gl_draw(vsv_gl *g, const vsv_scene *sc, const vsv_camera *cam, const int viewport[4], const float bg[3])
{
    if (cam->width < 1 || cam->height < 1)
        return VSV_EINVAL;
    vsv_march m;
    const int rc = prepare(g, sc, cam, &m);
    if (rc) {
        glUseProgram(0);
        return rc;
    }
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    glUniform1i(g->prog.direct, 1);
    glUniform2i(g->prog.origin, viewport[0], viewport[1]);
    glUniform3f(g->prog.bg, bg[0], bg[1], bg[2]);
    draw(g);
    return gl_errors(g);
}
