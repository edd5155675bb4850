/* test_tf_change.c — the colour and scale options every renderer takes
 * (--colormap SPECIES:NAME, --log SPECIES, --range SPECIES:LO:HI): parsed,
 * refused with their reason, and applied as documented — a log scale over
 * a range from 0 spans the four decades below the top, so a value a
 * hundredth of the top takes the colour map's middle. */
#include "vsv_render.h"
#include "vsv_testlib.h"

#include <math.h>
#include <string.h>

static int parse(const char *opt, const char *arg, vsv_tf_change *c, char *msg)
{
    return vsv_tf_change_parse(opt, arg, c, msg, 256);
}

static void test_parse(void)
{
    vsv_tf_change c;
    char msg[256];
    CHECK(!parse("colormap", "CLW:magma", &c, msg) && !strcmp(c.species, "CLW") && !strcmp(c.line, "colormap magma"),
          "--colormap CLW:magma");
    CHECK(parse("colormap", "CLW:rainbow", &c, msg) == VSV_EINVAL && strstr(msg, "no colour map 'rainbow'") &&
              strstr(msg, "inferno") && strstr(msg, "plasma"),
          "an unknown colour map is refused, the maps named", "%s", msg);
    CHECK(!parse("log", "SNOW", &c, msg) && !strcmp(c.species, "SNOW") && !strcmp(c.line, "scale log"), "--log SNOW");
    CHECK(!parse("range", "Q:0.001:0.02", &c, msg) && !strcmp(c.species, "Q") && !strncmp(c.line, "range 0.001", 11),
          "--range Q:0.001:0.02");
    CHECK(!parse("range", "Q=0:1", &c, msg) && !strcmp(c.species, "Q"), "--range Q=0:1 (the older spelling)");
    CHECK(parse("range", "Q:1:0", &c, msg) == VSV_EINVAL && strstr(msg, "LO < HI"), "--range with LO >= HI refused");
    CHECK(parse("range", "Q:0:inf", &c, msg) == VSV_EINVAL, "--range to infinity refused");
    CHECK(parse("colormap", ":magma", &c, msg) == VSV_EINVAL && strstr(msg, "SPECIES:NAME"),
          "--colormap without a species refused", "%s", msg);
    CHECK(parse("log", "", &c, msg) == VSV_EINVAL, "--log without a species refused");
}

static void test_apply(void)
{
    vsv_tf lin, lg;
    char msg[256];
    vsv_tf_change c;
    CHECK(!vsv_tf_parse(&lin, "colormap viridis\nrange 0 0.001\nopacity 1 1\n", msg, sizeof msg), "a linear tf");
    lg = lin;
    parse("log", "CLW", &c, msg);
    CHECK(!vsv_tf_change_apply(&lg, &c, msg, sizeof msg) && lg.scale == VSV_SCALE_LOG && fabs(lg.lo - 1e-7) < 1e-20 &&
              lg.hi == 0.001,
          "--log over 0..top spans the four decades below the top", "%g..%g", lg.lo, lg.hi);
    float a[4], b[4];
    vsv_tf_eval(&lg, 1e-5f, a);  /* two decades below the top: the middle of the map */
    vsv_tf_eval(&lin, 5e-4f, b); /* the middle of the linear range */
    CHECK(fabsf(a[0] - b[0]) < 0.02f && fabsf(a[1] - b[1]) < 0.02f && fabsf(a[2] - b[2]) < 0.02f,
          "a hundredth of the top takes the map's middle on the log scale", "%g %g %g vs %g %g %g", a[0], a[1], a[2],
          b[0], b[1], b[2]);
    vsv_tf t = lin;
    parse("colormap", "CLW:magma", &c, msg);
    CHECK(!vsv_tf_change_apply(&t, &c, msg, sizeof msg) && !strcmp(t.colormap, "magma") && t.lo == 0 && t.hi == 0.001 &&
              t.scale == VSV_SCALE_LINEAR,
          "--colormap changes the map alone");
    vsv_tf_eval(&t, 0.001f, a);
    CHECK(a[0] > 0.95f && a[1] > 0.95f && a[2] > 0.7f, "magma's top is its pale yellow", "%g %g %g", a[0], a[1], a[2]);
    t = lg;
    parse("range", "CLW:0:0.002", &c, msg);
    CHECK(vsv_tf_change_apply(&t, &c, msg, sizeof msg) == VSV_EINVAL && strstr(msg, "log scale") &&
              t.scale == VSV_SCALE_LOG && t.lo == lg.lo,
          "a range from 0 on a log scale is refused, the tf unchanged", "%s", msg);
    vsv_tf z;
    vsv_tf_parse(&z, "range -1 0\n", msg, sizeof msg);
    parse("log", "T", &c, msg);
    CHECK(vsv_tf_change_apply(&z, &c, msg, sizeof msg) == VSV_EINVAL && strstr(msg, "nothing above 0"),
          "--log of a range with nothing above 0 is refused", "%s", msg);
}

int main(void)
{
    test_parse();
    test_apply();
    return vsv_test_done();
}
