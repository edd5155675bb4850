/* vsv_player.h — what vsv-play does, whatever shows it: a file, its pager,
 * the playback clock, the species' visibility and opacity, the camera and a
 * renderer, driven by actions in one small language shared by the keyboard,
 * the wand and --script files:
 *
 *   play | pause | toggle-play | step [+N|-N] | seek ISO-TIME|INDEX
 *   speed X (negative plays backwards) | faster | slower | forward | rewind
 *   loop on|off|bounce | start | end
 *   toggle [SPECIES] | show [SPECIES] | hide [SPECIES] (default: the selected)
 *   opacity SPECIES|- VALUE|+D|-D ('-': the selected; signed: a change)
 *   select +1|-1|#INDEX|SPECIES | camera AZ EL [DIST] | orbit DAZ DEL | zoom FACTOR
 *   pan DX DY (fractions of the view) | renderer raycast|shearwarp|gl|switch
 *   view plan|south|west|oblique (vsv-render's --view, the domain filling
 *   the view) | light [on|off] | slices [on|off] | wind [on|off] (the
 *   trajectories and wind arrows; no argument: switch)
 *   trajectory LAT LON HEIGHT (a path from there, from the step shown)
 *   help | screenshot FILE.png | quit
 *
 * Display back ends (viewer/vsv-play.c: GLFW; viewer/vsv-play-freevr.c: FreeVR)
 * own the window and call update, then render for each eye's camera, then
 * draw the image on a billboard (vsv_billboard.h). */
#ifndef VSV_PLAYER_H
#define VSV_PLAYER_H

#include "vsv_clock.h"
#include "vsv_gl.h"
#include "vsv_pager.h"
#include "vsv_http.h"
#include "vsv_render.h"
#include "vsv_flow.h"

#include <stddef.h>

/* How many --colormap, --log and --range options a player takes. */
#define VSV_PLAYER_MAX_TF_CHANGES 16
/* Their help, the same in vsv-play and vsv-play-freevr (and vsv-render). */
#define VSV_PLAYER_TF_HELP                                                                                             \
    "      --colormap SPECIES:NAME  its colour map: viridis, magma, cividis, inferno,\n"                               \
    "                          plasma (perceptually uniform, matplotlib's), clouds,\n"                                 \
    "                          rain, ice, snow, graupel, greys\n"                                                      \
    "      --log SPECIES       its colours on a log scale (over its range; a range\n"                                  \
    "                          from 0 starts 4 decades below its top)\n"                                               \
    "      --range SPECIES:LO:HI  the values its colours span (also SPECIES=LO:HI)\n"                                  \
    "                          (these repeat, per species, in the order given)\n"

/* The --iso option's help, the same in vsv-play and vsv-play-freevr. */
#define VSV_PLAYER_ISO_HELP                                                                                            \
    "      --iso S:V[:COLOUR]  an opaque, lit isosurface where species S equals V, at\n"                               \
    "                          the model's own heights (COLOUR: white grey red orange\n"                               \
    "                          yellow green cyan blue purple #RRGGBB); repeatable (8)\n"

/* The wind's options (vsv_flow.h), the same in vsv-play and vsv-play-freevr:
 * their help, and their getopt_long entries, all of value v (the name tells
 * them apart: vsv_player_option). */
#define VSV_PLAYER_FLOW_HELP                                                                                           \
    "      --trajectory LAT,LON,HEIGHT[:COLOUR]  the path of the air from there\n"                                     \
    "                          (HEIGHT in metres as the file's heights), drawn up to\n"                                \
    "                          the time shown as a lit tube with an arrowhead\n"                                       \
    "      --seed-line LAT,LON,H:LAT,LON,H:N[:COLOUR]  N paths along a line\n"                                         \
    "      --seed-slice HEIGHT:EVERY[:COLOUR]  a path from every EVERY-th column\n"                                    \
    "      --traj-from T       the air leaves at step or time T (default: the first)\n"                                \
    "      --traj-for DURATION  followed so long (1h30m; default: to the last step)\n"                                 \
    "      --streamlines       streamlines of the wind shown, held still, drawn whole\n"                               \
    "      --barbs HEIGHT[:EVERY]  wind arrows on a horizontal plane (20 m/s spans\n"                                  \
    "                          EVERY columns)\n"                                                                       \
    "      --tube-radius M     the tubes' radius in metres (default: 1/300 of the domain)\n"
#define VSV_PLAYER_FLOW_LONGOPTS(v)                                                                                    \
    {"trajectory", required_argument, 0, (v)}, {"seed-line", required_argument, 0, (v)},                               \
        {"seed-slice", required_argument, 0, (v)}, {"traj-from", required_argument, 0, (v)},                           \
        {"traj-for", required_argument, 0, (v)}, {"barbs", required_argument, 0, (v)},                                 \
        {"streamlines", no_argument, 0, (v)},                                                                          \
    {                                                                                                                  \
        "tube-radius", required_argument, 0, (v)                                                                       \
    }

