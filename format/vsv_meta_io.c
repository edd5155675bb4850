/* vsv_meta_io.c — the tagged metadata records (SPEC.md part 1 "Metadata
 * records") shared by the .vsv file and the field stream header. */
#include "vsv_format_internal.h"

#include <math.h>
#include <stdlib.h>

static int rec_begin(vsv_buf *b, const char *tag, size_t *at)
{
    *at = b->len;
    if (vsv_buf_put(b, tag, 4) || vsv_buf_u32(b, 0))
        return VSV_ENOMEM;
    return 0;
}

static int rec_end(vsv_buf *b, size_t at)
{
    vsv_wr32(b->p + at + 4, (uint32_t)(b->len - at - 8));
    return vsv_buf_zeros(b, (size_t)(vsv_align_up(b->len, 8) - b->len));
}

int vsv_meta_encode(const vsv_meta *m, const vsv_quant *quant, int coded, vsv_buf *b)
{
    size_t at;
    int rc = 0;
    const size_t plane = (size_t)m->nx * (size_t)m->ny;
#define TRY(x)                                                                                                         \
    do {                                                                                                               \
        if ((rc = (x)))                                                                                                \
            return rc;                                                                                                 \
    } while (0)
    TRY(rec_begin(b, "GRID", &at));
    TRY(vsv_buf_u32(b, (uint32_t)m->nx));
    TRY(vsv_buf_u32(b, (uint32_t)m->ny));
    TRY(vsv_buf_u32(b, (uint32_t)m->nz));
    TRY(vsv_buf_u32(b, (uint32_t)m->vert_kind));
    for (int i = 0; i < 3; i++)
        TRY(vsv_buf_f64(b, m->origin[i]));
    for (int i = 0; i < 3; i++)
        TRY(vsv_buf_f64(b, m->spacing[i]));
    TRY(vsv_buf_str(b, m->vert_units));
    TRY(rec_end(b, at));
    if (m->levels) {
        TRY(rec_begin(b, "LEVL", &at));
        for (int k = 0; k < m->nz; k++)
            TRY(vsv_buf_f64(b, m->levels[k]));
        TRY(rec_end(b, at));
    }
    TRY(rec_begin(b, "PROJ", &at));
    TRY(vsv_buf_u32(b, (uint32_t)m->proj.kind));
    TRY(vsv_buf_u32(b, 0));
    TRY(vsv_buf_f64(b, m->proj.lat0));
    TRY(vsv_buf_f64(b, m->proj.lon0));
    TRY(vsv_buf_f64(b, m->proj.lat1));
    TRY(vsv_buf_f64(b, m->proj.lat2));
    TRY(vsv_buf_f64(b, m->proj.radius));
    TRY(rec_end(b, at));
    TRY(rec_begin(b, "SRC ", &at));
    TRY(vsv_buf_str(b, m->model));
    TRY(vsv_buf_str(b, m->run));
    TRY(rec_end(b, at));
    for (int i = 0; i < m->nattrs; i++) {
        TRY(rec_begin(b, "ATTR", &at));
        TRY(vsv_buf_str(b, m->attr_keys[i]));
        TRY(vsv_buf_str(b, m->attr_values[i]));
        TRY(rec_end(b, at));
    }
    for (int i = 0; i < m->nvars; i++) {
        TRY(rec_begin(b, "VAR ", &at));
        TRY(vsv_buf_str(b, m->vars[i].name));
        TRY(vsv_buf_str(b, m->vars[i].units));
        TRY(vsv_buf_str(b, m->vars[i].description));
        TRY(rec_end(b, at));
        if (quant) {
            const vsv_quant *q = &quant[i];
            TRY(rec_begin(b, "QUAN", &at));
            TRY(vsv_buf_u32(b, (uint32_t)i));
            TRY(vsv_buf_u32(b, (uint32_t)q->bits));
            TRY(vsv_buf_u32(b, (uint32_t)q->scale));
            TRY(vsv_buf_u32(b, q->missing ? 1u : 0u));
            TRY(vsv_buf_f64(b, q->lo));
            TRY(vsv_buf_f64(b, q->hi));
            TRY(vsv_buf_f64(b, q->threshold));
            TRY(vsv_buf_f64(b, q->max_abs_error));
            TRY(vsv_buf_f64(b, q->data_min));
            TRY(vsv_buf_f64(b, q->data_max));
            TRY(rec_end(b, at));
        }
        if (m->tf && m->tf[i]) {
            TRY(rec_begin(b, "TFUN", &at));
            TRY(vsv_buf_u32(b, (uint32_t)i));
            TRY(vsv_buf_str(b, m->tf[i]));
            TRY(rec_end(b, at));
        }
    }
    const float *planes[2] = {m->terrain, m->landuse};
    const char *tags[2][2] = {{"TERR", "LUSE"}, {"TERZ", "LUSZ"}}; /* raw; coded (format 3) */
    for (int p = 0; p < 2; p++) {
        if (!planes[p])
            continue;
        TRY(rec_begin(b, tags[coded != 0][p], &at));
        if (coded) {
            TRY(vsv_plane_code(planes[p], plane, b));
        } else {
            TRY(vsv_buf_reserve(b, plane * 4));
            for (size_t i = 0; i < plane; i++)
                vsv_wrf32(b->p + b->len + 4 * i, planes[p][i]);
            b->len += plane * 4;
        }
        TRY(rec_end(b, at));
    }
    for (int i = 0; i < m->nheights; i++) {
        TRY(rec_begin(b, "HGTS", &at));
        TRY(vsv_heights_encode(m, &m->heights[i], coded, b));
        TRY(rec_end(b, at));
    }
    for (int i = 0; i < m->nmoves; i++) {
        TRY(rec_begin(b, "MOVE", &at));
        TRY(vsv_moves_encode(m, &m->moves[i], coded, b));
        TRY(rec_end(b, at));
    }
    TRY(rec_begin(b, "END ", &at));
    TRY(rec_end(b, at));
#undef TRY
    return 0;
}

