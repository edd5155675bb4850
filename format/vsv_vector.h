/* vsv_vector.h — vector species (the wind, stored as three species) and the
 * local geometry of a grid's projection that turns a vector between the
 * grid's axes and the earth's. Part of the public interface of vsv_format.h,
 * which includes it after vsv_meta. */
#ifndef VSV_VECTOR_H
#define VSV_VECTOR_H

#include "vsv_format.h"

#ifdef __cplusplus
extern "C" {
#endif

VSV_API_BEGIN

/* A vector species (SPEC.md §4 "Vectors", since 3.1): the attribute
 * "vector:NAME" lists, space-separated, the three species that hold its
 * earth-relative components, eastward, northward and upward, in that order;
 * or only the first two, a horizontal vector (a model without a vertical
 * wind: nothing is stored for it, never zeros). */
#define VSV_VECTOR_ATTR "vector:"
/* The wind: its species and its vector's name. */
#define VSV_WIND "wind"
#define VSV_WIND_EAST "wind_east"
#define VSV_WIND_NORTH "wind_north"
#define VSV_WIND_UP "wind_up"
/* What the model's winds were and how they were made earth-relative (free
 * text, written with the wind). */
#define VSV_WIND_SOURCE_ATTR "wind source"

/* The species of m's vector `name`: idx[0..2] east, north, up; idx[2] is -1
 * for a horizontal vector. 0, or VSV_ENOTFOUND when m has no such vector
 * (or a species it lists is not in m). */
int vsv_meta_vector(const vsv_meta *m, const char *name, int idx[3]);
/* 1 when species v of m is a component of one of its vectors, else 0. */
int vsv_meta_var_in_vector(const vsv_meta *m, int v);

/* The ground a step of one projected unit covers at projected point (x, y)
 * of p: along the grid's x axis, j[0][0] metres east and j[0][1] north;
 * along its y axis j[1][0] east and j[1][1] north. A grid-relative wind
 * (ug, vg), m/s along the grid's axes, is earth-relative (east, north) =
 * ug * j[0] / |j[0]| + vg * j[1] / |j[1]|; an earth-relative wind moves
 * the point by J^-1 (east, north) projected units a second. Projection
 * "none": x east and y north, metres. 0, or VSV_EINVAL / VSV_EUNSUPPORTED /
 * VSV_ERANGE as vsv_proj_inverse. */
int vsv_proj_jacobian(const vsv_proj *p, double x, double y, double j[2][2]);

VSV_API_END

#ifdef __cplusplus
}
#endif
#endif