typedef struct vsv_player_opts {
    const char *path;          /* a .vsv file or an http(s):// URL */
    const vsv_http_opts *http; /* URLs: the cache and retries; NULL = the defaults */
    size_t cache_bytes;        /* 0 = the pager's default */
    int threads;               /* render threads; 0 = all cores */
    int renderer;              /* VSV_RENDER_* (-1, only with no_renderer: to be
                                  chosen where it draws); VSV_RENDER_GL: the GPU raycaster in
                                  the OpenGL context current when the player is
                                  opened and used (vsv_gl.h); opening fails with
                                  VSV_EUNSUPPORTED when it cannot be made */
    size_t gpu_budget;         /* its brick memory; 0 = its default */
    int no_renderer;           /* never draws: `renderer` is only named (the process
                                  that decodes for render processes, vsv_room.h) */
    int gl_by_caller;          /* with VSV_RENDER_GL: the caller draws with its own
                                  GPU raycaster per context (vsv_player_draw); the
                                  player makes none */
    const char *species; /* NAME[:OPACITY],... visible at start; NULL = all but water vapour (vsv_meta_default_shown) */
    const char *tfpath;  /* transfer functions file or NULL */
    vsv_tf_change tf_changes[VSV_PLAYER_MAX_TF_CHANGES]; /* --colormap, --log, --range */
    int ntf_changes;                              /* (vsv_player_tf_option), applied in order over each species' */
    double exaggerate;                            /* 0 = the default */
    double rate;                                  /* model seconds per wall second at x1; 0 = the default */
    int loop;                                     /* VSV_CLOCK_STOP / LOOP / BOUNCE */
    int play;                                     /* start playing */
    int terrain;                                  /* draw the ground */
    int clock_only;                               /* no pager, no renderer: the input process of a
                                                     multi-process back end (state and clock only) */
    int external;                                 /* the volumes come from elsewhere (vsv_player_show:
                                                     a render process of a multi-process back end,
                                                     vsv_room.h): no decoding, no pager threads */
    void *(*slab_alloc)(void *ctx, size_t bytes); /* the pager's brick memory */
    void *slab_ctx;                               /* (vsv_pager_opts.slab_alloc; NULL: the heap) */
    int light;                                    /* gradient shading at start */
    double sun_az, sun_el;                        /* its sun (degrees; default 315, 45) */
    const char *slices[8];                        /* --slice specs (vsv_slice_parse), shown at start */
    int nslices;
    const char *slice_species;           /* the slices' species (NULL: the first visible) */
    const char *slice_colormap;          /* their colour map (NULL: viridis) */
    double slice_range[2];               /* their colours' range fixed (NaN: the range of
                                            the values they show in the step shown,
                                            vsv_slice_range, as vsv-render) */
    const char *isos[VSV_SCENE_ISO_MAX]; /* --iso SPECIES:VALUE[:COLOUR] (vsv_player_iso_option),
                                            parsed against the file when opened */
    int nisos;
    vsv_flow_opts flow; /* --trajectory, --seed-line, --seed-slice, --traj-from,
                           --traj-for, --barbs, --tube-radius (vsv_flow_opt) */
} vsv_player_opts;

void vsv_player_opts_init(vsv_player_opts *o);

typedef struct vsv_player vsv_player;

/* Takes option opt ("colormap", "log" or "range") with its argument into
 * o->tf_changes. 0, or VSV_EINVAL with the reason in msg. */
int vsv_player_tf_option(vsv_player_opts *o, const char *opt, const char *arg, char *msg, size_t cap);
/* Takes option opt (its name without dashes: colormap, log, range, iso or
 * one of the wind's) with its argument into o. 0, or VSV_EINVAL with the
 * reason in msg. */
int vsv_player_option(vsv_player_opts *o, const char *opt, const char *arg, char *msg, size_t cap);
/* Takes an --iso argument into o->isos (checked against the file by
 * vsv_player_open, as vsv_iso_parse). 0, or VSV_EINVAL (too many) with the
 * reason in msg. */
int vsv_player_iso_option(vsv_player_opts *o, const char *arg, char *msg, size_t cap);
/* Opens the file and starts the pager and the renderer. 0; -1 with the
 * reason in err ("FILE: what"); or VSV_EINVAL when an option does not fit
 * the file (a species, slice, slice species, isosurface or colour map: misuse, as
 * vsv-render takes it), the reason in err; VSV_ERANGE for an isosurface
 * at a value the file never reaches ("FILE: --iso ...: no surface: ...").
 * On failure *out is NULL (what was made is freed). */