/* A bounds-checked cursor over one record's payload. */
typedef struct cursor {
    const unsigned char *p;
    size_t n, at;
    int bad;
} cursor;

static const unsigned char *take(cursor *c, size_t k)
{
    if (c->bad || k > c->n - c->at) {
        c->bad = 1;
        return NULL;
    }
    const unsigned char *r = c->p + c->at;
    c->at += k;
    return r;
}

static uint32_t get32(cursor *c)
{
    const unsigned char *p = take(c, 4);
    return p ? vsv_rd32(p) : 0;
}

static double getf64(cursor *c)
{
    const unsigned char *p = take(c, 8);
    return p ? vsv_rdf64(p) : 0;
}

static void getstr(cursor *c, char *dst, size_t cap)
{
    uint32_t n = get32(c);
    const unsigned char *p = n < cap && n <= VSV_MAX_STRING ? take(c, n) : NULL;
    if (!p) {
        c->bad = 1;
        dst[0] = 0;
        return;
    }
    memcpy(dst, p, n);
    dst[n] = 0;
    if (strlen(dst) != n)
        c->bad = 1; /* embedded NUL */
}

/* The GRID record: the dimensions, origin, spacing and vertical kind; 0 or VSV_ECORRUPT. */
static int decode_grid(vsv_meta *m, cursor *c, char *msg, size_t cap)
{
    m->nx = (int)get32(c);
    m->ny = (int)get32(c);
    m->nz = (int)get32(c);
    m->vert_kind = (int)get32(c);
    for (int i = 0; i < 3; i++)
        m->origin[i] = getf64(c);
    for (int i = 0; i < 3; i++)
        m->spacing[i] = getf64(c);
    getstr(c, m->vert_units, sizeof m->vert_units);
    if (m->nx < 1 || m->ny < 1 || m->nz < 1 || m->nx > VSV_MAX_DIM || m->ny > VSV_MAX_DIM || m->nz > VSV_MAX_DIM) {
        vsv_msg(msg, cap, "GRID record: dimensions out of range");
        return VSV_ECORRUPT;
    }
    return 0;
}

/* A LEVL, TERR or LUSE record (the levels, or a plane the size of the grid's),
 * or TERZ, LUSZ (the plane coded); 0 or VSV_ECORRUPT. */
