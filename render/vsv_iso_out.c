/* vsv_iso_out.c — an extracted isosurface written as a file other tools
 * read (vsv_iso_write): binary PLY (MeshLab, Blender, ParaView) or glTF 2.0
 * with its buffer embedded (Blender, three.js, any web viewer). */
#include "vsv_render.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* The whole surface in one set of arrays: every brick's vertices, its
 * triangles' indices moved past the bricks before it. */
typedef struct iso_all {
    float *pos, *nrm;
    uint32_t *tri;
    size_t nv, nt;
} iso_all;

static int gather(const vsv_iso *s, iso_all *A)
{
    vsv_iso_info in;
    vsv_iso_get_info(s, &in);
    memset(A, 0, sizeof *A);
    if (!in.ntris)
        return VSV_ERANGE;
    if (in.nverts > UINT32_MAX)
        return VSV_ENOMEM;
    A->pos = malloc(in.nverts * 3 * sizeof *A->pos);
    A->nrm = malloc(in.nverts * 3 * sizeof *A->nrm);
    A->tri = malloc(in.ntris * 3 * sizeof *A->tri);
    if (!A->pos || !A->nrm || !A->tri)
        return VSV_ENOMEM;
    vsv_iso_mesh b;
    for (int i = 0; vsv_iso_brick(s, i, &b) == 0; i++) {
        if (!b.nverts) /* a skipped brick: no arrays */
            continue;
        memcpy(A->pos + 3 * A->nv, b.pos, (size_t)b.nverts * 3 * sizeof *A->pos);
        memcpy(A->nrm + 3 * A->nv, b.nrm, (size_t)b.nverts * 3 * sizeof *A->nrm);
        for (int t = 0; t < 3 * b.ntris; t++)
            A->tri[3 * A->nt + t] = (uint32_t)A->nv + b.tri[t];
        A->nv += (size_t)b.nverts;
        A->nt += (size_t)b.ntris;
    }
    return 0;
}

static void put_u32(unsigned char *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (unsigned char)(v >> (8 * i));
}

static void put_f32(unsigned char *p, float f)
{
    uint32_t v;
    memcpy(&v, &f, 4);
    put_u32(p, v);
}

/* Title text safe in a PLY comment line or a JSON string: printable ASCII
 * without quotes or backslashes. */
static void clean(const char *in, char *out, size_t cap)
{
    size_t n = 0;
    for (; in && *in && n + 1 < cap; in++)
        out[n++] = *in >= 32 && *in < 127 && *in != '"' && *in != '\\' ? *in : '_';
    out[n] = 0;
}

static void write_ply(FILE *fp, const iso_all *A, const float rgb[3], const char *title)
{
    char t[256];
    clean(title, t, sizeof t);
    fprintf(fp,
            "ply\nformat binary_little_endian 1.0\ncomment vesuvius isosurface%s%s\n"
            "comment x east, y north, z up, metres (the file's projected frame)\n"
            "element vertex %zu\nproperty float x\nproperty float y\nproperty float z\n"
            "property float nx\nproperty float ny\nproperty float nz\n"
            "property uchar red\nproperty uchar green\nproperty uchar blue\n"
            "element face %zu\nproperty list uchar uint vertex_indices\nend_header\n",
            t[0] ? ": " : "", t, A->nv, A->nt);
    unsigned char c[3], rec[27];
    for (int k = 0; k < 3; k++)
        c[k] = (unsigned char)lrintf(fminf(fmaxf(rgb[k], 0), 1) * 255);
    for (size_t v = 0; v < A->nv; v++) {
        for (int k = 0; k < 3; k++) {
            put_f32(rec + 4 * k, A->pos[3 * v + k]);
            put_f32(rec + 12 + 4 * k, A->nrm[3 * v + k]);
        }
        memcpy(rec + 24, c, 3);
        fwrite(rec, 1, 27, fp);
    }
    for (size_t f = 0; f < A->nt; f++) {
        rec[0] = 3;
        for (int k = 0; k < 3; k++)
            put_u32(rec + 1 + 4 * k, A->tri[3 * f + k]);
        fwrite(rec, 1, 13, fp);
    }
}

/* base64 of a stream of bytes, three at a time (the tail padded). */
typedef struct b64 {
    FILE *fp;
    unsigned char in[3];
    int n;
} b64;

static void b64_flush(b64 *e)
{
    static const char abc[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    if (!e->n)
        return;
    const unsigned v = (unsigned)e->in[0] << 16 | (e->n > 1 ? (unsigned)e->in[1] << 8 : 0) | (e->n > 2 ? e->in[2] : 0);
    const char out[4] = {abc[v >> 18], abc[v >> 12 & 63], e->n > 1 ? abc[v >> 6 & 63] : '=',
                         e->n > 2 ? abc[v & 63] : '='};
    fwrite(out, 1, 4, e->fp);
    e->n = 0;
}

static void b64_put(b64 *e, const unsigned char *p, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        e->in[e->n++] = p[i];
        if (e->n == 3)
            b64_flush(e);
    }
}

