/* vsv_place.h — where the scene stands in an immersive display's room, and
 * how the user moves it there. Matrices are 4x4, OpenGL column order; the
 * scene's world is metres (x east, y north, z up and exaggerated: the box
 * of vsv_player_bounds), the room is the display's real-world frame
 * (FreeVR: feet, y up, the front wall towards -z, the floor at the room
 * box's lowest y), so north is -z and east +x.
 *
 * A placement (vsv_place_base) is relative to the room's box and floor,
 * never to where a tracked head happens to be; navigation (vsv_nav_*) is a
 * room-to-room matrix N applied after it: the scene stands at N * base. */
#ifndef VSV_PLACE_H
#define VSV_PLACE_H

enum {
    /* the domain on a virtual table: its largest horizontal extent 0.6 of
     * the room's smaller horizontal side, its box standing on a tabletop
     * 3 feet above the floor, centred across the room and 0.15 of the
     * room's depth in front of its centre */
    VSV_PLACE_TABLE = 0,
    /* standing inside the clouds: the box's bottom on the floor and its top
     * at the ceiling (one scale for every axis, so the horizontal scale is
     * true and the vertical that times the exaggeration), its centre over
     * the room's centre */
    VSV_PLACE_ROOM = 1
};

/* The tabletop's height above the floor (feet, as FreeVR's units). */
#define VSV_PLACE_TABLE_HEIGHT 3.0

/* The placement of the box mn..mx (world metres) in the room lo..hi. */
void vsv_place_base(int kind, const double room_lo[3], const double room_hi[3], const double mn[3], const double mx[3],
                    double M[16]);

/* N = the identity (where the placement put the scene). */
void vsv_nav_identity(double N[16]);
/* The user travels by d (room units): the scene moves by -d. */
void vsv_nav_travel(double N[16], const double d[3]);
/* The user turns by deg (counter-clockwise seen from above) about the
 * vertical through `about`: the scene turns by -deg. */
void vsv_nav_turn(double N[16], const double about[3], double deg);
/* The scene grows by f (> 0) about the room point `about`. */
void vsv_nav_scale(double N[16], const double about[3], double f);

/* out = a * b (either may be out). */
void vsv_mat4_mul(const double a[16], const double b[16], double out[16]);
/* The inverse of m; 0 when it is singular. */
int vsv_mat4_invert(const double m[16], double out[16]);
/* out = M p (a point). */
void vsv_mat4_point(const double M[16], const double p[3], double out[3]);

#endif
