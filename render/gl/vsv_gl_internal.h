/* vsv_gl_internal.h — what the GPU raycaster's files share: the program
 * and its uniforms (vsv_gl_shader.c), the brick atlas and page tables
 * (vsv_gl_bricks.c) and the renderer (vsv_gl.c). Private to render/gl/. */
#ifndef VSV_GL_INTERNAL_H
#define VSV_GL_INTERNAL_H

#include "vsv_gl.h"

#include <epoxy/gl.h>

#define VSV_GL_MAXL VSV_MARCH_MAX
#define VSV_GL_STAGING ((size_t)32 << 20) /* the uploads' staging buffer, bytes */
#define VSV_GL_STR2(x) #x
#define VSV_GL_STR(x) VSV_GL_STR2(x)
#define VSV_GL_MAXL_S VSV_GL_STR(VSV_MARCH_MAX)
#define VSV_GL_LUT_S VSV_GL_STR(VSV_TF_LUT)
#define VSV_GL_AMBIENT_S VSV_GL_STR(VSV_LIGHT_AMBIENT)
#define VSV_GL_DIFFUSE_S VSV_GL_STR(VSV_LIGHT_DIFFUSE)
#define VSV_GL_GFULL_S VSV_GL_STR(VSV_LIGHT_GFULL)

/* The program and its uniforms' locations. */
typedef struct vsv_gl_prog {
    GLuint id;
    GLint atlas, pages, lut, surf, nl, has_surf, persp, light, direct, par, par2, o, f, r, u, bmin, bmax, hi, ldir,
        icell, bg, sx0, sxk, sy0, syk, snear, sfar, st, inv_st, term, last, bdim, slots, shift, mask, e, height, rect,
        origin;
} vsv_gl_prog;
/* Compiles and links it (in the current context): 0, or -1 with the
 * compiler's words in err. */
int vsv_gl_program(vsv_gl_prog *p, char *err, size_t cap);

/* The bricks on the GPU: the atlas of slots, each holding one brick's
 * sampling copy ((brick + 1)^3 floats), keyed by the values it holds; the
 * page tables of the frame's layers (one 3-D texture, the layers stacked
 * along z: x slot or -1, y 1 where the brick is clear in that layer). */
typedef struct vsv_gl_slot {
    uint64_t key;  /* 0: free */
    uint64_t used; /* the frame that used it last */
    float lo, hi;  /* its values' range (NaN left out; lo > hi: none) */
} vsv_gl_slot;

typedef struct vsv_gl_bricks {
    GLuint atlas, pages, pbo;
    int e, brick;           /* slot edge (brick + 1) and the brick edge */
    int sx, sy, sz, nslots; /* slots per axis, in all */
    vsv_gl_slot *slot;
    uint32_t *hash; /* open addressing: slot + 1, 0 empty */
    int nhash;      /* a power of two, at least twice nslots */
    size_t budget;
    uint64_t frame; /* frames drawn (slot.used) */
    int *page;      /* the frame's page table (2 ints a brick and layer) */
    size_t page_cap;
    int pw, ph, pd; /* the page texture's size */
    float *copy;    /* one brick's copy, filled on the CPU */
    size_t copy_cap;
    int hand; /* where the search for a slot goes on */
    int *cnt; /* the layers' opacity counts (vsv_march_counts) */
    uint64_t uploads, last_uploads, last_bricks;
} vsv_gl_bricks;

void vsv_gl_bricks_free(vsv_gl_bricks *b);
/* Makes the frame's bricks resident (uploading those not in the atlas) and
 * its page tables, for march m's layers. 0; VSV_ENOMEM with the reason in
 * err when they do not fit the budget (or memory runs out). */
int vsv_gl_bricks_frame(vsv_gl_bricks *b, const vsv_march *m, char *err, size_t cap);

#endif