static int decode_plane(vsv_meta *m, cursor *c, const char *tag, uint32_t len, int have_grid, char *msg, size_t cap)
{
    if (!have_grid) {
        vsv_msg(msg, cap, "'%s' record before GRID", tag);
        return VSV_ECORRUPT;
    }
    if (tag[0] == 'L' && tag[1] == 'E') {
        if (len != (size_t)m->nz * 8 || m->levels || vsv_meta_alloc_levels(m)) {
            vsv_msg(msg, cap, "LEVL record: %u bytes for %d levels", len, m->nz);
            return VSV_ECORRUPT;
        }
        for (int k = 0; k < m->nz; k++)
            m->levels[k] = getf64(c);
    } else {
        const size_t plane = (size_t)m->nx * (size_t)m->ny;
        float **dst = tag[0] == 'T' ? &m->terrain : &m->landuse;
        const int coded = tag[3] == 'Z';
        if ((coded ? !len : len != plane * 4) || *dst ||
            (tag[0] == 'T' ? vsv_meta_alloc_terrain(m) : vsv_meta_alloc_landuse(m))) {
            vsv_msg(msg, cap, "%s record: %u bytes for a %dx%d plane, or a second one", tag, len, m->nx, m->ny);
            return VSV_ECORRUPT;
        }
        int rc = 0;
        if (coded)
            rc = vsv_plane_decode(c->p, len, plane, *dst);
        else
            for (size_t i = 0; i < plane; i++)
                (*dst)[i] = vsv_rdf32(c->p + 4 * i);
        if (rc == VSV_ENOMEM) {
            vsv_msg(msg, cap, "%s record: out of memory decoding its %dx%d plane", tag, m->nx, m->ny);
            return rc;
        }
        if (rc) {
            vsv_msg(msg, cap, "%s record: %u bytes that do not decode to a %dx%d plane", tag, len, m->nx, m->ny);
            return rc;
        }
        c->at = len;
    }
    return 0;
}

/* A VAR record: one more variable, and its (zeroed) quantisation in *quant; 0 or VSV_ECORRUPT. */
static int decode_var(vsv_meta *m, cursor *c, vsv_quant **quant, char *msg, size_t cap)
{
    vsv_var v;
    getstr(c, v.name, sizeof v.name);
    getstr(c, v.units, sizeof v.units);
    getstr(c, v.description, sizeof v.description);
    if (!c->bad) {
        int idx = vsv_meta_add_var(m, v.name, v.units, v.description);
        vsv_quant *nq = m->nvars ? realloc(*quant, (size_t)m->nvars * sizeof *nq) : *quant;
        if (nq)
            *quant = nq; /* (moved even when the variable was refused) */
        if (idx < 0 || !nq) {
            vsv_msg(msg, cap, "too many variables");
            return VSV_ECORRUPT;
        }
        memset(&(*quant)[idx], 0, sizeof **quant);
    }
    return 0;
}

/* A QUAN record: the quantisation of the variable just declared; 0 or VSV_ECORRUPT. */
static int decode_quan(const vsv_meta *m, cursor *c, vsv_quant *quant, char *msg, size_t cap)
{
    uint32_t i = get32(c);
    if (i != (uint32_t)m->nvars - 1 || !quant) {
        vsv_msg(msg, cap, "QUAN record for variable %u out of order", i);
        return VSV_ECORRUPT;
    }
    vsv_quant *q = &quant[i];
    q->bits = (int)get32(c);
    q->scale = (int)get32(c);
    const uint32_t flags = get32(c);
    q->missing = flags & 1;
    if (flags > 1 || (q->missing && q->scale != VSV_SCALE_LINEAR))
        c->bad = 1;
    q->lo = getf64(c);
    q->hi = getf64(c);
    q->threshold = getf64(c);
    q->max_abs_error = getf64(c);
    q->data_min = getf64(c);
    q->data_max = getf64(c);
    if ((q->bits != 8 && q->bits != 16) || (q->scale != 0 && q->scale != 1) || !isfinite(q->lo) || !isfinite(q->hi) ||
        !(q->hi >= q->lo) || (q->scale == VSV_SCALE_LOG && !(q->lo > 0))) {
        vsv_msg(msg, cap, "QUAN record of variable %u has invalid parameters", i);
        return VSV_ECORRUPT;
    }
    return 0;
}

/* A TFUN record: a variable's transfer function text (sbuf: VSV_MAX_STRING + 1 bytes of scratch); 0,
 * VSV_ECORRUPT or VSV_ENOMEM. */
static int decode_tfun(vsv_meta *m, cursor *c, char *sbuf, char *msg, size_t cap)
{
    uint32_t i = get32(c);
    getstr(c, sbuf, VSV_MAX_STRING + 1);
    if (!c->bad) {
        if (i >= (uint32_t)m->nvars) {
            vsv_msg(msg, cap, "TFUN record for unknown variable %u", i);
            return VSV_ECORRUPT;
        }
        if (!m->tf && !(m->tf = calloc((size_t)m->nvars + 1, sizeof(char *))))
            return VSV_ENOMEM;
        free(m->tf[i]);
        if (!(m->tf[i] = strdup(sbuf)))
            return VSV_ENOMEM;
    }
    return 0;
}

