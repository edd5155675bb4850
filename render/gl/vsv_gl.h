/* vsv_gl.h — the GPU raycaster (libvesuvius-gl): the CPU raycaster's
 * picture (vsv_render.h, "marchers": the same rays, samples, classification,
 * compositing, surfaces and lighting) marched by a GLSL fragment shader in
 * an OpenGL 3.3 context, over the pager's bricks on the GPU.
 *
 * Bricks: each visible species' bricks live in one brick atlas, a 3-D float
 * texture of slots (brick + 1)^3 cells each (the raycaster's sampling copy:
 * a trilinear sample never straddles slots), found through a page table per
 * species (a 3-D texture of slot numbers, -1 for a brick whose copy holds
 * only the empty value). A slot is keyed by the values it holds (the brick's
 * key and those of the bricks after it, vsv_volume.bkey; the volume's load
 * where it has no keys), so on a new time step only the bricks whose values
 * changed are uploaded, in batches through a pixel buffer object (32 MB);
 * free slots, then the least recently used, take them, and the atlas never
 * grows past the budget. A brick
 * every species leaves transparent (from its values' range and the
 * transfer functions) is leapt over whole, as the CPU leaps its blocks:
 * the same samples are taken either way.
 *
 * The surfaces each ray ends on (the ground, slices) come from the CPU
 * renderer's own set-up (vsv_render_march), uploaded as a texture: exactly
 * the CPU's ground. Native levels are resampled on the CPU as for the CPU
 * renderers.
 *
 * Every call needs the context the raycaster was made in to be current on
 * the calling thread (one vsv_gl per context; not shared between threads). */
#ifndef VSV_GL_H
#define VSV_GL_H

#include "vsv_render.h"

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vsv_gl vsv_gl;

typedef struct vsv_gl_opts {
    size_t budget;     /* bytes of GPU memory for bricks; 0 = 512 MiB */
    int threads;       /* CPU threads for the surfaces; 0 = all cores */
    double step_cells; /* as vsv_render_opts (0: its default) */
    double term;       /* as vsv_render_opts (0: its default) */
} vsv_gl_opts;

void vsv_gl_opts_init(vsv_gl_opts *o);

/* Makes the raycaster in the current context: 0; VSV_EUNSUPPORTED when the
 * context is not OpenGL 3.3 or later (or a shader does not compile: err
 * says which and why); VSV_ENOMEM. err: caller buffer of cap bytes. Caller
 * frees with vsv_gl_free, with the context current. */
int vsv_gl_create(const vsv_gl_opts *o, vsv_gl **out, char *err, size_t cap);
void vsv_gl_free(vsv_gl *g);
/* 1 when the current context draws with a software rasteriser (Mesa's
 * llvmpipe, softpipe, swrast: a CPU); 0 otherwise or with no context. */
int vsv_gl_context_software(void);
/* The context's renderer (GL_RENDERER), e.g. "llvmpipe (LLVM 15.0.6, 256
 * bits)" or a GPU's name; borrowed. */
const char *vsv_gl_device(const vsv_gl *g);

/* vsv_render's contract (rgba premultiplied, row 0 at the top; depth along
 * the ray, INFINITY where none; either may be NULL): renders into an
 * offscreen framebuffer and reads it back (the framebuffer binding and the
 * viewport are put back; the pack alignment is left at 4). 0 or a VSV_E* code;
 * VSV_ENOMEM also when the bricks of one frame do not fit the budget
 * (vsv_gl_error says so). */
int vsv_gl_render(vsv_gl *g, const vsv_scene *sc, const vsv_camera *cam, float *rgba, float *depth);
/* Renders straight into the framebuffer bound now, in the viewport given
 * (x, y, w, h; cam is w x h): each pixel the frame's colour over bg
 * (linear), with the gamma of vsv_image_rgb8, opaque; nothing read back.
 * For displays that draw each eye themselves (FreeVR). Leaves: the
 * viewport as given, the depth test and blending off, the program 0, the
 * vertex array as it was, texture units 0-3 with nothing bound and unit 0
 * active, the unpack alignment 4. Both calls keep the surfaces of the two
 * views drawn last (a stereo pair's eyes), so each is worked out again on
 * the CPU only when its view changes. */
int vsv_gl_draw(vsv_gl *g, const vsv_scene *sc, const vsv_camera *cam, const int viewport[4], const float bg[3]);
/* The last failure's message (borrowed). */
const char *vsv_gl_error(const vsv_gl *g);

typedef struct vsv_gl_stats {
    uint64_t uploads;      /* bricks uploaded since the raycaster was made */
    uint64_t last_uploads; /* by the last frame */
    uint64_t last_bricks;  /* non-empty bricks the last frame drew (resident) */
    int slots;             /* slots in the atlas now */
    size_t atlas_bytes;    /* the atlas's size on the GPU */
    size_t budget;         /* the budget in force */
} vsv_gl_stats;
void vsv_gl_stats_get(const vsv_gl *g, vsv_gl_stats *st);

/* A headless context (EGL: Mesa's surfaceless platform, else the first
 * device), OpenGL 3.3 core or later, made current on the calling thread.
 * 0, or VSV_EUNSUPPORTED with the reason in err. Caller frees with
 * vsv_gl_context_free. */
typedef struct vsv_gl_context vsv_gl_context;
int vsv_gl_context_create(vsv_gl_context **out, char *err, size_t cap);
void vsv_gl_context_free(vsv_gl_context *c);

#ifdef __cplusplus
}
#endif

#endif
