/* vsv_wand.h — what a CAVE wand (three buttons and a joystick) and a
 * display's further switches do in Vesuvius, as a small state machine over
 * FreeVR's inputs (2switches 1..15, valuators 0 and 1): player actions in
 * vsv_player_do's language, and travel, turn, scale and reset of the
 * scene's placement (vsv_place.h). No FreeVR in it: tests drive it.
 *
 * A button's own action (its "click") fires when it is released, unless
 * the joystick or another button was used while it was held: holding a
 * button changes what the joystick does. The map is vsv_wand_help(). */
#ifndef VSV_WAND_H
#define VSV_WAND_H

#define VSV_WAND_SWITCHES 16
#define VSV_WAND_DEAD 0.15 /* joystick dead zone: continuous controls */
#define VSV_WAND_FLICK 0.8 /* a flick: past this, then back under 0.3 */
#define VSV_WAND_TURN 45.0 /* degrees a second at full deflection */
#define VSV_WAND_MAXACT 8

typedef struct vsv_wand_in {
    int sw[VSV_WAND_SWITCHES]; /* 2switch values (switch 0, quit, is not read) */
    float jx, jy;              /* the joystick, -1..1 (right, up) */
    double dt;                 /* seconds since the last update */
} vsv_wand_in;

typedef struct vsv_wand_out {
    const char *act[VSV_WAND_MAXACT]; /* player actions, in order (static strings) */
    int nact;
    double travel; /* room units to travel along the wand's pointing */
    double turn;   /* degrees to turn, counter-clockwise seen from above */
    double scale;  /* factor to grow the scene about the wand's tip (1: none) */
    int reset;     /* the scene back where its placement put it */
    int place;     /* switch the placement (table, room) */
    int seed;      /* a trajectory from the wand's tip */
} vsv_wand_out;

typedef struct vsv_wand {
    int held[VSV_WAND_SWITCHES], used[VSV_WAND_SWITCHES];
    int flick_x, flick_y; /* a flick in progress: its sign, until the stick returns */
    int chord;            /* buttons 1 and 2 down together, reset given */
    double speed;         /* travel: room units a second at full deflection */
} vsv_wand;

/* speed: travel at full deflection, room units a second. */
void vsv_wand_init(vsv_wand *w, double speed);
void vsv_wand_update(vsv_wand *w, const vsv_wand_in *in, vsv_wand_out *out);
/* The map, lines separated by '\n' (for --help and the man page). */
const char *vsv_wand_help(void);

#endif