/* The world's (x, y, z) as glTF's axes: +Y up, right-handed (a rotation, so
 * the triangles keep their winding). */
static void gltf_axes(const float *w, float g[3]) { g[0] = w[0], g[1] = w[2], g[2] = -w[1]; }

static void write_gltf(FILE *fp, const iso_all *A, const float rgb[3], const char *title)
{
    char t[256];
    clean(title, t, sizeof t);
    float mn[3] = {INFINITY, INFINITY, INFINITY}, mx[3] = {-INFINITY, -INFINITY, -INFINITY}, g[3];
    for (size_t v = 0; v < A->nv; v++) {
        gltf_axes(A->pos + 3 * v, g);
        for (int k = 0; k < 3; k++)
            mn[k] = fminf(mn[k], g[k]), mx[k] = fmaxf(mx[k], g[k]);
    }
    const size_t vb = A->nv * 12, ib = A->nt * 12, total = 2 * vb + ib;
    fprintf(fp, "{\"asset\":{\"version\":\"2.0\",\"generator\":\"vesuvius " VSV_VERSION_STRING "\"},\n");
    fprintf(fp, "\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\n\"nodes\":[{\"mesh\":0,\"name\":\"%s\"}],\n", t);
    fprintf(fp,
            "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorFactor\":[%.6g,%.6g,%.6g,1],"
            "\"metallicFactor\":0,\"roughnessFactor\":1},\"doubleSided\":true}],\n",
            rgb[0], rgb[1], rgb[2]);
    fprintf(fp, "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":1},\"indices\":2,"
                "\"material\":0,\"mode\":4}]}],\n");
    fprintf(fp,
            "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\","
            "\"min\":[%.9g,%.9g,%.9g],\"max\":[%.9g,%.9g,%.9g]},\n"
            " {\"bufferView\":1,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\"},\n"
            " {\"bufferView\":2,\"componentType\":5125,\"count\":%zu,\"type\":\"SCALAR\"}],\n",
            A->nv, mn[0], mn[1], mn[2], mx[0], mx[1], mx[2], A->nv, 3 * A->nt);
    fprintf(fp,
            "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":%zu,\"target\":34962},\n"
            " {\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu,\"target\":34962},\n"
            " {\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu,\"target\":34963}],\n",
            vb, vb, vb, 2 * vb, ib);
    fprintf(fp, "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"data:application/octet-stream;base64,", total);
    b64 e = {fp, {0}, 0};
    unsigned char q[12];
    for (int part = 0; part < 2; part++)
        for (size_t v = 0; v < A->nv; v++) {
            if (part == 0)
                gltf_axes(A->pos + 3 * v, g);
            else
                gltf_axes(A->nrm + 3 * v, g);
            for (int k = 0; k < 3; k++)
                put_f32(q + 4 * k, g[k]);
            b64_put(&e, q, 12);
        }
    for (size_t i = 0; i < 3 * A->nt; i++) {
        put_u32(q, A->tri[i]);
        b64_put(&e, q, 4);
    }
    b64_flush(&e);
    fprintf(fp, "\"}]}\n");
}

int vsv_iso_write(const vsv_iso *s, const char *path, int format, const float rgb[3], const char *title, char *msg,
                  size_t cap)
{
    iso_all A;
    int rc = gather(s, &A);
    if (rc) {
        snprintf(msg, cap, rc == VSV_ERANGE ? "%s: no triangle to write" : "%s: out of memory", path);
        goto done;
    }
    char tmp[4200];
    const int fd = vsv_output_temp(path, NULL, tmp, sizeof tmp);
    FILE *fp = fd >= 0 ? fdopen(fd, "wb") : NULL;
    if (!fp) {
        snprintf(msg, cap, "%s: cannot create: %s", path, strerror(errno));
        if (fd >= 0)
            close(fd), vsv_output_discard(tmp);
        rc = VSV_EIO;
        goto done;
    }
    if (format == VSV_ISO_GLTF)
        write_gltf(fp, &A, rgb, title);
    else
        write_ply(fp, &A, rgb, title);
    /* a full disk or a failed write shows at the flush, fsync or close */
    const int bad = fflush(fp) || ferror(fp) || fsync(fileno(fp));
    const int e = errno;
    if (fclose(fp) || bad || vsv_output_publish(tmp, path)) {
        snprintf(msg, cap, "%s: cannot write: %s", path, strerror(bad ? e : errno));
        vsv_output_discard(tmp);
        rc = VSV_EIO;
    }
done:
    free(A.pos);
    free(A.nrm);
    free(A.tri);
    return rc;
}