int vsv_player_open(const vsv_player_opts *o, vsv_player **out, char *err, size_t cap);
void vsv_player_free(vsv_player *p);

/* The action "trajectory LAT LON HEIGHT": a path added from there, leaving
 * at the step shown. 0, or -1 with the reason in err. */
int vsv_player_add_trajectory(vsv_player *p, const char *lat, const char *lon, const char *height, char *err,
                              size_t cap);
/* The same from projected (x, y) and height z (vsv_traj_run's seed); at
 * most VSV_PLAYER_MAX_SEEDS a run. */
int vsv_player_add_seed(vsv_player *p, const double seed[3], char *err, size_t cap);
/* The same from a point of the scene's world (metres, z exaggerated, as the
 * box of vsv_player_bounds): the wand's tip in vsv-play-freevr. */
int vsv_player_seed_world(vsv_player *p, const double world[3], char *err, size_t cap);

/* Runs one action (the language above). 0, or -1 with the reason in err. */
int vsv_player_do(vsv_player *p, const char *action, char *err, size_t cap);

/* Advances the clock by dt wall seconds and brings the shown step up to it:
 * the clock's step when decoded, else (while playing) the newest decoded
 * step between the one shown and it (counted as a stall). exact: wait until
 * the clock's step itself is shown (screenshots, paused seeks); for a URL,
 * never waiting: try it each call until it is (vsv_player_waiting). 0, or
 * -1 when a step cannot be decoded for another reason than damage or a
 * failed transfer (out of memory; vsv_player_error says why); nothing is
 * drawn from a step that failed. */
int vsv_player_update(vsv_player *p, double dt, int exact);
const char *vsv_player_error(const vsv_player *p);
/* A damaged step (a chunk or brick that fails its checks) is not an error
 * of update: it is shown as nothing (no species drawn), the status says so,
 * and playback goes on past it. This returns a step newly found damaged
 * since the last call (0-based) with the pager's message in *why (the file,
 * step, species, brick; owned by the player), or -1: a back end says it
 * once on stderr. */
int vsv_player_damage(vsv_player *p, const char **why);

/* A URL's steps come as the pager's workers fetch and decode them: the
 * player never waits for a server (update shows what is there; a stalled
 * server never freezes the caller's frame loop). This is the step update
 * could not show yet for want of its bricks (the clock's step in exact
 * mode), or -1 when none waits; with *why (may be NULL) NULL while it is
 * only loading, else the message of the transfer that failed for it
 * (owned by the player): not damage, it is tried again on a later frame. */
int vsv_player_waiting(const vsv_player *p, const char **why);
/* A step whose transfer newly failed (a server stalled or went away) since
 * the last call, once until a step shows again, with the message in *why
 * (owned by the player), or -1: a back end says it once on stderr. */
int vsv_player_stalled(vsv_player *p, const char **why);
/* The camera for a w x h view from the orbit state. */
void vsv_player_camera(const vsv_player *p, int w, int h, vsv_camera *cam);
/* Renders the scene for cam into 8-bit RGB over the background (w*h*3
 * bytes, row 0 at the top), re-rendering only when the camera, the step,
 * a species setting or the renderer changed. Returns the image (owned by
 * the player, valid until the next call) or NULL with the reason in err. */
const unsigned char *vsv_player_image(vsv_player *p, const vsv_camera *cam, char *err, size_t cap);
/* The frame vsv_player_image drew last, with the annotation parts
 * (VSV_ANNOT_*; 0: the bare frame) drawn in as vsv-render draws them: the
 * shown step's time, the file's name, a colour bar per visible species and
 * the slices', with font and outlines (borrowed for the call; either may be
 * NULL). 8-bit RGB of that frame's size, owned by the player, valid until
 * the next call; NULL with the reason in err. */
const unsigned char *vsv_player_annotated(vsv_player *p, unsigned parts, vsv_font *font, const vsv_outlines *outlines,
                                          char *err, size_t cap);
/* Renders exactly this frame again on the next vsv_player_image. */
void vsv_player_invalidate(vsv_player *p);

/* The on-screen lines: model time, step, play state, speed, ends and
 * renderer; then each species' visibility and opacity (the selected one in
 * brackets). Nothing in them moves with wall-clock time. */
void vsv_player_status(const vsv_player *p, char *buf, size_t cap);
/* The help text (keys and mouse), lines separated by '\n'. */
const char *vsv_player_help_text(void);

/* What the displays of a multi-process back end (FreeVR forks one render
 * process per window) need from the process that reads the input: plain
 * data, fit for shared memory. Species beyond the first 64 keep their
 * start settings. */