int vsv_meta_decode(const unsigned char *p, size_t n, vsv_meta *m, vsv_quant **quant_out, char *msg, size_t cap)
{
    vsv_meta_clear(m);
    vsv_quant *quant = NULL;
    char *sbuf = malloc(VSV_MAX_STRING + 1);
    int have_grid = 0, have_end = 0, nquant = 0;
    int rc = VSV_ECORRUPT;
    size_t at = 0;
    if (!sbuf)
        return VSV_ENOMEM;
    while (!have_end) {
        if (n - at < 8) {
            vsv_msg(msg, cap, "metadata ends without END record at byte %zu", at);
            goto fail;
        }
        char tag[5];
        memcpy(tag, p + at, 4);
        tag[4] = 0;
        uint32_t len = vsv_rd32(p + at + 4);
        size_t padded = (size_t)vsv_align_up(len, 8);
        if (len > n - at - 8 || padded > n - at - 8) {
            vsv_msg(msg, cap, "metadata record '%s' at byte %zu overruns the section", tag, at);
            goto fail;
        }
        for (size_t i = len; i < padded; i++)
            if (p[at + 8 + i]) {
                vsv_msg(msg, cap, "non-zero padding after metadata record '%s' at byte %zu", tag, at);
                goto fail;
            }
        cursor c = {p + at + 8, len, 0, 0};
        int e = 0; /* the record's error: VSV_ECORRUPT (the message in msg) or VSV_ENOMEM */
        if (!strcmp(tag, "GRID")) {
            if (!(e = decode_grid(m, &c, msg, cap)))
                have_grid = 1;
        } else if (!strcmp(tag, "LEVL") || !strcmp(tag, "TERR") || !strcmp(tag, "LUSE") || !strcmp(tag, "TERZ") ||
                   !strcmp(tag, "LUSZ")) {
            e = decode_plane(m, &c, tag, len, have_grid, msg, cap);
        } else if (!strcmp(tag, "PROJ")) {
            m->proj.kind = (int)get32(&c);
            if (get32(&c) != 0)
                c.bad = 1;
            m->proj.lat0 = getf64(&c);
            m->proj.lon0 = getf64(&c);
            m->proj.lat1 = getf64(&c);
            m->proj.lat2 = getf64(&c);
            m->proj.radius = getf64(&c);
        } else if (!strcmp(tag, "SRC ")) {
            getstr(&c, m->model, sizeof m->model);
            getstr(&c, m->run, sizeof m->run);
        } else if (!strcmp(tag, "ATTR")) {
            char key[64];
            getstr(&c, key, sizeof key);
            getstr(&c, sbuf, 256);
            if (!c.bad && vsv_meta_add_attr(m, key, sbuf))
                e = VSV_ENOMEM;
        } else if (!strcmp(tag, "VAR ")) {
            e = decode_var(m, &c, &quant, msg, cap);
        } else if (!strcmp(tag, "QUAN")) {
            if (!(e = decode_quan(m, &c, quant, msg, cap)))
                nquant++;
        } else if (!strcmp(tag, "TFUN")) {
            e = decode_tfun(m, &c, sbuf, msg, cap);
        } else if (!strcmp(tag, "HGTS")) {
            if (!have_grid) {
                vsv_msg(msg, cap, "'HGTS' record before GRID");
                goto fail;
            }
            e = vsv_heights_decode(m, c.p, len, msg, cap);
            c.at = len;
        } else if (!strcmp(tag, "MOVE")) {
            if (!have_grid) {
                vsv_msg(msg, cap, "'MOVE' record before GRID");
                goto fail;
            }
            e = vsv_moves_decode(m, c.p, len, msg, cap);
            c.at = len;
        } else if (!strcmp(tag, "END ")) {
            have_end = 1;
        } else {
            c.at = len; /* other tags: skipped (added by a later minor version) */
        }
        if (e) {
            rc = e;
            goto fail;
        }
        if (c.bad || c.at != len) {
            vsv_msg(msg, cap, "metadata record '%s' at byte %zu is malformed", tag, at);
            goto fail;
        }
        at += 8 + padded;
    }
    if (at != n) {
        vsv_msg(msg, cap, "%zu bytes after the END metadata record", n - at);
        goto fail;
    }
    if (!have_grid) {
        vsv_msg(msg, cap, "metadata has no GRID record");
        goto fail;
    }
    if (vsv_meta_validate(m, msg, cap))
        goto fail;
    if (quant_out) {
        if (nquant != m->nvars) {
            vsv_msg(msg, cap, "%d of %d variables have QUAN records", nquant, m->nvars);
            goto fail;
        }
        *quant_out = quant;
        quant = NULL;
    }
    free(quant);
    free(sbuf);
    return 0;
fail:
    free(quant);
    free(sbuf);
    vsv_meta_clear(m);
    return rc;
}
