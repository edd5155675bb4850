/* vsv_plot_out.c — a plot written as PNG, SVG or PDF (vsv_plot_write): drawn
 * by vsv_plot_draw.c on the cairo surface of the format into memory, then
 * written to a temporary beside the output and renamed into place. cairo's
 * SVG writes glyphs as outlines that no script, search or editor can read,
 * so in SVG the plot's texts are <text> elements instead, set in DejaVu
 * Sans at the places cairo would draw them. */
#include "vsv_plot_draw.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

static cairo_status_t collect(void *closure, const unsigned char *data, unsigned int n)
{
    return vsv_buf_put(closure, data, n) ? CAIRO_STATUS_NO_MEMORY : CAIRO_STATUS_SUCCESS;
}

/* The SVG cairo wrote (in b) with the texts (t) in a group before its
 * closing tag, into out. 0 or VSV_ENOMEM (VSV_EINVAL: no closing tag). */
static int svg_join(const vsv_buf *b, const vsv_buf *t, vsv_buf *out)
{
    static const char close[] = "</svg>";
    size_t at = b->len;
    while (at >= sizeof close - 1 && memcmp(b->p + at - (sizeof close - 1), close, sizeof close - 1))
        at--;
    if (at < sizeof close - 1)
        return VSV_EINVAL;
    at -= sizeof close - 1;
    int err = vsv_buf_put(out, b->p, at);
    err |= vsv_plot_put(out, "<g font-family=\"DejaVu Sans, Verdana, sans-serif\" fill=\"#000000\">\n");
    err |= vsv_buf_put(out, t->p, t->len);
    err |= vsv_plot_put(out, "</g>\n</svg>\n");
    return err ? VSV_ENOMEM : 0;
}

/* Draws p on a surface of format fmt into out (the file's bytes). 0 or an error code. */
static int render(const vsv_plot *p, int fmt, vsv_buf *out, char *msg, size_t cap)
{
    const double w = p->o.size[0], h = p->o.size[1];
    vsv_buf raw = {0}, texts = {0};
    cairo_surface_t *s = fmt == VSV_PLOT_PNG   ? cairo_image_surface_create(CAIRO_FORMAT_RGB24, (int)w, (int)h)
                         : fmt == VSV_PLOT_SVG ? cairo_svg_surface_create_for_stream(collect, &raw, w, h)
                                               : cairo_pdf_surface_create_for_stream(collect, &raw, w, h);
    if (fmt == VSV_PLOT_SVG)
        cairo_svg_surface_set_document_unit(s, CAIRO_SVG_UNIT_PX);
    if (fmt == VSV_PLOT_PDF) {
        char creator[64];
        snprintf(creator, sizeof creator, "Vesuvius %s (vsv-plot)", VSV_VERSION_STRING);
        cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_TITLE, p->title);
        cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_CREATOR, creator);
    }
    cairo_t *cr = cairo_create(s);
    plot_canvas c = {.cr = cr, .svg = fmt == VSV_PLOT_SVG ? &texts : NULL, .w = w, .h = h};
    int rc = vsv_plot_draw(p, &c);
    cairo_status_t st = cairo_status(cr);
    cairo_destroy(cr);
    if (!rc && !st && fmt == VSV_PLOT_PNG)
        st = cairo_surface_write_to_png_stream(s, collect, &raw);
    cairo_surface_finish(s); /* SVG and PDF: the last bytes */
    if (!st)
        st = cairo_surface_status(s);
    cairo_surface_destroy(s);
    if (!rc && st) {
        vsv_msg(msg, cap, "drawing failed: %s", cairo_status_to_string(st));
        rc = st == CAIRO_STATUS_NO_MEMORY ? VSV_ENOMEM : VSV_EIO;
    } else if (rc) {
        vsv_msg(msg, cap, "drawing failed: %s", vsv_strerror(rc));
    } else if (fmt == VSV_PLOT_SVG) {
        if ((rc = svg_join(&raw, &texts, out)))
            vsv_msg(msg, cap, "%s", rc == VSV_ENOMEM ? "out of memory" : "cairo wrote no whole SVG");
    } else {
        *out = raw;
        raw.p = NULL;
    }
    vsv_buf_free(&raw);
    vsv_buf_free(&texts);
    return rc;
}

int vsv_plot_write(const vsv_plot *p, const char *path, char *msg, size_t cap)
{
    const int fmt = vsv_plot_format(path);
    if (fmt < 0) {
        vsv_msg(msg, cap, "%s: the format comes from the name: .png, .svg or .pdf", path);
        return VSV_EINVAL;
    }
    vsv_buf out = {0};
    char why[256], tmp[4200];
    int rc = render(p, fmt, &out, why, sizeof why);
    if (rc) {
        vsv_msg(msg, cap, "%s: %s", path, why);
        goto fail;
    }
    const int fd = vsv_output_temp(path, NULL, tmp, sizeof tmp);
    if (fd < 0) {
        vsv_msg(msg, cap, "%s: cannot create: %s", path, strerror(errno));
        rc = VSV_EIO;
        goto fail;
    }
    if (vsv_write_full(fd, out.p, out.len, -1)) {
        vsv_msg(msg, cap, "%s: cannot write: %s", path, strerror(errno));
        close(fd);
        vsv_output_discard(tmp);
        rc = VSV_EIO;
        goto fail;
    }
    if (vsv_output_commit(fd, tmp, path)) {
        vsv_msg(msg, cap, "%s: cannot write: %s", path, strerror(errno));
        rc = VSV_EIO;
    }
fail:
    vsv_buf_free(&out);
    return rc;
}