#define VSV_PLAYER_MAX_SPECIES 64
#define VSV_PLAYER_MAX_SEEDS 16
typedef struct vsv_player_state {
    double model, speed;
    int step, playing, ends, renderer, selected, help, light, slices, wind;
    int nseeds;                            /* the trajectories seeded while playing (vsv_player_add_seed), */
    double seeds[VSV_PLAYER_MAX_SEEDS][4]; /* in order: projected x, y, height, step */
    unsigned char visible[VSV_PLAYER_MAX_SPECIES];
    float opacity[VSV_PLAYER_MAX_SPECIES];
} vsv_player_state;
void vsv_player_state_get(const vsv_player *p, vsv_player_state *st);
/* Takes st over (the clock follows it; it does not tick by itself). 0 or -1
 * with the reason in err. */
int vsv_player_state_apply(vsv_player *p, const vsv_player_state *st, char *err, size_t cap);
/* Advances only the clock (the input process of a multi-process back end). */
void vsv_player_tick(vsv_player *p, double dt);

/* Immersive displays: the scene stands in the display's real-world
 * coordinates (FreeVR: feet, y up) as the matrix place (OpenGL column
 * order) maps world metres (x east, y north, z up, exaggerated) there; it
 * must scale every axis alike (a rotation, a uniform scale and a
 * translation: viewer/vsv_place.h makes them). From the projection P (a
 * glFrustum) and model-view MV (real world to eye) that the display loaded
 * for one eye, both in OpenGL column order, the camera that renders that
 * eye's view (off-axis frustum, w x h pixels). */
void vsv_player_camera_from_gl(const double place[16], const double P[16], const double MV[16], int w, int h,
                               vsv_camera *cam);

/* The GPU raycaster's picture for cam straight into the framebuffer bound
 * now, in viewport (x, y, w, h; cam w x h), by gl (the caller's, made in
 * the GL context current now: one per context, so a display that draws
 * several windows makes one for each): over the background, opaque,
 * nothing read back (displays that draw each eye themselves: FreeVR).
 * 0; VSV_EUNSUPPORTED when the renderer in use is not "gl"; else a VSV_E*
 * code with the reason in err. */
int vsv_player_draw(vsv_player *p, vsv_gl *gl, const vsv_camera *cam, const int viewport[4], char *err, size_t cap);
/* The renderer in use (VSV_RENDER_*). */
int vsv_player_renderer(const vsv_player *p);

/* A multi-process back end (vsv_room.h). The process that decodes: its
 * pager (borrowed), and what the step shown draws of species s (NULL: not
 * drawn) and why it is not drawn at all (damage; NULL when it is). */
vsv_pager *vsv_player_pager(vsv_player *p);
const vsv_volume *vsv_player_volume(const vsv_player *p, int s);
const char *vsv_player_shown_damage(const vsv_player *p);
/* A render process (opened with `external`): shows step with these
 * volumes (per species, NULL: none; borrowed until the next call or the
 * free) and damage (NULL, or why nothing is drawn), re-rendering on the next
 * vsv_player_image only when a volume's gen, the step or the damage
 * changed. */
void vsv_player_show(vsv_player *p, int step, const vsv_volume *const *vols, const char *damage);

/* State the back ends read. */
int vsv_player_quit(const vsv_player *p);
int vsv_player_help_shown(const vsv_player *p);
/* A screenshot asked for by an action: its path (then cleared), or NULL. */
const char *vsv_player_take_screenshot(vsv_player *p);
const vsv_clock *vsv_player_clock(const vsv_player *p);
/* The file's metadata, borrowed until vsv_player_free. */
const vsv_meta *vsv_player_meta(const vsv_player *p);
int vsv_player_shown_step(const vsv_player *p);
/* The step the player means to show now: the clock's, or when a frame spans
 * several steps the one of every k-th at or before it (vsv_clock_stride). */
int vsv_player_target_step(const vsv_player *p);
/* Wall seconds the last vsv_player_update waited for its step's bricks
 * (playing, a quarter of a frame at most; 0 when it did not wait). */
double vsv_player_waited(const vsv_player *p);
/* The time of step t (seconds since 1970, UTC); 0 outside the file. */
int64_t vsv_player_step_time(const vsv_player *p, int t);
void vsv_player_pager_stats(const vsv_player *p, vsv_pager_stats *st);
/* The scene as the player draws it now (layers, exaggeration, light,
 * slices; borrowed from the player until its next call). */
void vsv_player_scene(vsv_player *p, vsv_scene *sc);
/* The scene's centre and size (world metres), for billboards. */
void vsv_player_bounds(const vsv_player *p, double mn[3], double mx[3]);
const float *vsv_player_background(const vsv_player *p);

#endif
