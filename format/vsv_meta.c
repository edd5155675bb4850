/* vsv_meta.c — the metadata of a file (vsv_meta): its ownership (init,
 * copy, clear), variables, attributes, levels, terrain and validation. */
#include "vsv_format_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void vsv_meta_init(vsv_meta *m)
{
    memset(m, 0, sizeof *m);
    m->spacing[0] = m->spacing[1] = m->spacing[2] = 1;
    m->proj.kind = VSV_PROJ_NONE;
}

void vsv_meta_clear(vsv_meta *m)
{
    if (!m)
        return;
    free(m->levels);
    free(m->attr_keys);
    free(m->attr_values);
    if (m->tf)
        for (int i = 0; i < m->nvars; i++)
            free(m->tf[i]);
    free(m->tf);
    free(m->vars);
    free(m->terrain);
    free(m->landuse);
    vsv_heights_clear_all(m);
    vsv_moves_clear_all(m);
    vsv_meta_init(m);
}

static int dup_array(void **dst, const void *src, size_t bytes)
{
    *dst = NULL;
    if (!src)
        return 0;
    *dst = malloc(bytes ? bytes : 1);
    if (!*dst)
        return VSV_ENOMEM;
    memcpy(*dst, src, bytes);
    return 0;
}

int vsv_meta_copy(vsv_meta *dst, const vsv_meta *src)
{
    vsv_meta_clear(dst);
    *dst = *src;
    dst->levels = NULL;
    dst->attr_keys = NULL;
    dst->attr_values = NULL;
    dst->vars = NULL;
    dst->tf = NULL;
    dst->terrain = dst->landuse = NULL;
    dst->heights = NULL;
    dst->nheights = 0;
    dst->moves = NULL;
    dst->nmoves = 0;
    size_t plane = (size_t)src->nx * (size_t)src->ny * sizeof(float);
    if (dup_array((void **)&dst->levels, src->levels, (size_t)src->nz * sizeof(double)) ||
        dup_array((void **)&dst->attr_keys, src->attr_keys, (size_t)src->nattrs * 64) ||
        dup_array((void **)&dst->attr_values, src->attr_values, (size_t)src->nattrs * 256) ||
        dup_array((void **)&dst->vars, src->vars, (size_t)src->nvars * sizeof(vsv_var)) ||
        dup_array((void **)&dst->terrain, src->terrain, plane) ||
        dup_array((void **)&dst->landuse, src->landuse, plane) || vsv_heights_copy_all(dst, src) ||
        vsv_moves_copy_all(dst, src))
        goto fail;
    if (src->tf) {
        dst->tf = calloc((size_t)src->nvars + 1, sizeof(char *));
        if (!dst->tf)
            goto fail;
        for (int i = 0; i < src->nvars; i++)
            if (src->tf[i] && !(dst->tf[i] = strdup(src->tf[i])))
                goto fail;
    }
    return 0;
fail:
    vsv_meta_clear(dst);
    return VSV_ENOMEM;
}

static void copy_str(char *dst, size_t cap, const char *src) { snprintf(dst, cap, "%s", src ? src : ""); }

int vsv_meta_add_var(vsv_meta *m, const char *name, const char *units, const char *desc)
{
    if (m->nvars >= VSV_MAX_VARS || strlen(name) >= sizeof m->vars->name)
        return VSV_EINVAL; /* (a name is never cut: two could become one) */
    vsv_var *v = realloc(m->vars, ((size_t)m->nvars + 1) * sizeof *v);
    if (!v)
        return VSV_ENOMEM;
    m->vars = v;
    if (m->tf) {
        char **tf = realloc(m->tf, ((size_t)m->nvars + 2) * sizeof *tf);
        if (!tf)
            return VSV_ENOMEM;
        m->tf = tf;
        m->tf[m->nvars] = NULL;
    }
    vsv_var *nv = &m->vars[m->nvars];
    memset(nv, 0, sizeof *nv);
    copy_str(nv->name, sizeof nv->name, name);
    copy_str(nv->units, sizeof nv->units, units);
    copy_str(nv->description, sizeof nv->description, desc);
    return m->nvars++;
}

int vsv_meta_add_attr(vsv_meta *m, const char *key, const char *value)
{
    char(*k)[64] = realloc(m->attr_keys, ((size_t)m->nattrs + 1) * 64);
    if (!k)
        return VSV_ENOMEM;
    m->attr_keys = k;
    char(*v)[256] = realloc(m->attr_values, ((size_t)m->nattrs + 1) * 256);
    if (!v)
        return VSV_ENOMEM;
    m->attr_values = v;
    memset(k[m->nattrs], 0, 64);
    memset(v[m->nattrs], 0, 256);
    copy_str(k[m->nattrs], 64, key);
    copy_str(v[m->nattrs], 256, value);
    m->nattrs++;
    return 0;
}

