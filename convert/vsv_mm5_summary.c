/* vsv_mm5_summary.c — what vsv-info says of an MM5 v3 file: its program
 * and run, domain, projection, reference state, output times and the
 * fields of one output time, from the big header and the record index. */
#include "vsv_mm5.h"
#include "vsv_source_internal.h"

#include <string.h>

char *vsv_mm5_summary(const vsv_source *s, const vsv_mm5 *m, int IX, int JX)
{
    vsv_buf b = {0};
    char line[512], desc[96];
    const int prog = vsv_mm5_bhi(m, 1, 1);
#define OUT(...) (snprintf(line, sizeof line, __VA_ARGS__), vsv_buf_put(&b, line, strlen(line)))
    OUT("MM5 v3 file, %s-endian, written by program %d (%s); %d big header%s\n",
        vsv_mm5_little_endian(m) ? "little" : "big", prog, s->grid.run, vsv_mm5_nbighdr(m),
        vsv_mm5_nbighdr(m) == 1 ? "" : "s");
    static const char *pn[] = {"?", "Lambert conformal", "polar stereographic", "Mercator"};
    const int proj = vsv_mm5_bhi(m, 7, 1);
    OUT("  domain      %d: %d x %d dot points (IX south-north, JX west-east), nest level %d, ratio %d\n",
        vsv_mm5_bhi(m, 13, 1), IX, JX, vsv_mm5_bhi(m, 15, 1), vsv_mm5_bhi(m, 20, 1));
    OUT("  coarse      %d x %d, %.0f m; this domain starts at coarse (I, J) = (%g, %g)\n", vsv_mm5_bhi(m, 5, 1),
        vsv_mm5_bhi(m, 6, 1), vsv_mm5_bhr(m, 1, 1), vsv_mm5_bhr(m, 10, 1), vsv_mm5_bhr(m, 11, 1));
    OUT("  projection  %s, centre %.4g, %.4g, true latitudes %.4g / %.4g, cone factor %.4g, grid %.0f m\n",
        proj >= 1 && proj <= 3 ? pn[proj] : "unknown", vsv_mm5_bhr(m, 2, 1), vsv_mm5_bhr(m, 3, 1), vsv_mm5_bhr(m, 5, 1),
        vsv_mm5_bhr(m, 6, 1), vsv_mm5_bhr(m, 4, 1), vsv_mm5_bhr(m, 9, 1));
    if (vsv_mm5_bhr(m, 2, 2) > 0)
        OUT("  PTOP        %g Pa\n", vsv_mm5_bhr(m, 2, 2));
    if (vsv_mm5_bhr(m, 2, 5) > 0)
        OUT("  base state  P00 %g Pa, TS0 %g K, TLP %g K, TISO %g K\n", vsv_mm5_bhr(m, 2, 5), vsv_mm5_bhr(m, 3, 5),
            vsv_mm5_bhr(m, 4, 5), vsv_mm5_bhr(m, 5, 5));
    if (vsv_mm5_bhi(m, 5, 11) > 0)
        OUT("  MM5 run     start %04d-%02d-%02d %02d:%02d, %d layers, output every %g min, IMPHYS %d\n",
            vsv_mm5_bhi(m, 5, 11), vsv_mm5_bhi(m, 6, 11), vsv_mm5_bhi(m, 7, 11), vsv_mm5_bhi(m, 8, 11),
            vsv_mm5_bhi(m, 9, 11), vsv_mm5_bhi(m, 12, 11), vsv_mm5_bhr(m, 4, 12), vsv_mm5_bhi(m, 3, 13));
    vsv_mm5_bhic(m, 1, 1, desc, sizeof desc);
    OUT("  periods     %d output time%s", vsv_mm5_nperiods(m), vsv_mm5_nperiods(m) == 1 ? "" : "s");
    for (int t = 0; t < s->ntimes && t < 12; t++) {
        char tb[40];
        vsv_time_format(s->times[t], tb, sizeof tb);
        OUT("%s%s", t ? ", " : ": ", tb);
    }
    OUT("%s\n", s->ntimes > 12 ? ", ..." : "");
    if (vsv_mm5_skipped(m))
        OUT("  note        %d boundary-slab records (YSB XSB YWB XWB): lateral boundary values, not volumes\n",
            vsv_mm5_skipped(m));
    OUT("  fields      %d per output time\n    %-9s %-7s %-16s %-16s %s\n", s->nfields, "name", "order", "dims",
        "units", "description");
    for (int i = 0; i < vsv_mm5_nfields(m); i++) {
        const vsv_mm5_field *f = vsv_mm5_field_at(m, i);
        if (f->period != vsv_mm5_field_at(m, 0)->period)
            break;
        char dims[32];
        snprintf(dims, sizeof dims, "%d", f->end[0] - f->start[0] + 1);
        for (int d = 1; d < f->ndim; d++)
            snprintf(dims + strlen(dims), sizeof dims - strlen(dims), "x%d", f->end[d] - f->start[d] + 1);
        OUT("    %-9s %-3s %-3s %-16s %-16s %s\n", f->name, f->order, f->stag, dims, f->units, f->desc);
    }
#undef OUT
    vsv_buf_put(&b, "", 1);
    return (char *)b.p;
}
