/* vsv_gl_shader.c — the GPU raycaster's GLSL: one full-screen triangle, and
 * a fragment shader that marches each pixel's ray by the CPU raycaster's
 * rule (vsv_render.h, "marchers"; the one-ray loop of vsv_raycast.c step for
 * step), reading bricks through the page tables (vsv_gl_bricks.c). */
#include "vsv_gl_internal.h"

#include <stdio.h>
#include <string.h>

static const char VERT[] =
    "#version 330 core\n"
    "void main() {\n"
    "    vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);\n"
    "    gl_Position = vec4(p, 0.0, 1.0);\n"
    "}\n";

/* GLSL 3.30 has no fma: a * b + c, rounded twice where the CPU rounds once
 * (the pictures differ in the last bits); no infinity literal: BIG stands
 * for it (ray ends, surfaces that are not there, the far distance). */
static const char FRAG[] =
    "#version 330 core\n"
    "#define MAXL " VSV_GL_MAXL_S "\n"
    "#define LUT " VSV_GL_LUT_S "\n"
    "#define CACHE 16 /* layers whose pages a ray keeps while in a brick */\n"
    "const float BIG = 3.0e38;\n"
    "const float SMALL_U = 0.25;\n"
    "uniform sampler3D u_atlas;\n"
    "uniform isampler3D u_pages;\n"
    "uniform sampler2D u_lut;\n"
    "uniform sampler2D u_surf;\n"
    "uniform int u_nl, u_has_surf, u_persp, u_light, u_direct;\n"
    "uniform vec4 u_par[MAXL];   /* lo, inv, off, log */\n"
    "uniform vec4 u_par2[MAXL];  /* sigma, inv_span, empty is NaN, empty value */\n"
    "uniform vec3 u_o, u_f, u_r, u_u, u_bmin, u_bmax, u_hi, u_ldir, u_icell, u_bg;\n"
    "uniform float u_sx0, u_sxk, u_sy0, u_syk, u_snear, u_sfar, u_st, u_inv_st, u_term;\n"
    "uniform ivec3 u_last, u_bdim, u_slots;\n"
    "uniform int u_shift, u_mask, u_e, u_height;\n"

    "uniform ivec4 u_rect;   /* x0, x1, y0, y1: the pixels that may meet the box */\n"
    "uniform ivec2 u_origin; /* the viewport's corner (drawing into a window) */\n"
    "layout(location = 0) out vec4 o_rgba;\n"
    "layout(location = 1) out float o_depth;\n"
    "\n"
    "float lerp1(float a, float b, float f) { return (b - a) * f + a; }\n"
    "ivec2 page(int l, ivec3 bk) { return texelFetch(u_pages, ivec3(bk.x, bk.y, bk.z + l * u_bdim.z), 0).xy; }\n"
    "float empty_value(int l) { return u_par2[l].z != 0.0 ? uintBitsToFloat(0x7fc00000u) : u_par2[l].w; }\n"
    "/* layer l's trilinear value at lower cell ci with fractions f, its\n"
    " * brick's page pg: the eight cells (in one slot), lerped as\n"
    " * vsv_rc_trilinear does (the texture unit's filtering has too few\n"
    " * bits in its weights on GPUs to draw the CPU's picture) */\n"
    "float value_pg(int l, ivec2 pg, ivec3 ci, vec3 f) {\n"
    "    if (pg.x < 0) return empty_value(l);\n"
    "    ivec3 q = ivec3(pg.x % u_slots.x, (pg.x / u_slots.x) % u_slots.y, pg.x / (u_slots.x * u_slots.y)) * u_e\n"
    "              + (ci & u_mask);\n"
    "    float c000 = texelFetch(u_atlas, q, 0).r, c100 = texelFetch(u_atlas, q + ivec3(1, 0, 0), 0).r;\n"
    "    float c010 = texelFetch(u_atlas, q + ivec3(0, 1, 0), 0).r, c110 = texelFetch(u_atlas, q + ivec3(1, 1, 0), "
    "0).r;\n"
    "    float c001 = texelFetch(u_atlas, q + ivec3(0, 0, 1), 0).r, c101 = texelFetch(u_atlas, q + ivec3(1, 0, 1), "
    "0).r;\n"
    "    float c011 = texelFetch(u_atlas, q + ivec3(0, 1, 1), 0).r, c111 = texelFetch(u_atlas, q + ivec3(1, 1, 1), "
    "0).r;\n"
    "    float a0 = lerp1(c000, c100, f.x), a1 = lerp1(c010, c110, f.x);\n"
    "    float a2 = lerp1(c001, c101, f.x), a3 = lerp1(c011, c111, f.x);\n"
    "    return lerp1(lerp1(a0, a1, f.y), lerp1(a2, a3, f.y), f.z);\n"
    "}\n"
    "float value(int l, ivec3 ci, vec3 f) { return value_pg(l, page(l, ci >> u_shift), ci, f); }\n"
    "/* at cell coordinates p, clamped into the grid (rc_value) */\n"
    "float value_at(int l, vec3 p) {\n"
    "    vec3 c = clamp(p, vec3(0.0), u_hi);\n"
    "    ivec3 ci = min(ivec3(c), u_last);\n"
    "    return value(l, ci, c - vec3(ci));\n"
    "}\n"
    "/* the lighting factor (vsv_light_shade) of layer l's value v at c */\n"
    "float shade(int l, vec3 c, float v) {\n"
    "    vec3 d;\n"
    "    for (int a = 0; a < 3; a++) {\n"
    "        vec3 p = c; p[a] = c[a] + 1.0;\n"
    "        float hi = value_at(l, p);\n"
    "        p[a] = c[a] - 1.0;\n"
    "        float lo = value_at(l, p);\n"
    "        hi = isnan(hi) ? v : hi;\n"
    "        lo = isnan(lo) ? v : lo;\n"
    "        d[a] = 0.5 * (hi - lo);\n"
    "    }\n"
    "    float k = u_par2[l].y;\n"
    "    if (u_par[l].w != 0.0) k = v > 0.0 ? u_par2[l].y / v : 0.0;\n"
    "    vec3 g = d * k;\n"
    "    float m2 = dot(g, g);\n"
    "    if (!(m2 > 0.0) || isinf(m2) || isnan(m2)) return 1.0;\n"
    "    vec3 gw = g * u_icell;\n"
    "    float n2 = dot(gw, gw), gl = dot(gw, u_ldir);\n"
    "    float ndotl = n2 > 0.0 ? -gl / sqrt(n2) : 0.0;\n"
    "    float w = min(1.0, sqrt(m2) * (1.0 / " VSV_GL_GFULL_S "));\n"
    "    float lam = " VSV_GL_AMBIENT_S " + " VSV_GL_DIFFUSE_S " * max(ndotl, 0.0);\n"
    "    return 1.0 + w * (lam - 1.0);\n"
    "}\n"
    "float opacity_per_u(float u) {\n"
    "    if (u < SMALL_U)\n"
    "        return 1.0 + u * (-1.0 / 2.0 + u * (1.0 / 6.0 + u * (-1.0 / 24.0 + u * (1.0 / 120.0 + u * (-1.0 / "
    "720.0)))));\n"
    "    return (1.0 - exp(-u)) / u;\n"
    "}\n"
    "void main() {\n"
    "    ivec2 fc = ivec2(gl_FragCoord.xy) - u_origin;\n"
    "    int px = fc.x, py = u_direct != 0 ? u_height - 1 - fc.y : fc.y; /* image row 0 at the top */\n"
    "    float t_hit = BIG;\n"
    "    vec3 srgb = vec3(0.0);\n"
    "    if (u_has_surf != 0) {\n"
    "        vec4 s = texelFetch(u_surf, ivec2(px, py), 0);\n"
    "        if (s.a >= 0.0) { t_hit = s.a; srgb = s.rgb; }\n"
    "    }\n"
    "    float T = 1.0, depth = BIG;\n"
    "    vec3 acc = vec3(0.0);\n"
    "    if (u_nl > 0 && px >= u_rect.x && px <= u_rect.y && py >= u_rect.z && py <= u_rect.w) {\n"
    "        /* the ray (vsv_rc_ray_setup) */\n"
    "        float sx = float(px) * u_sxk + u_sx0, sy = float(py) * u_syk + u_sy0;\n"
    "        vec3 o, dp;\n"
    "        if (u_persp != 0) {\n"
    "            float k = 1.0 / sqrt(sx * sx + (sy * sy + 1.0));\n"
    "            o = u_o;\n"
    "            dp = (sx * u_r + (sy * u_u + u_f)) * k;\n"
    "        } else {\n"
    "            o = sx * u_r + (sy * u_u + u_o);\n"
    "            dp = u_f;\n"
    "        }\n"
    "        float lo = -BIG, hi = BIG;\n"
    "        bool outside = false;\n"
    "        vec3 inv = vec3(BIG);\n"
    "        for (int a = 0; a < 3; a++) {\n"
    "            if (dp[a] == 0.0) {\n"
    "                outside = outside || o[a] < u_bmin[a] || o[a] > u_bmax[a];\n"
    "                continue;\n"
    "            }\n"
    "            inv[a] = 1.0 / dp[a];\n"
    "            float s0 = (u_bmin[a] - o[a]) * inv[a], s1 = (u_bmax[a] - o[a]) * inv[a];\n"
    "            lo = max(lo, min(s0, s1));\n"
    "            hi = min(hi, max(s0, s1));\n"
    "        }\n"
    "        bool hit = !outside && hi >= lo && hi > 0.0;\n"
    "        lo = max(lo, u_snear);\n"
    "        hi = min(hi, u_sfar);\n"
    "        float s_hit = t_hit < BIG ? t_hit * u_inv_st : BIG;\n"
    "        float ts = lo + 0.5, seg = min(hi, s_hit) - lo;\n"
    "        int ns = hit && seg > 0.0 ? int(ceil(min(seg, 1.0e8))) : 0;\n"
    "        float wl = min(seg - float(ns - 1), 1.0);\n"
    "        float nl = 0.5 * wl + float(ns - 1) - 0.5;\n"
    "        vec3 p = ts * dp + o;\n"
    "        ivec3 cbk = ivec3(-1);\n"
    "        bool shown = false;\n"
    "        ivec2 cpg[CACHE];\n"
    "        for (int n = 0; n < ns; n++) {\n"
    "            float nf = n == ns - 1 ? nl : float(n);\n"
    "            vec3 c = clamp(nf * dp + p, vec3(0.0), u_hi);\n"
    "            ivec3 ci = min(ivec3(c), u_last);\n"
    "            ivec3 bk = ci >> u_shift;\n"
    "            if (bk != cbk) { /* a new brick: its pages, once */\n"
    "                cbk = bk;\n"
    "                shown = false;\n"
    "                for (int l = 0; l < u_nl; l++) {\n"
    "                    ivec2 pg = page(l, bk);\n"
    "                    if (l < CACHE) cpg[l] = pg;\n"
    "                    shown = shown || pg.y == 0;\n"
    "                }\n"
    "            }\n"
    "            if (!shown) { /* every layer clear in this brick: leap out of it (vsv_rc_leap, d 1) */\n"
    "                float k = float(ns);\n"
    "                ivec3 blo, bhi;\n"
    "                for (int a = 0; a < 3; a++) {\n"
    "                    int b = ci[a] >> u_shift, up = (b + 1) << u_shift, down = b << u_shift;\n"
    "                    bool never = dp[a] > 0.0 ? up > u_last[a] : dp[a] < 0.0 ? down <= 0 : true;\n"
    "                    if (!never) {\n"
    "                        float ka = (float(dp[a] > 0.0 ? up : down) - p[a]) * inv[a];\n"
    "                        k = ka < k ? ka : k;\n"
    "                    }\n"
    "                    blo[a] = down;\n"
    "                    bhi[a] = up;\n"
    "                }\n"
    "                int kn = k > float(n) ? int(k) : n;\n"
    "                float kf = kn == ns - 1 ? nl : float(kn);\n"
    "                ivec3 ck = min(ivec3(clamp(kf * dp + p, vec3(0.0), u_hi)), u_last);\n"
    "                if (all(greaterThanEqual(ck, blo)) && all(lessThan(ck, bhi))) kn++;\n"
    "                n = max(kn, n + 1) - 1;\n"
    "                continue;\n"
    "            }\n"
    "            vec3 f = c - vec3(ci);\n"
    "            float sig = 0.0;\n"
    "            vec3 col = vec3(0.0);\n"
    "            for (int l = 0; l < u_nl; l++) {\n"
    "                ivec2 pg = l < CACHE ? cpg[l] : page(l, bk);\n"
    "                if (pg.y != 0) continue; /* transparent in this brick: adds nothing */\n"
    "                float v = value_pg(l, pg, ci, f);\n"
    "                if (isnan(v) || !(v >= u_par[l].x)) continue;\n"
    "                float x = (u_par[l].w != 0.0 ? log(v) : v) * u_par[l].y + u_par[l].z;\n"
    "                x = min(x, float(LUT - 1));\n"
    "                int i = min(int(x), LUT - 2);\n"
    "                float ff = x - float(i);\n"
    "                vec4 a0 = texelFetch(u_lut, ivec2(i, l), 0), a1 = texelFetch(u_lut, ivec2(i + 1, l), 0);\n"
    "                float s = lerp1(a0.a, a1.a, ff) * u_par2[l].x;\n"
    "                if (s > 0.0) {\n"
    "                    sig += s;\n"
    "                    float k = u_light != 0 ? s * shade(l, c, v) : s;\n"
    "                    col += k * ((a1.rgb - a0.rgb) * ff + a0.rgb);\n"
    "                }\n"
    "            }\n"
    "            if (sig > 0.0) {\n"
    "                float stn = n == ns - 1 ? u_st * wl : u_st;\n"
    "                float us = sig * stn, fo = opacity_per_u(us);\n"
    "                float a = us * fo, kk = T * fo * stn;\n"
    "                acc += kk * col;\n"
    "                T = T - T * a;\n"
    "                if (depth == BIG && 1.0 - T > 0.1) depth = u_st * (ts + float(n));\n"
    "                if (T < u_term) break;\n"
    "            }\n"
    "        }\n"
    "    }\n"
    "    vec4 rgba = vec4(acc, 1.0 - T);\n"
    "    if (t_hit < BIG && T >= u_term) {\n"
    "        rgba.rgb += T * srgb;\n"
    "        rgba.a = 1.0;\n"
    "        if (depth == BIG) depth = t_hit;\n"
    "    }\n"
    "    if (u_direct != 0) { /* over the background, with vsv_image_rgb8's gamma */\n"
    "        vec3 v = clamp(rgba.rgb + (1.0 - rgba.a) * u_bg, 0.0, 1.0);\n"
    "        o_rgba = vec4(pow(v, vec3(1.0 / 2.2)), 1.0);\n"
    "    } else {\n"
    "        o_rgba = rgba;\n"
    "    }\n"
    "    o_depth = depth == BIG ? uintBitsToFloat(0x7f800000u) : depth;\n"
    "}\n";