const char *vsv_meta_attr(const vsv_meta *m, const char *key)
{
    for (int i = 0; i < m->nattrs; i++)
        if (!strcmp(m->attr_keys[i], key))
            return m->attr_values[i];
    return NULL;
}

int vsv_meta_above_ground(const vsv_meta *m)
{
    const char *d = vsv_meta_attr(m, VSV_ATTR_DATUM);
    return d && !strcmp(d, "ground");
}

int vsv_meta_periodic_x(const vsv_meta *m)
{
    return m->proj.kind == VSV_PROJ_LATLON && m->nx > 1 && fabs(m->nx * m->spacing[0] - 360) <= 360e-6;
}

int vsv_meta_outputs(const vsv_meta *m, int64_t *first, int64_t *every)
{
    const char *v = vsv_meta_attr(m, VSV_ATTR_OUTPUTS);
    long long e;
    char iso[40];
    if (!v || sscanf(v, "every %lld s from %39s", &e, iso) != 2 || e <= 0 ||
        vsv_cal_parse(vsv_meta_calendar(m), iso, first))
        return 0;
    *every = e;
    return 1;
}

int vsv_meta_alloc_levels(vsv_meta *m)
{
    free(m->levels);
    m->levels = calloc((size_t)m->nz ? (size_t)m->nz : 1, sizeof(double));
    return m->levels ? 0 : VSV_ENOMEM;
}

int vsv_meta_alloc_terrain(vsv_meta *m)
{
    free(m->terrain);
    m->terrain = calloc((size_t)m->nx * (size_t)m->ny + 1, sizeof(float));
    return m->terrain ? 0 : VSV_ENOMEM;
}

int vsv_meta_alloc_landuse(vsv_meta *m)
{
    free(m->landuse);
    m->landuse = calloc((size_t)m->nx * (size_t)m->ny + 1, sizeof(float));
    return m->landuse ? 0 : VSV_ENOMEM;
}

int vsv_meta_find_var(const vsv_meta *m, const char *name)
{
    for (int i = 0; i < m->nvars; i++)
        if (!strcmp(m->vars[i].name, name))
            return i;
    return VSV_ENOTFOUND;
}

/* 1 when s is UTF-8 text without control characters (what JSON, Python
 * and a terminal can take as it is). */
static int clean_text(const char *s)
{
    const unsigned char *p = (const unsigned char *)s;
    while (*p) {
        int n = *p < 0x80 ? 0 : (*p & 0xe0) == 0xc0 ? 1 : (*p & 0xf0) == 0xe0 ? 2 : (*p & 0xf8) == 0xf0 ? 3 : -1;
        if (n < 0 || (n == 0 && (*p < 0x20 || *p == 0x7f)) || (n == 1 && *p < 0xc2))
            return 0;
        for (int i = 1; i <= n; i++)
            if ((p[i] & 0xc0) != 0x80)
                return 0;
        p += n + 1;
    }
    return 1;
}

int vsv_meta_check_proj(const vsv_meta *m, char *msg, size_t cap)
{
    const vsv_proj *p = &m->proj;
    if (p->kind == VSV_PROJ_NONE)
        return 0;
    const double lat[3] = {p->lat0, p->lat1, p->lat2};
    static const char *const ln[3] = {"lat0", "lat1", "lat2"};
    for (int i = 0; i < 3; i++)
        if (!(fabs(lat[i]) <= 90)) {
            vsv_msg(msg, cap, "projection %s: %s %g is not a latitude (-90 to 90)", vsv_proj_name(p->kind), ln[i],
                    lat[i]);
            return VSV_EINVAL;
        }
    if (!(fabs(p->lon0) <= 360) || !(p->radius >= 0 && p->radius < 1e9)) {
        vsv_msg(msg, cap, "projection %s: lon0 %g (-360 to 360) or radius %g m (0: the default) out of range",
                vsv_proj_name(p->kind), p->lon0, p->radius);
        return VSV_EINVAL;
    }
    for (int c = 0; c < 4; c++) {
        const double x = m->origin[0] + (c & 1 ? m->nx - 1 : 0) * m->spacing[0],
                     y = m->origin[1] + (c & 2 ? m->ny - 1 : 0) * m->spacing[1];
        double la, lo;
        if (vsv_proj_inverse(p, x, y, &la, &lo) || !(fabs(la) <= 90)) {
            vsv_msg(msg, cap, "projection %s: the grid's corner cell at x %g, y %g maps to no latitude and longitude",
                    vsv_proj_name(p->kind), x, y);
            return VSV_EINVAL;
        }
    }
    return 0;
}

