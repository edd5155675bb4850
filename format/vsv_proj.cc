/* vsv_proj.cc — the thin C shim over GeographicLib's projections: turns a
 * projected (x, y) of a .vsv grid into latitude/longitude and back. The
 * projections are taken on a sphere (MM5, WRF and CAMx all assume one). */
#include "vsv_format.h"

#include <GeographicLib/AlbersEqualArea.hpp>
#include <GeographicLib/LambertConformalConic.hpp>
#include <GeographicLib/TransverseMercator.hpp>
#include <GeographicLib/PolarStereographic.hpp>
#include <cmath>
#include <exception>

using GeographicLib::AlbersEqualArea;
using GeographicLib::LambertConformalConic;
using GeographicLib::PolarStereographic;
using GeographicLib::TransverseMercator;

namespace
{

double radius_of(const vsv_proj *p) { return p->radius > 0 ? p->radius : 6370000.0; }

/* A conic (or, with one standard parallel at 0, Mercator) for p. */
LambertConformalConic conic(const vsv_proj *p)
{
    const double a = radius_of(p);
    if (p->kind == VSV_PROJ_MERCATOR)
        return LambertConformalConic(a, 0.0, 0.0, std::cos(p->lat1 * M_PI / 180.0));
    if (std::fabs(p->lat1 - p->lat2) < 1e-9)
        return LambertConformalConic(a, 0.0, p->lat1, 1.0);
    return LambertConformalConic(a, 0.0, p->lat1, p->lat2, 1.0);
}

bool north(const vsv_proj *p) { return (p->lat1 != 0 ? p->lat1 : p->lat0) >= 0; }

PolarStereographic stereo(const vsv_proj *p)
{
    const double s = std::sin(std::fabs(p->lat1 != 0 ? p->lat1 : 90.0) * M_PI / 180.0);
    return PolarStereographic(radius_of(p), 0.0, (1 + s) / 2);
}

AlbersEqualArea albers(const vsv_proj *p)
{
    if (std::fabs(p->lat1 - p->lat2) < 1e-9)
        return AlbersEqualArea(radius_of(p), 0.0, p->lat1, 1.0);
    return AlbersEqualArea(radius_of(p), 0.0, p->lat1, p->lat2, 1.0);
}

TransverseMercator tmerc(const vsv_proj *p)
{
    return TransverseMercator(radius_of(p), 0.0, p->lat1 > 0 ? p->lat1 : 1.0);
}

double wrap(double lon)
{
    lon = std::remainder(lon, 360.0);
    return lon == -180 ? 180 : lon;
}

} // namespace

extern "C" int vsv_proj_forward(const vsv_proj *p, double lat, double lon, double *x, double *y)
{
    try {
        double g, k, x0, y0, x1, y1;
        switch (p->kind) {
        case VSV_PROJ_LATLON:
            *x = lon;
            *y = lat;
            return 0;
        case VSV_PROJ_LCC:
        case VSV_PROJ_MERCATOR: {
            const LambertConformalConic c = conic(p);
            c.Forward(p->lon0, p->lat0, p->lon0, x0, y0, g, k);
            c.Forward(p->lon0, lat, lon, x1, y1, g, k);
            break;
        }
        case VSV_PROJ_PSTEREO: {
            const PolarStereographic s = stereo(p);
            s.Forward(north(p), p->lat0, 0.0, x0, y0, g, k);
            s.Forward(north(p), lat, wrap(lon - p->lon0), x1, y1, g, k);
            break;
        }
        case VSV_PROJ_TMERC: {
            const TransverseMercator t = tmerc(p);
            t.Forward(p->lon0, p->lat0, p->lon0, x0, y0, g, k);
            t.Forward(p->lon0, lat, lon, x1, y1, g, k);
            break;
        }
        case VSV_PROJ_ALBERS: {
            const AlbersEqualArea a = albers(p);
            a.Forward(p->lon0, p->lat0, p->lon0, x0, y0, g, k);
            a.Forward(p->lon0, lat, lon, x1, y1, g, k);
            break;
        }
        default: return VSV_EUNSUPPORTED;
        }
        *x = x1 - x0;
        *y = y1 - y0;
        return std::isfinite(*x) && std::isfinite(*y) ? 0 : VSV_ERANGE;
    } catch (const std::exception &) {
        return VSV_EINVAL;
    }
}

extern "C" int vsv_proj_inverse(const vsv_proj *p, double x, double y, double *lat, double *lon)
{
    try {
        double g, k, x0, y0;
        switch (p->kind) {
        case VSV_PROJ_LATLON:
            *lat = y;
            *lon = x;
            return 0;
        case VSV_PROJ_LCC:
        case VSV_PROJ_MERCATOR: {
            const LambertConformalConic c = conic(p);
            c.Forward(p->lon0, p->lat0, p->lon0, x0, y0, g, k);
            c.Reverse(p->lon0, x + x0, y + y0, *lat, *lon, g, k);
            break;
        }
        case VSV_PROJ_PSTEREO: {
            const PolarStereographic s = stereo(p);
            s.Forward(north(p), p->lat0, 0.0, x0, y0, g, k);
            s.Reverse(north(p), x + x0, y + y0, *lat, *lon, g, k);
            *lon = wrap(*lon + p->lon0);
            break;
        }
        case VSV_PROJ_TMERC: {
            const TransverseMercator t = tmerc(p);
            t.Forward(p->lon0, p->lat0, p->lon0, x0, y0, g, k);
            t.Reverse(p->lon0, x + x0, y + y0, *lat, *lon, g, k);
            break;
        }
        case VSV_PROJ_ALBERS: {
            const AlbersEqualArea a = albers(p);
            a.Forward(p->lon0, p->lat0, p->lon0, x0, y0, g, k);
            a.Reverse(p->lon0, x + x0, y + y0, *lat, *lon, g, k);
            break;
        }
        default: return VSV_EUNSUPPORTED;
        }
        return std::isfinite(*lat) && std::isfinite(*lon) ? 0 : VSV_ERANGE;
    } catch (const std::exception &) {
        return VSV_EINVAL;
    }
}