static GLuint compile(GLenum kind, const char *src, char *err, size_t cap)
{
    GLuint s = glCreateShader(kind);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048] = "";
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        snprintf(err, cap, "the %s shader does not compile: %s", kind == GL_VERTEX_SHADER ? "vertex" : "fragment", log);
        glDeleteShader(s);
        return 0;
    }
    return s;
}

int vsv_gl_program(vsv_gl_prog *p, char *err, size_t cap)
{
    memset(p, 0, sizeof *p);
    const GLuint vs = compile(GL_VERTEX_SHADER, VERT, err, cap);
    const GLuint fs = vs ? compile(GL_FRAGMENT_SHADER, FRAG, err, cap) : 0;
    if (!fs) {
        if (vs)
            glDeleteShader(vs);
        return -1;
    }
    p->id = glCreateProgram();
    glAttachShader(p->id, vs);
    glAttachShader(p->id, fs);
    glLinkProgram(p->id);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(p->id, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[2048] = "";
        glGetProgramInfoLog(p->id, sizeof log, NULL, log);
        snprintf(err, cap, "the shaders do not link: %s", log);
        glDeleteProgram(p->id);
        p->id = 0;
        return -1;
    }
#define LOC(name) p->name = glGetUniformLocation(p->id, "u_" #name)
    LOC(atlas), LOC(pages), LOC(lut), LOC(surf), LOC(nl), LOC(has_surf), LOC(persp), LOC(light), LOC(direct);
    LOC(par), LOC(par2), LOC(o), LOC(f), LOC(r), LOC(u), LOC(bmin), LOC(bmax), LOC(hi), LOC(ldir), LOC(icell);
    LOC(bg), LOC(sx0), LOC(sxk), LOC(sy0), LOC(syk), LOC(snear), LOC(sfar), LOC(st), LOC(inv_st), LOC(term);
    LOC(last), LOC(bdim), LOC(slots), LOC(shift), LOC(mask), LOC(e), LOC(height), LOC(rect), LOC(origin);

#undef LOC
    return 0;
}