int vsv_meta_validate(const vsv_meta *m, char *msg, size_t cap)
{
    if (m->nx < 1 || m->ny < 1 || m->nz < 1 || m->nx > VSV_MAX_DIM || m->ny > VSV_MAX_DIM || m->nz > VSV_MAX_DIM) {
        vsv_msg(msg, cap, "grid %dx%dx%d outside 1..%d", m->nx, m->ny, m->nz, VSV_MAX_DIM);
        return VSV_EINVAL;
    }
    if ((uint64_t)m->nx * (uint64_t)m->ny * (uint64_t)m->nz > VSV_MAX_CELLS) {
        vsv_msg(msg, cap, "grid has too many cells");
        return VSV_EINVAL;
    }
    if (m->nvars < 1 || m->nvars > VSV_MAX_VARS) {
        vsv_msg(msg, cap, "%d variables (need 1..%d)", m->nvars, VSV_MAX_VARS);
        return VSV_EINVAL;
    }
    for (int i = 0; i < 3; i++)
        if (!isfinite(m->origin[i]) || !isfinite(m->spacing[i]) || !(m->spacing[i] > 0)) {
            vsv_msg(msg, cap, "origin/spacing along axis %d is not finite and positive", i);
            return VSV_EINVAL;
        }
    if (m->vert_kind < 0 || m->vert_kind > VSV_VERT_COORD) {
        vsv_msg(msg, cap, "unknown vertical kind %d", m->vert_kind);
        return VSV_EINVAL;
    }
    const char *vk = m->vert_kind == VSV_VERT_NATIVE ? "native levels" : "coordinate levels";
    if (m->vert_kind != VSV_VERT_EVEN && m->vert_kind != VSV_VERT_INDEX && !m->levels) {
        vsv_msg(msg, cap, "%s need their levels", vk);
        return VSV_EINVAL;
    }
    /* heights rise with k (level 0 drawn lowest); a coordinate (pressure)
     * may fall instead, but one way throughout. Native levels with heights
     * per column are those columns' means, in no order of their own (MM5
     * REGRID: the ground's mean height, then 1000 hPa's, lower) */
    const int ordered = m->vert_kind == VSV_VERT_COORD || (m->vert_kind == VSV_VERT_NATIVE && !m->nheights);
    for (int k = 1; m->levels && ordered && k < m->nz; k++) {
        const double d = m->levels[k] - m->levels[k - 1], d0 = m->levels[1] - m->levels[0];
        if (!(m->vert_kind == VSV_VERT_NATIVE ? d > 0 : d * d0 > 0)) {
            vsv_msg(msg, cap, "%s: level %d (%g) after level %d (%g): they must %s", vk, k, m->levels[k], k - 1,
                    m->levels[k - 1], m->vert_kind == VSV_VERT_NATIVE ? "rise with k" : "run one way");
            return VSV_EINVAL;
        }
    }
    for (int i = 0; i < m->nmoves; i++)
        if (!m->moves[i].terrain != !m->terrain) {
            vsv_msg(msg, cap, "placement %d of the moving grid %s terrain where the grid %s", i,
                    m->moves[i].terrain ? "has" : "lacks", m->terrain ? "has one" : "has none");
            return VSV_EINVAL;
        }
    if (m->proj.kind < 0 || m->proj.kind >= VSV_PROJ_COUNT) {
        vsv_msg(msg, cap, "unknown projection %d", m->proj.kind);
        return VSV_EINVAL;
    }
    if (vsv_meta_check_proj(m, msg, cap))
        return VSV_EINVAL;
    for (int i = 0; i < m->nvars; i++) {
        if (!m->vars[i].name[0]) {
            vsv_msg(msg, cap, "variable %d has no name", i);
            return VSV_EINVAL;
        }
        if (!clean_text(m->vars[i].name) || !clean_text(m->vars[i].units) || !clean_text(m->vars[i].description)) {
            vsv_msg(msg, cap,
                    "variable %d: its name, units or description is not UTF-8 text (or holds control "
                    "characters)",
                    i);
            return VSV_EINVAL;
        }
        for (int j = 0; j < i; j++)
            if (!strcmp(m->vars[i].name, m->vars[j].name)) {
                vsv_msg(msg, cap, "variable name %s appears twice", m->vars[i].name);
                return VSV_EINVAL;
            }
    }
    return 0;
}

const char *vsv_proj_name(int kind)
{
    static const char *names[] = {"none", "latlon", "lcc", "pstereo", "mercator", "tmerc", "albers"};
    return kind >= 0 && kind < VSV_PROJ_COUNT ? names[kind] : "unknown";
}
