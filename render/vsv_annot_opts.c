/* vsv_annot_opts.c — the annotation as the tools ask for it (vsv_render.h):
 * --annotate's part names, and the font and outlines a frame's parts need,
 * sized for the frame, so vsv-render and vsv-play annotate alike. */
#include "vsv_render.h"

#include <stdio.h>
#include <string.h>

int vsv_annot_parse(const char *list, unsigned *parts, char *msg, size_t cap)
{
    static const struct {
        const char *name;
        unsigned bit;
    } names[] = {
        {"time", VSV_ANNOT_TIME},      {"bars", VSV_ANNOT_COLOURBAR},      {"exaggeration", VSV_ANNOT_EXAGGERATION},
        {"scale", VSV_ANNOT_SCALEBAR}, {"graticule", VSV_ANNOT_GRATICULE}, {"outlines", VSV_ANNOT_OUTLINES},
        {"all", VSV_ANNOT_ALL}};
    unsigned got = 0;
    for (const char *p = list ? list : ""; *p;) {
        const size_t n = strcspn(p, ",");
        size_t i = 0;
        while (i < sizeof names / sizeof *names && (strlen(names[i].name) != n || strncmp(names[i].name, p, n)))
            i++;
        if (i == sizeof names / sizeof *names) {
            snprintf(msg, cap, "--annotate %s: parts are time, bars, exaggeration, scale, graticule, outlines, all",
                     list);
            return VSV_EINVAL;
        }
        got |= names[i].bit;
        p += n + (p[n] == ',');
    }
    if (!got) {
        snprintf(msg, cap, "--annotate %s: no part named (--no-annotate for none)", list ? list : "");
        return VSV_EINVAL;
    }
    *parts = got;
    return 0;
}

int vsv_annot_load(const vsv_meta *m, unsigned parts, int w, int h, double span_m, int notes_all, vsv_font **font,
                   vsv_outlines **outlines, char *note, size_t cap)
{
    char err[512];
    size_t n = 0;
    *font = NULL;
    *outlines = NULL;
    note[0] = 0;
    if (parts) {
        const int px = h / 40 < 11 ? 11 : h / 40 > 32 ? 32 : h / 40;
        if (vsv_font_open(NULL, px, font, err, sizeof err))
            n += (size_t)snprintf(note + n, n < cap ? cap - n : 0, "%s: frames without text", err);
    }
    if (parts & VSV_ANNOT_OUTLINES) {
        const double km = span_m / (w > 0 ? w : 1) / 1000;
        const int rc = vsv_outlines_load(m, NULL, vsv_outlines_resolution(km), outlines, err, sizeof err);
        if (rc == VSV_ENOTFOUND || (rc == VSV_EUNSUPPORTED && notes_all)) /* a missing package, always */
            snprintf(note + n, n < cap ? cap - n : 0, "%s%s", n ? "\n" : "", err);
        else if (rc && rc != VSV_EUNSUPPORTED) {
            vsv_font_free(*font);
            *font = NULL;
            snprintf(note, cap, "%s", err);
            return rc;
        }
    }
    return 0;
}
