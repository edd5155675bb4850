/* vsv_traj.h — trajectories through the time-varying wind a .vsv file
 * stores (the vector species "wind", vsv_vector.h): where air that passes a
 * point at one time came from or goes. Part of the public interface of
 * libvesuvius (include after vsv_format.h). */
#ifndef VSV_TRAJ_H
#define VSV_TRAJ_H

#include "vsv_format.h"

#ifdef __cplusplus
extern "C" {
#endif

VSV_API_BEGIN

/* One point of a path: plain info. */
typedef struct vsv_traj_point {
    double t;              /* seconds since 1970 (the file's calendar), fractional */
    double x, y;           /* projected position in the grid's projection (as GRID's origin) */
    double z;              /* height in the file's vertical datum: metres above sea level
                              (above the ground where vsv_meta_above_ground) */
    double lat, lon;       /* degrees */
    float east, north, up; /* the wind there and then, m/s */
} vsv_traj_point;

/* Why a path ended. */
enum {
    VSV_TRAJ_END_TIME = 0,   /* reached the time asked for */
    VSV_TRAJ_END_EDGE = 1,   /* left the grid sideways */
    VSV_TRAJ_END_GROUND = 2, /* met the ground */
    VSV_TRAJ_END_TOP = 3,    /* left through the top of the grid */
    VSV_TRAJ_END_DATA = 4,   /* the file's times (or its wind) ran out */
};

/* A path: plain info that owns its points; clear with vsv_traj_path_clear. */
typedef struct vsv_traj_path {
    int n; /* points, the seed first, in the order travelled */
    vsv_traj_point *pts;
    int end; /* VSV_TRAJ_END_* */
} vsv_traj_path;

typedef struct vsv_traj vsv_traj;

/* Trajectories through f's wind (f borrowed: it must outlive the handle).
 * One handle is used by one thread at a time; handles on one vsv_file may
 * run in parallel (the file's shareable calls only). VSV_ENOTFOUND when f
 * stores no wind, VSV_ENOMEM. */
int vsv_traj_create(vsv_file *f, vsv_traj **out);
void vsv_traj_free(vsv_traj *t);
/* Message for the last error of t ("where" included); borrowed. */
const char *vsv_traj_error(const vsv_traj *t);

/* Integrates the path of the air at projected (seed[0], seed[1]) and height
 * seed[2] (as vsv_traj_point.z) at time `from` until time `to` (to < from:
 * backward in time). The wind between the file's steps is linear in time,
 * in space trilinear between cell centres at the columns' own heights; the
 * scheme is RK4 with the step rule of vsv_traj.c (stated in its header and
 * the man page vsv-query(1)); a point is recorded every `every` seconds of
 * model time (0: every step of the scheme) and at the end. out is cleared
 * first. 0 (out->end says why it stopped: it may stop early), VSV_EINVAL
 * (seed outside the grid or below the ground, from outside the file's
 * times, non-finite), VSV_ENOMEM, or a read error of f (VSV_EIO,
 * VSV_ECORRUPT, VSV_ETRUNC). */
int vsv_traj_run(vsv_traj *t, const double seed[3], double from, double to, double every, vsv_traj_path *out);
void vsv_traj_path_clear(vsv_traj_path *p);
/* Streamlines: after this, t's paths follow the wind as it was at time `at`
 * (seconds, within the file's times), frozen: `from` and `to` of
 * vsv_traj_run then only measure the travel (its points' t is `from` plus
 * the seconds the air took at that wind), and the file's times do not end
 * a path (VSV_TRAJ_END_DATA only where the wind has no data). NAN: the wind
 * changes in time again (trajectories, the default). 0, or VSV_EINVAL (`at`
 * outside the file's times). */
int vsv_traj_freeze(vsv_traj *t, double at);

/* Seeds for vsv_traj_run, as projected (x, y) and height (caller buffer of
 * 3 * n doubles, x y z a seed). Along a line: n >= 1 seeds evenly spaced in
 * the grid's projection from end a to end b (each latitude, longitude in
 * degrees and height as vsv_traj_point.z; heights linear between them; one
 * seed: a). 0, VSV_EINVAL (n < 1, non-finite) or VSV_EUNSUPPORTED (a grid
 * without a projection). Nothing is checked against the grid: a seed
 * outside it is vsv_traj_run's VSV_EINVAL. */
int vsv_traj_seed_line(const vsv_meta *m, const double a[3], const double b[3], int n, double *seeds);
/* On a horizontal slice: the centres of every `every`-th column of m as it
 * lies at `time` (vsv_meta_placed) in x and y, starting at the middle of the
 * first interval (every / 2), at height z, leaving out the columns where z
 * is below the ground or outside the column's levels. Writes at most cap
 * seeds and returns how many there are (more than cap: only cap written;
 * seeds may be NULL with cap 0 to count), or VSV_EINVAL (every < 1, z not
 * finite). */
int vsv_traj_seed_plane(const vsv_meta *m, int64_t time, double z, int every, double *seeds, int cap);

VSV_API_END

#ifdef __cplusplus
}
#endif
#endif
