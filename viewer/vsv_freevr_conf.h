/* vsv_freevr_conf.h — how many windows and render processes a FreeVR
 * configuration asks for, read from the texts FreeVR itself reads
 * ($FREEVR_HOME/.freevrrc, $HOME/.freevrrc, ./.freevrrc, the FREEVR
 * variable, then each command-line string), so that the FreeVR back end can
 * size the shared arena (FreeVR takes its own per-window state from it) and
 * split the brick cache between the render processes before vrConfigure.
 *
 * and where their walls stand (the room the model is placed in, and how
 * many pixels a foot of wall gets: the in-room panel's text size).
 *
 * It understands the statements that decide these (FreeVR's syntax,
 * ../shared/docs/FREEVR.md): `usesystem "S";`, `system "S" = { procs = ...; }`,
 * `process "P" = { type = visren; objects = "W", ...; }` and
 * `window "W" = { mount = "fixed"; args = "geometry=WxH+X+Y; ..."; rw2w_coords = ...; }`,
 * with `#` and `//` comments; every other statement is skipped. Later texts
 * override earlier definitions of the same name, as in FreeVR. */
#ifndef VSV_FREEVR_CONF_H
#define VSV_FREEVR_CONF_H

typedef struct vsv_freevr_layout {
    int windows;      /* windows the render processes open (>= 1) */
    int visren;       /* render processes (>= 1) */
    int explicit;     /* 1: counted from the system named by usesystem; 0: no
                         such system (FreeVR's simulator: 1 and 1), or an
                         upper bound from every window and process defined */
    char missing[64]; /* the system usesystem names when no text defines it
                         (FreeVR then opens its simulator with no input);
                         "" when it is defined, "simulator" or not named */
    /* the room: the box of the used system's fixed walls (mount "fixed",
     * rw2w_coords), in FreeVR's real-world feet (y up); FreeVR's default
     * 10-foot CAVE (-5..5, 0..10, -5..5) when there are none */
    double room_lo[3], room_hi[3];
    int walls;        /* fixed walls with corners in the used system */
    double px_per_ft; /* their lowest pixel density (window geometry over
                         the wall's size); 0 when none is known */
} vsv_freevr_layout;

/* Counts over n texts (NULL entries are skipped), in the order FreeVR reads
 * them. Never fails: what it cannot read counts as FreeVR's simulator. */
void vsv_freevr_layout_count(const char *const *texts, int n, vsv_freevr_layout *out);

/* The shared-arena size for a layout: FreeVR's own default (16 MiB) or, for
 * larger layouts, 1 MiB plus 256 KiB a window (FreeVR's own state was
 * measured at about 445 KB plus 75-80 KB a window: three times that), plus
 * `app` bytes the application allocates itself. */
unsigned long vsv_freevr_arena_bytes(const vsv_freevr_layout *l, unsigned long app);

#endif
