/* vsv_render.h — the renderer interface (DESIGN.md §5): a camera, the
 * decoded volumes of the visible species with one transfer function and
 * opacity each, the terrain and a vertical exaggeration in; an RGBA float
 * image and a depth image out. Implementations sit behind vsv_renderer.
 *
 * Compositing rule, the same in every renderer: at each sample point every
 * visible species s turns its value into a colour c_s and an extinction
 * sigma_s (its transfer function's opacity curve times its opacity slider,
 * per horizontal cell size); the sample's extinction is sum(sigma_s) and its
 * colour sum(sigma_s * c_s) / sum(sigma_s); samples composite front to back
 * with alpha = 1 - exp(-sum(sigma_s) * step). The result does not depend on
 * the order of the species, and hiding a species (or opacity 0) is exactly
 * removing its term.
 *
 * Lighting (vsv_scene.light, off unless set), the same in every renderer:
 * each species' colour at a sample is multiplied by a factor from the
 * gradient of its value there (central differences one cell either way, on
 * ln value for a log-scale transfer function, in fractions of its range per
 * cell; the normal n points down the gradient, out of the cloud, in world
 * metres with z exaggerated): 1 - w + w (VSV_LIGHT_AMBIENT +
 * VSV_LIGHT_DIFFUSE max(0, n . L)), L toward the light, w = min(1, |gradient|
 * / VSV_LIGHT_GFULL). Extinction, so transmittance and depth, never change,
 * and where a value does not change the colour does not either. The
 * raycaster shades every sample, the shear-warp every voxel it classifies
 * (the light is fixed in the world, so a view change does not reclassify).
 *
 * Slices (vsv_scene.slices): horizontal planes and vertical curtains drawn
 * as opaque surfaces in the colours of one layer's values through
 * vsv_scene.slice_tf (values clamped into its range; no data and the part below the ground not drawn),
 * behind the volume in front of them and hiding what is behind, as the
 * ground does. Frames with slices are raycast whatever the renderer.
 *
 * Isosurfaces (vsv_scene.isos) and lines (vsv_scene.lines: trajectories,
 * wind arrows) are opaque surfaces too, lit, drawn the same way
 * (vsv_scene_iso, vsv_scene_line). */
#ifndef VSV_RENDER_H
#define VSV_RENDER_H

#include "vsv_format.h"

#ifdef __cplusplus
extern "C" {
#endif

VSV_API_BEGIN

/* ------------------------------------------------------ transfer functions */

#define VSV_TF_LUT 1024
#define VSV_TF_MAXPTS 16

/* One species' transfer function: plain info. */
typedef struct vsv_tf {
    char colormap[32]; /* viridis magma cividis clouds rain ice snow graupel greys */
    double lo, hi;     /* value range mapped to the colour map */
    int scale;         /* VSV_SCALE_LINEAR or VSV_SCALE_LOG */
    int nopacity;      /* opacity curve: samples evenly over [lo, hi] */
    float opacity[VSV_TF_MAXPTS];
    /* derived by vsv_tf_prepare: colour and extinction tables */
    float lut[VSV_TF_LUT][4];
    double base, inv; /* table position = (value or ln value - base) * inv */
} vsv_tf;

/* Names of the colour maps, NULL-terminated; borrowed, static. */
const char *const *vsv_tf_colormaps(void);
/* Parses a transfer function from text (SPEC.md §14: lines "colormap NAME",
 * "range LO HI", "scale linear|log", "opacity P0 P1 ..."; "kind" and unknown
 * keys are ignored). msg receives the reason on error (line number). */
int vsv_tf_parse(vsv_tf *tf, const char *text, char *msg, size_t cap);
/* Formats it back (the same keys); buf of cap bytes. */
void vsv_tf_format(const vsv_tf *tf, char *buf, size_t cap);
/* Builds the lookup tables after the fields were set. 0 or VSV_EINVAL. */
int vsv_tf_prepare(vsv_tf *tf);
/* Colour (rgb) and opacity-curve value of one data value (NaN: none). */
void vsv_tf_eval(const vsv_tf *tf, float value, float rgba[4]);

/* Loads a file of transfer functions: "species NAME" lines start a block for
 * that species; returns the block's text for `species`, or NULL. The text
 * is copied into buf (cap bytes). */
int vsv_tf_file_block(const char *path, const char *species, char *buf, size_t cap, char *msg, size_t msgcap);

/* The transfer function of species s: its block in tfpath (when given and
 * present), else the one stored in the file, else the default by kind; in
 * the last two cases a colour map an earlier species of the file shows is
 * swapped for the first of vsv_tf_colormaps none of them shows, so species
 * drawn together are told apart (the same in every tool).
 * 0, or an error with the reason in msg: VSV_EIO (msg names tfpath) or
 * VSV_EINVAL ("transfer function of NAME: why", from tfpath if given, else
 * from the file). */
int vsv_tf_for_species(const vsv_file *f, int s, const char *tfpath, vsv_tf *tf, char *msg, size_t cap);

/* One change to a species' transfer function from the command line, in
 * every renderer alike: --colormap SPECIES:NAME, --log SPECIES, --range
 * SPECIES:LO:HI (or SPECIES=LO:HI). Plain info. */
typedef struct vsv_tf_change {
    char species[64];
    char line[96]; /* a transfer-function line (SPEC.md §14) */
} vsv_tf_change;
/* Parses option opt ("colormap", "log" or "range") with its argument into
 * c. 0, or VSV_EINVAL with the reason in msg. */
int vsv_tf_change_parse(const char *opt, const char *arg, vsv_tf_change *c, char *msg, size_t cap);
/* Applies c to tf (the key it names changes, the rest stays) and prepares
 * it. A log scale over a range that starts at or below 0 starts 4 decades
 * below its top instead. 0, or VSV_EINVAL with the reason in msg. */
int vsv_tf_change_apply(vsv_tf *tf, const vsv_tf_change *c, char *msg, size_t cap);

/* ------------------------------------------------------------------ scene */

typedef struct vsv_camera {
    double pos[3];        /* world metres (z already exaggerated) */
    double dir[3], up[3]; /* view direction and up (need not be unit) */
    double fov_deg;       /* vertical field of view; 0 = orthographic */
    double ortho_height;  /* orthographic: world height of the image */
    double eye_offset;    /* stereo: shift along the camera's right axis */
    double znear, zfar;
    int width, height;
    /* off-axis perspective (a CAVE wall seen from a tracked head): the image's
     * left, right, bottom, top edges at unit distance along dir; all 0 = the
     * symmetric frustum of fov_deg */
    double window[4];
} vsv_camera;

typedef struct vsv_layer {
    const vsv_volume *vol;
    const vsv_tf *tf;
    float opacity; /* slider, 0..; 0 = hidden */
    int visible;
} vsv_layer;

/* The lighting rule's constants (top of this file). */
#define VSV_LIGHT_AMBIENT 0.35f
#define VSV_LIGHT_DIFFUSE 0.75f
#define VSV_LIGHT_GFULL 0.05f

/* A slice: plain info (vsv_slice_parse fills it). A horizontal plane at
 * height z (metres above sea level), or a vertical curtain standing on the
 * polyline of npts world points (x, y metres), from the ground to the top. */
enum { VSV_SLICE_Z = 0, VSV_SLICE_CURTAIN = 1 };
#define VSV_SLICE_MAXPTS 65
typedef struct vsv_slice {
    int kind;
    double z;
    int npts;
    double xy[VSV_SLICE_MAXPTS][2];
} vsv_slice;

/* The largest vertical exaggeration the tools take (a 16 km troposphere
 * as high as 16 000 km: far past any use). */
#define VSV_MAX_EXAGGERATION 1000
typedef struct vsv_scene {
    const vsv_meta *meta; /* grid, levels, terrain */
    const vsv_layer *layers;
    int nlayers;
    double exaggeration; /* vertical */
    int show_terrain;
    int light;               /* lighting (top of this file); 0: unlit */
    double light_dir[3];     /* toward the light, world axes (vsv_scene_sun) */
    const vsv_slice *slices; /* nslices of them, borrowed; coloured by */
    int nslices;
    int slice_layer;                  /* the layer (index in layers) whose values colour
                                         the slices; its volume must be loaded,
                                         visible or not */
    const vsv_tf *slice_tf;           /* the slices' colours: colour map, range and
                                       scale (NULL: the layer's transfer function) */
    const struct vsv_scene_iso *isos; /* nisos isosurfaces, borrowed */
    int nisos;
    const struct vsv_scene_line *lines; /* nlines lines, borrowed */
    int nlines;
} vsv_scene;

/* An isosurface drawn in a scene (vsv_scene.isos): the surface where layer
 * `layer`'s volume (loaded, visible or not) equals value, extracted as
 * vsv_iso_extract does (at the file's own per-column heights) and drawn
 * as an opaque surface in colour rgb (0..1, as given: gamma-encoded),
 * shaded by VSV_LIGHT_AMBIENT + VSV_LIGHT_DIFFUSE max(0, n . L) (at most
 * 1) with n its normal turned toward the eye and L the scene's light, or
 * the eye's direction when the scene is unlit. The volume in front of it
 * is composited over it and it hides what is behind, as the ground and
 * slices do. Frames with isosurfaces are raycast whatever the renderer
 * (the shear-warp composites whole slices and cannot stop at a surface
 * inside the volume); each renderer keeps the triangles of the bricks
 * that did not change from one step to the next. Plain info. */
#define VSV_SCENE_ISO_MAX 8
typedef struct vsv_scene_iso {
    int layer;
    float value;
    float rgb[3];
} vsv_scene_iso;

/* A line drawn in a scene (vsv_scene.lines): a polyline of npts points
 * (xyz: x, y world metres as the renderers place columns, vsv_scene_units;
 * z metres above sea level, not exaggerated, as isosurfaces' vertices)
 * drawn as a tube of `radius` world metres (round in the exaggerated
 * world: the same radius across and up) with VSV_TUBE_SIDES sides and
 * smooth normals, ending (with `arrow`) in a cone VSV_ARROW_LEN radii long
 * and VSV_ARROW_WIDTH radii wide at its base whose tip is the last point:
 * the direction of travel. The tube's first end is closed by a disc.
 * Opaque, in colour rgb (0..1, as given: gamma-encoded), shaded as
 * isosurfaces are; composited with the volumes, ground, slices and
 * isosurfaces as they are (frames with lines are raycast whatever the
 * renderer). Points closer than a thousandth of the radius to the one
 * before are skipped; a line of one point draws nothing. Plain info. */
#define VSV_TUBE_SIDES 8
#define VSV_ARROW_LEN 6
#define VSV_ARROW_WIDTH 2.5
typedef struct vsv_scene_line {
    const double *xyz; /* npts * 3 */
    int npts;
    double radius;
    int arrow;
    float rgb[3];
} vsv_scene_line;

/* Wind arrows on the horizontal plane at height z (metres, as the file's
 * heights: above sea level, or above the ground where
 * vsv_meta_above_ground): from the centre of every `every`-th column
 * (i and j multiples of every) where z lies between the column's lowest
 * and highest level and above its ground, an arrow along the wind there
 * (east, north: volumes of m's wind components at one step, m placed at
 * that step; linear in height within the column), as long as the air
 * goes in `seconds` seconds, turned onto the grid's axes by the
 * projection's Jacobian (vsv_proj_jacobian). Writes at most cap arrows:
 * xyz + 6 a holds arrow a's tail then its tip, in vsv_scene_line's
 * coordinates; *n the arrows written (calm columns included: tail ==
 * tip), *fastest the largest speed among them (m/s, horizontal). 0 or
 * VSV_EINVAL. */
int vsv_wind_arrows(const vsv_meta *m, const vsv_volume *east, const vsv_volume *north, double z, int every,
                    double seconds, double *xyz, int cap, int *n, double *fastest);

/* Lights the scene from a sun at azimuth az (degrees clockwise from north)
 * and elevation el (degrees). */
void vsv_scene_sun(vsv_scene *sc, double az, double el);
/* Parses a sun as the tools' --light=AZ,EL takes it (degrees; a finite
 * azimuth, -90 <= EL <= 90). 0, or VSV_EINVAL. */
int vsv_sun_parse(const char *spec, double *az, double *el);

/* Parses a slice: "z=HEIGHT" (metres above sea level; a trailing m allowed),
 * "lat=DEG" or "lon=DEG" (a curtain along that parallel or meridian across
 * the grid), "line=LAT1,LON1:LAT2,LON2" (a curtain on the straight line
 * between two points in the grid's projection). 0, or VSV_EINVAL with the
 * reason in msg (the grid's range when the slice misses it). */
int vsv_slice_parse(const vsv_meta *m, const char *spec, vsv_slice *s, char *msg, size_t cap);
/* The range of the values the scene's slices show (the slice layer's loaded
 * volume, sampled as they draw it: every column of a horizontal slice, a
 * cell's step along a curtain at every level; above the ground only): the
 * slices' own colour range. 0, or VSV_ERANGE when they show no data,
 * VSV_ENOMEM. */
int vsv_slice_range(const vsv_scene *sc, double *lo, double *hi);

/* World metres per unit of the file's x and y: 1 for projected grids; for a
 * latitude/longitude grid its degrees as metres on the sphere (plate
 * carree, true at the grid's middle latitude), so every grid is drawn in
 * metres. */
void vsv_scene_units(const vsv_meta *m, double *ux, double *uy);
/* Latitude/longitude of world (x, y) metres, and back. 0 or an error. */
int vsv_scene_latlon(const vsv_meta *m, double x, double y, double *lat, double *lon);
int vsv_scene_world(const vsv_meta *m, double lat, double lon, double *x, double *y);

/* World box of the scene (metres, z exaggerated): min[3], max[3]; of every
 * placement when the scene's grid moves (vsv_meta_span): cameras framed on
 * it hold still while a moving nest travels. Renderers take a scene whose
 * meta is placed at the time drawn (vsv_meta_placed). */
void vsv_scene_bounds(const vsv_scene *sc, double min[3], double max[3]);
/* A camera looking at the scene's centre from azimuth az (degrees clockwise
 * from north), elevation el (degrees), distance dist (world metres; 0 = frame
 * the whole box), perspective fov 35 degrees. */
void vsv_camera_orbit(vsv_camera *cam, const vsv_scene *sc, double az, double el, double dist, int width, int height);

/* The same from azimuth az and elevation el, placed so that the scene's box
 * fills the image: the eye as near as lets every corner in with a 4 %
 * margin, then turned to the middle of the corners' extent (which spans
 * over 92 % of the frame seen from a side, 86 % from the default oblique view:
 * tests/test_picture.c). */
void vsv_camera_fit(vsv_camera *cam, const vsv_scene *sc, double az, double el, int width, int height);
/* A map view: orthographic, looking straight down, north up, the domain
 * filling the image. */
void vsv_camera_plan(vsv_camera *cam, const vsv_scene *sc, int width, int height);
/* The same, the domain filling the image less the margins inset (pixels:
 * left, top, right, bottom), e.g. vsv_annotate_insets' for the legend. */
void vsv_camera_plan_inset(vsv_camera *cam, const vsv_scene *sc, int width, int height, const int inset[4]);
/* The views scientists use, by name: "plan" (1: vsv_camera_plan), "south"
 * and "west" (from 8 degrees up), "oblique" (azimuth 225, 30 degrees up)
 * (0: vsv_camera_fit from *az, *el). -1 for any other name. */
int vsv_view_preset(const char *name, double *az, double *el);

/* ---------------------------------------------------------------- renderer */

/* The GPU raycaster (VSV_RENDER_GL) is libvesuvius-gl's (render/gl/vsv_gl.h):
 * vsv_renderer_create refuses it (VSV_EUNSUPPORTED); programs that draw
 * with it name it here so that one setting says which renderer runs. */
enum { VSV_RENDER_RAYCAST = 0, VSV_RENDER_SHEARWARP = 1, VSV_RENDER_GL = 2 };

typedef struct vsv_render_opts {
    int kind;          /* VSV_RENDER_* */
    int threads;       /* 0 = all cores */
    double step_cells; /* sample step in horizontal cells (default 0.5) */
    int no_skip;       /* disable empty-space skipping (reference renders) */
    double term;       /* raycaster: a ray ends once its transmittance is
                          below this (0 or out of (0, 1): 1/512) */
} vsv_render_opts;

void vsv_render_opts_init(vsv_render_opts *o);

typedef struct vsv_renderer vsv_renderer;

/* Starts the threads. Caller frees with vsv_renderer_free. */
int vsv_renderer_create(const vsv_render_opts *o, vsv_renderer **out);
void vsv_renderer_free(vsv_renderer *r);
/* Renders into rgba (w*h*4 floats, premultiplied, row 0 at the top) and
 * depth (w*h floats: distance along the ray to the first opaque-enough point,
 * INFINITY where none); either may be NULL. The same pixels whatever the
 * thread count. The raycaster marches sixteen rays at once on CPUs with AVX2
 * and FMA, in one AVX-512 register where the CPU has AVX-512F (chosen when
 * the renderer is created; VSV_SIMD=0 in the environment keeps it to one ray
 * at a time, VSV_SIMD=avx2 to the AVX2 build), with the same pixels either
 * way; the shear-warp's parallel-ray compositing is built for any x86-64 and
 * for AVX2, FMA and F16C, chosen the same way (the two differ by rounding,
 * under 1e-5). */
int vsv_render(vsv_renderer *r, const vsv_scene *sc, const vsv_camera *cam, float *rgba, float *depth);
/* vsv_render's picture as premultiplied 8-bit RGBA (w*h*4 bytes, each
 * channel round(255 v), v clamped to [0, 1]: VolPack's and OpenGL's
 * convention), rgba not NULL. The shear-warp writes the bytes row by row
 * as it warps (the float picture never exists whole: a quarter of the
 * memory written); the raycaster converts its floats at the end. */
int vsv_render_rgba8(vsv_renderer *r, const vsv_scene *sc, const vsv_camera *cam, unsigned char *rgba, float *depth);

/* Seconds the last rebuild of precomputed state took, redone when the time
 * step changes. Shear-warp: classifying the species into the copy for one
 * principal viewing axis with its scanline footprints (also redone for an
 * axis's first view after a transfer function or an opacity changes; after
 * a new step only for the bricks whose values changed).
 * Raycaster: the sampling copies of the visible species (each brick with one
 * more cell along each axis, so a trilinear sample never straddles bricks:
 * 1.1 times the memory of the decoded volumes for bricks of 32). */
double vsv_renderer_rebuild_seconds(const vsv_renderer *r);
/* Shear-warp: how many bricks the last rebuild classified (all of them the
 * first time; after a new step only those whose values changed, as the
 * volumes' brick keys tell: vsv_volume.bkey). 0 for the raycaster. */
int vsv_renderer_rebuild_bricks(const vsv_renderer *r);

/* ---------------------------------------------------------------- marchers
 * What a renderer outside this library (the GPU raycaster, render/gl/)
 * needs to draw the CPU raycaster's picture by marching the same rays
 * through the same samples: the raycaster's frame as it works it out
 * before it marches, and its sampling copy of a brick. The rule the CPU
 * raycaster follows, to be followed by the marcher:
 *  - rays: pixel (px, py) (row 0 at the top) has screen position
 *    sx = px sxk + sx0, sy = py syk + sy0; in perspective its ray leaves o
 *    with a step dp = (sx r + (sy u + f)) / sqrt(sx^2 + (sy^2 + 1)), in
 *    parallel projection it leaves sx r + (sy u + o) with the step f; all
 *    in cell coordinates (cell (i, j, k) at its centre), a step st world
 *    units long; its stretch is where it is inside the box bmin..bmax and
 *    between snear and sfar steps, [lo, hi] in steps;
 *  - samples: at lo + 0.5 + n steps for every whole step, the last one in
 *    the middle of the part step left and weighted by its length (the
 *    stretch ends at hi, or at the surface its pixel meets); a sample's
 *    cell coordinates are clamped into 0..hi[a], its lower cell to at most
 *    last[a], and it reads the eight cells of that cell's brick's sampling
 *    copy (vsv_march_brick) trilinearly (lerps along x, then y, then z);
 *  - classification per layer: a value below lo (or NaN) adds nothing;
 *    else x = (log v or v) inv + off, clamped to at most VSV_TF_LUT - 1,
 *    i = min(floor x, VSV_TF_LUT - 2), and the colour and curve lerp entries
 *    i and i + 1 of lut by x - i; extinction = curve sigma; with light, the
 *    colour's weight is multiplied by the shading of vsv_render.h's rule,
 *    from central differences one cell either way;
 *  - compositing: per sample sig = the layers' summed extinction and col
 *    their extinction-weighted colour; u = sig st (the last: its part
 *    step), f = (1 - exp(-u)) / u, a = u f; acc += T f st col, T -= T a;
 *    the depth is the sample's distance at which 1 - T first passes 0.1; a
 *    ray ends once T < term;
 *  - the pixel: acc + T surface colour (alpha 1) where its ray met a surface
 *    and T >= term, else acc with alpha 1 - T; depth: the surface's where
 *    none was reached in the volume, else INFINITY. */
#define VSV_MARCH_MAX 64 /* layers marched at most */

/* Where a pixel's ray ends on a surface (the ground, a slice): distance
 * along the ray in world units (INFINITY: none) and the surface's colour. */
typedef struct vsv_surface {
    float t;
    float rgb[3];
} vsv_surface;

/* A visible layer as the raycaster classifies it. */
typedef struct vsv_march_layer {
    const vsv_volume *vol; /* the volume marched (native levels: resampled); borrowed */
    int layer;             /* its index among the scene's layers */
    const float (*lut)[4]; /* VSV_TF_LUT entries: colour, curve */
    float lo, inv, off;    /* table position = (ln v or v) inv + off; v < lo: nothing */
    int log;
    float sigma;    /* extinction per world unit of curve 1 */
    float inv_span; /* lighting: 1 / the range's span (of ln v on a log scale) */
} vsv_march_layer;

/* The raycaster's frame: plain info, valid until the renderer's next call. */
typedef struct vsv_march {
    int nlayers; /* 0: nothing to march (the surfaces only) */
    vsv_march_layer layer[VSV_MARCH_MAX];
    int n[3];                     /* the grid's cells per axis */
    float hi[3];                  /* the largest cell coordinate per axis */
    int last[3];                  /* the largest lower corner of a trilinear sample */
    int brick, shift, bdim[3];    /* bricks (their edge, log2 of it, per axis) */
    double st;                    /* the step, world units */
    float term;                   /* early ray termination: T below this */
    float o[3], f[3], r[3], u[3]; /* the rays (the rule above) */
    float sx0, sxk, sy0, syk;
    float bmin[3], bmax[3], snear, sfar;
    int persp;
    int light;          /* shading on */
    float light_dir[3]; /* unit, toward the light, world (exaggerated) axes */
    float inv_cell[3];  /* 1 / the world cell edges dx, dy, dz E */
    int width, height;
    int x0, x1, y0, y1;         /* the pixels whose rays may meet the scene's box */
    const vsv_surface *surface; /* width x height, row 0 at the top; NULL: none */
} vsv_march;

/* Works out the raycaster's frame for scene sc and camera cam into m, on
 * the renderer's threads (the ground is kept while the view stays; native
 * levels are resampled as vsv_render does). 0 or a VSV_E* code. */
int vsv_render_march(vsv_renderer *r, const vsv_scene *sc, const vsv_camera *cam, vsv_march *m);
/* Brick b's sampling copy: (brick + 1)^3 floats, cell (i, j, k) at
 * i + e j + e^2 k, e = brick + 1 (caller buffer): the brick and the first
 * cells of the bricks after it along each axis (past the grid, its last
 * cell again). */
void vsv_march_brick(const vsv_volume *v, int b, float *dst);
/* 1 when brick b's sampling copy holds only v->empty_value: the brick and
 * every brick whose cells it copies are EMPTY (NULL). */
int vsv_march_brick_empty(const vsv_volume *v, int b);
/* 1 when layer L makes every value in [lo, hi] transparent (the table
 * entries a sample of such a value reads have no opacity; NaN bounds:
 * none given); cnt: VSV_TF_LUT + 1 counts of entries with opacity before
 * each entry, from vsv_march_counts. */
void vsv_march_counts(const vsv_march_layer *L, int cnt[VSV_TF_LUT + 1]);
int vsv_march_clear(const vsv_march_layer *L, const int *cnt, float lo, float hi);

/* The vertical exaggeration that makes the domain a fifth as tall as wide
 * (at least 1, at most VSV_MAX_EXAGGERATION): the tools' default. */
double vsv_scene_default_exaggeration(const vsv_scene *sc);

/* ------------------------------------------------------------ isosurfaces
 * The surface where one species' value equals VALUE, as triangles per
 * brick: marching tetrahedra over the cell centres (each cube of eight
 * centres cut into the six tetrahedra around its diagonal from the lowest
 * corner to the highest, so no case is ambiguous and neighbouring cubes and
 * bricks cut their shared faces alike: no holes, no cracks, a closed
 * surface wherever it stays inside the grid). A point is above the surface
 * where its value is greater than VALUE; cubes with a NaN (no data) are
 * left out. Vertices lie in world metres: x, y as the renderers place
 * columns (vsv_scene_units; projected metres for a projected grid), z
 * metres above sea level not exaggerated, at each column's own heights
 * where the file has per-column native levels (a vertex on a vertical edge
 * lies at the height interpolated in its column), else on the renderers'
 * even axis (vsv_scene_geo). Triangles wind counter-clockwise seen from
 * their front, which faces the values below VALUE: out of a cloud. Normals
 * are unit, down the field's gradient (central differences between
 * neighbouring points, in world units), as the lighting rule's; where that
 * points against the vertex's triangles (across a layer a cell or two
 * thick the differences reach past it), their summed normal instead: all
 * of them, those of both bricks for a vertex on their common face, so the
 * two bricks' copies of it have one normal. (At a fold sharper than a
 * right angle a triangle can still face away from one of its corners'
 * normals.) Bricks none of whose points straddle
 * VALUE (the volumes' bmin/bmax of the brick and the next one along each
 * axis) are skipped; a brick whose values and neighbours' are unchanged
 * since the last extraction of the same value (the volumes' brick keys, or
 * the same volume) keeps its triangles. */

typedef struct vsv_iso vsv_iso;
/* An extractor with its own threads (0: all cores). Caller frees with
 * vsv_iso_free (NULL accepted). 0 or VSV_ENOMEM. */
int vsv_iso_create(int threads, vsv_iso **out);
void vsv_iso_free(vsv_iso *s);
/* Extracts the surface of value in v, a volume on m's grid (borrowed for
 * the call; m placed at v's time when the grid moves: vsv_meta_placed),
 * replacing the last one. 0, VSV_EINVAL (v not on m's grid, value not
 * finite) or VSV_ENOMEM. */
int vsv_iso_extract(vsv_iso *s, const vsv_meta *m, const vsv_volume *v, float value);
/* What the last extraction did: plain info. */
typedef struct vsv_iso_info {
    int nbricks; /* bricks of the volume */
    int visited; /* those whose values straddle VALUE */
    int reused;  /* of those, bricks whose triangles were kept */
    size_t nverts, ntris;
    double seconds; /* the extraction's wall time */
} vsv_iso_info;
void vsv_iso_get_info(const vsv_iso *s, vsv_iso_info *info);
/* One brick's triangles: plain info over the extractor's arrays, borrowed
 * until its next extraction or free. A vertex on a face two bricks share
 * appears in both, at the same position bit for bit. */
typedef struct vsv_iso_mesh {
    const float *pos;    /* nverts * 3: x, y, z world metres */
    const float *nrm;    /* nverts * 3: unit normals */
    const uint32_t *tri; /* ntris * 3 indices into pos */
    int nverts, ntris;
} vsv_iso_mesh;
/* Brick b's mesh (empty for a skipped brick). 0, or VSV_ERANGE for b out
 * of the last extraction's bricks. */
int vsv_iso_brick(const vsv_iso *s, int b, vsv_iso_mesh *mesh);

/* An isosurface as the tools' --iso takes it: plain info. */
typedef struct vsv_iso_spec {
    int species;  /* variable of the file */
    float value;  /* in the species' units */
    float rgb[3]; /* its colour, 0..1 (default white) */
} vsv_iso_spec;
/* Parses SPECIES:VALUE[:COLOUR] (COLOUR: white grey red orange yellow
 * green cyan blue purple, or #RRGGBB) against m's species. 0, or
 * VSV_EINVAL with the reason in msg (caller buffer of cap bytes; it names
 * the option and, for an unknown species, the file's). */
int vsv_iso_parse(const vsv_meta *m, const char *arg, vsv_iso_spec *spec, char *msg, size_t cap);
/* Parses --species NAME[:OPACITY],... against m's species (file: its name,
 * for messages): each named species' opacity (a finite number >= 0; 1
 * without one) into opac (caller array of m->nvars floats; the others
 * untouched). 0, or VSV_EINVAL (an empty name, a species the file lacks,
 * one named twice, a bad opacity) or VSV_ENOMEM with the reason in msg
 * (caller buffer of cap bytes). */
int vsv_species_parse(const vsv_meta *m, const char *list, const char *file, float *opac, char *msg, size_t cap);
/* Whether spec's value lies inside the range its species spans in f (the
 * values seen and the range coded): 0, or VSV_ERANGE with the reason in
 * msg (caller buffer of cap bytes), naming that range (a value no cell
 * reaches draws nothing: a wrong unit, most likely). arg: the option's
 * text, for the message. */
int vsv_iso_in_range(const vsv_file *f, const char *arg, const vsv_iso_spec *spec, char *msg, size_t cap);

/* The formats vsv_iso_write writes. */
enum { VSV_ISO_PLY = 0, VSV_ISO_GLTF = 1 };
/* Writes the last extraction of s as one mesh to path, through a temporary
 * renamed into place (vsv_output_*): all or nothing. PLY: binary little
 * endian, vertices x y z (float, world metres: x east, y north, z up, as
 * vsv_iso_extract places them) nx ny nz (float) red green blue (uchar,
 * rgb), faces as lists of three uint indices; comment lines hold title.
 * glTF 2.0 (.gltf): one JSON file, its buffer embedded as base64, one mesh
 * of POSITION and NORMAL (float VEC3, with POSITION's min and max) and
 * uint32 indices, a material of colour rgb; glTF's axes: +X east, +Y up,
 * +Z south (x, z, -y of the world), metres; title names the node. Bricks'
 * shared vertices appear once per brick. 0; VSV_ERANGE when s holds no
 * triangle; VSV_EIO ("path: cannot write: why") or VSV_ENOMEM with the
 * reason in msg (caller buffer of cap bytes). */
int vsv_iso_write(const vsv_iso *s, const char *path, int format, const float rgb[3], const char *title, char *msg,
                  size_t cap);

/* ------------------------------------------------------------- annotation */

/* A font for text drawn into frames (FreeType). */
typedef struct vsv_font vsv_font;
/* Loads the TrueType font at path (NULL or "": $VSV_FONT, else DejaVu Sans
 * of fonts-dejavu-core) at px pixels per em. Caller frees with
 * vsv_font_free. 0, or VSV_ENOTFOUND / VSV_EINVAL with the reason in err
 * (caller buffer of cap bytes). */
int vsv_font_open(const char *path, int px, vsv_font **out, char *err, size_t cap);
void vsv_font_free(vsv_font *f);
/* Pixels from one line of text to the next. */
int vsv_font_line(const vsv_font *f);
/* Width in pixels of one line of UTF-8 text. */
int vsv_text_width(vsv_font *f, const char *text);
/* Draws one line of UTF-8 text into rgba (w*h*4 floats, premultiplied, row
 * 0 at the top), its top-left corner at pixel (x, y), in colour rgb at
 * opacity alpha (0..1), blended over what is there; clipped to the image. */
void vsv_text_draw(vsv_font *f, float *rgba, int w, int h, int x, int y, const char *text, const float rgb[3],
                   float alpha);

/* Coast, lake and border lines under a grid (GSHHG, Debian's gmt-gshhg-low). */
typedef struct vsv_outlines vsv_outlines;
enum { VSV_OUTLINE_COAST = 1, VSV_OUTLINE_LAKE = 2, VSV_OUTLINE_BORDER = 3, VSV_OUTLINE_STATE = 4 };
/* The GSHHG resolution ('c' crude, 'l' low, 'i' intermediate) for a map of
 * km kilometres per pixel. */
char vsv_outlines_resolution(double km);
/* Reads the shorelines (coast; lakes with their islands and ponds) and the
 * national and state/province borders of the lat/lon box under m's grid
 * from the GSHHG binned netCDF files in dir (NULL or "": $VSV_GSHHG, else
 * /usr/share/gmt-gshhg) at resolution res, projected to world metres with
 * the grid's projection (vsv_scene_world). Caller frees with
 * vsv_outlines_free. 0; VSV_ENOTFOUND when the files are not there,
 * VSV_EUNSUPPORTED for a grid without a map projection, VSV_ECORRUPT or
 * VSV_ENOMEM; msg (cap bytes) says why. */
int vsv_outlines_load(const vsv_meta *m, const char *dir, char res, vsv_outlines **out, char *msg, size_t cap);
void vsv_outlines_free(vsv_outlines *o);
/* Number of polylines (0 for NULL), and polyline i: its kind
 * (VSV_OUTLINE_*) and n world (x, y) pairs, borrowed until the free. */
int vsv_outlines_count(const vsv_outlines *o);
const double *vsv_outlines_line(const vsv_outlines *o, int i, int *kind, int *n);

/* What vsv_annotate draws: bits of vsv_annot.parts. */
enum {
    VSV_ANNOT_TIME = 1,         /* model time (UTC, and the file's time zone) and the run */
    VSV_ANNOT_COLOURBAR = 2,    /* per visible species: name, units, colours over its range */
    VSV_ANNOT_EXAGGERATION = 4, /* "vertical xN" */
    VSV_ANNOT_SCALEBAR = 8,     /* kilometres at the ground under the image's centre */
    VSV_ANNOT_GRATICULE = 16,   /* latitude/longitude lines on the ground, labelled */
    VSV_ANNOT_OUTLINES = 32,    /* the outlines given, on the ground */
    VSV_ANNOT_ALL = 63
};

/* Parses a comma-separated list of parts, as the tools' --annotate takes
 * it: time, bars, exaggeration, scale, graticule, outlines, all. 0 with
 * *parts set, or VSV_EINVAL with the reason in msg (cap bytes). */
int vsv_annot_parse(const char *list, unsigned *parts, char *msg, size_t cap);
/* What annotating frames w x h of a grid m with these parts needs: the font
 * (DejaVu Sans at a fortieth of h, 11 to 32 pixels) for any part, and
 * the GSHHG outlines under the grid (at the resolution of a map span_m
 * metres across w pixels) when parts has VSV_ANNOT_OUTLINES. A part that
 * cannot be had is left out: *font or *outlines NULL, and note (cap bytes,
 * else "") says why in one line per part: a missing font or data set always,
 * a grid without a map projection only when notes_all. 0, or an error code
 * with the reason in note (a damaged data set). Caller frees with
 * vsv_font_free and vsv_outlines_free. */
int vsv_annot_load(const vsv_meta *m, unsigned parts, int w, int h, double span_m, int notes_all, vsv_font **font,
                   vsv_outlines **outlines, char *note, size_t cap);

/* Annotation of one frame: plain info, everything borrowed for the call. */
typedef struct vsv_annot {
    unsigned parts;               /* VSV_ANNOT_* */
    vsv_font *font;               /* NULL: the lines only, no text */
    int64_t time;                 /* the frame's model time */
    const char *source;           /* the file's name, shown with the run */
    const int *species;           /* per scene layer: its variable in the meta */
    const vsv_outlines *outlines; /* or NULL */
    /* or NULL: told of every box vsv_annotate draws (part: the VSV_ANNOT_*
     * it belongs to; box: pixels x0, y0, x1, y1), for tests and callers
     * that place more on the frame */
    void (*placed)(void *ctx, unsigned part, const int box[4]);
    void *placed_ctx;
} vsv_annot;

/* Draws the annotation into a frame rendered for (sc, cam): rgba as
 * vsv_render wrote it (cam->width x cam->height), depth its depth image or
 * NULL. Lines on the ground are hidden by the terrain in front of them and
 * dimmed behind clouds (depth); text and bars go on top. The colour bar of
 * each visible layer, and of the slices, shows its transfer function's
 * colours from lo to hi (evenly in value, or in log value on a log scale);
 * each isosurface of sc gets an entry below them ("NAME = VALUE (units),
 * isosurface" over a swatch of its colour), in the panel too.
 * 0, or VSV_ENOMEM. */
int vsv_annotate(const vsv_annot *a, const vsv_scene *sc, const vsv_camera *cam, float *rgba, const float *depth);
/* Where vsv_annotate draws the colour bar of layer l (l = sc->nlayers: the
 * slices' bar, of slice_tf, when the scene has slices): box = pixels x0,
 * x1 (lo to hi), y0, y1; for tests and callers that label it further. 0,
 * or VSV_ERANGE when there is no such bar. */
int vsv_annotate_bar_box(const vsv_annot *a, const vsv_scene *sc, const vsv_camera *cam, int l, int box[4]);
/* The margins (pixels: left, top, right, bottom) a plan view of frames w x
 * h leaves so that the annotation covers none of the map: the time block
 * in a band along the top, the colour bars and the scale in a column at
 * the right (where vsv_annotate puts them in a plan view). Zero where a's
 * parts draw none of them. */
void vsv_annotate_insets(const vsv_annot *a, const vsv_scene *sc, int w, int h, int inset[4]);

/* A legend panel (a display's information placed in its room, or any
 * caption): the time line as the annotation writes it (a->time: UTC, and
 * local time where the file has a zone), then `lines` ('\n' separated; may
 * be NULL), then a colour bar per visible layer of sc (and the slices')
 * with its name, units and range as vsv_annotate draws them, the bars as
 * wide as the panel, all in a->font (a->species maps layers to variables)
 * on a translucent dark box. vsv_legend_size gives the smallest w x h that
 * holds it; vsv_legend_draw fills rgba (w x h x 4 floats, premultiplied,
 * row 0 at the top), which it clears first. */
void vsv_legend_size(const vsv_annot *a, const vsv_scene *sc, const char *lines, int *w, int *h);
void vsv_legend_draw(const vsv_annot *a, const vsv_scene *sc, const char *lines, float *rgba, int w, int h);

/* ------------------------------------------------------------------ plots
 * Plots with axes, as NCL and GrADS users draw them (vsv-plot): a vertical
 * cross-section along a line (distance against height, one species in the
 * colours of a colour map, a colour bar), a time series at a point (one line
 * per species against time, a legend) and a profile (height against value),
 * each titled with its time, place, species and units, written as PNG, SVG
 * or PDF through cairo. The values drawn are the file's decoded values at
 * the nearest cells, located as vsv-query locates them (vsv_point_locate_at
 * at the step's time, vsv_query_sample nearest): a series' and a profile's
 * rows are vsv-query's. A section samples the straight line between its
 * ends in the grid's projection (as vsv_slice_parse's line=) every half
 * cell; each sample is the nearest column, its levels drawn from level to
 * level at that column's heights at the time (vsv_meta_cell_height_at: a
 * native level spans the midpoints to its neighbours, the lowest starts at
 * the ground), the ground grey under the terrain, and no data grey too. */
enum { VSV_PLOT_SECTION = 0, VSV_PLOT_SERIES = 1, VSV_PLOT_PROFILE = 2 };
#define VSV_PLOT_MAXSPECIES 8

/* What to plot: plain info; vsv_plot_opts_init sets the defaults. */
typedef struct vsv_plot_opts {
    int kind;                         /* VSV_PLOT_* */
    double lat[2], lon[2];            /* degrees: the section's two ends; a series' or profile's point is [0] */
    double at_height;                 /* series: metres above sea level (the grid's level unit when its
                                         levels are not heights); NaN (default): the lowest level above
                                         the ground, as vsv-query --at LAT,LON */
    int nspecies;                     /* 1..VSV_PLOT_MAXSPECIES (a section: 1) */
    int species[VSV_PLOT_MAXSPECIES]; /* variables of the file */
    int step0, step1;                 /* a section's and profile's step is step0; a series' step0..step1 */
    int size[2];                      /* width x height in pixels (PDF: points); default 800 x 600 */
    char colormap[32];                /* a vsv_tf_colormaps name; "" (default): viridis for a section,
                                         a qualitative palette for lines */
    int log;                          /* the values on a log scale (colour bar, or value axis) */
    double lo, hi;                    /* the values' range; NaN (default): the values drawn */
    double top;                       /* the height axis' top (as at_height); NaN: the model's top */
    const char *title;                /* NULL or "": made of the species and time (series: place) */
    const char *source;               /* the file's name, in the subtitle; NULL: none */
} vsv_plot_opts;

void vsv_plot_opts_init(vsv_plot_opts *o);

typedef struct vsv_plot vsv_plot;
/* Reads what o asks of f (through a vsv_query of its own; f is borrowed
 * for the call). Caller frees with vsv_plot_free. 0; VSV_ERANGE when a
 * point lies off the grid (msg names the grid's range, as vsv_point_locate
 * does) or there is nothing to put on a log scale; VSV_EINVAL for options
 * that do not fit together (msg says why); a reader's error (msg names the
 * file). msg: caller buffer of cap bytes. */
int vsv_plot_create(vsv_file *f, const vsv_plot_opts *o, vsv_plot **out, char *msg, size_t cap);
void vsv_plot_free(vsv_plot *p);
/* The formats, from an output name's extension (any case): .png, .svg,
 * .pdf. VSV_PLOT_PNG.. or -1 for another. */
enum { VSV_PLOT_PNG = 0, VSV_PLOT_SVG = 1, VSV_PLOT_PDF = 2 };
int vsv_plot_format(const char *path);
/* Draws p and writes it to path in the format of its extension, through a
 * temporary beside it renamed into place (vsv_output_*): all or nothing.
 * In SVG every text is a <text> element (class title, subtitle, xlabel,
 * ylabel, xtick, ytick, xdate, cbar-label, cbar-tick, legend), so scripts,
 * search and editors read it; PNG and PDF draw DejaVu Sans. 0; VSV_EINVAL
 * (another extension), VSV_EIO ("path: cannot write: why"), VSV_ENOMEM. */
int vsv_plot_write(const vsv_plot *p, const char *path, char *msg, size_t cap);
/* The values drawn, as CSV on fp: vsv-query --csv's columns (a section's
 * with "distance (km)" after the time), one row per time (series), level
 * (profile) or sample and level (section, along the line). 0 or VSV_EIO. */
int vsv_plot_csv(const vsv_plot *p, FILE *fp);
/* The value range drawn: the colour bar's ends, or the value axis'. */
void vsv_plot_range(const vsv_plot *p, double *lo, double *hi);

/* ------------------------------------------------------------------ files */

/* A rendered image (w*h*4 floats, premultiplied) over a background colour,
 * gamma 1/2.2, as 8-bit RGB (w*h*3 bytes, row 0 at the top). */
void vsv_image_rgb8(const float *rgba, int w, int h, const float bg[3], unsigned char *rgb);
/* Writes 8-bit RGB (row 0 at the top) as a PNG file, through a temporary
 * name renamed into place; 0, or -1 with the reason in err. */
int vsv_png_write(const char *path, const unsigned char *rgb, int w, int h, char *err, size_t cap);

/* Writes an OpenEXR image: R, G, B, A as half floats (premultiplied, row 0 at
 * the top) and Z (depth) as float; depth may not be NULL. Written to a
 * temporary name and renamed. 0, or -1 with err filled. */
int vsv_exr_write(const char *path, const float *rgba, const float *depth, int w, int h, char *err, size_t cap);

VSV_API_END

#ifdef __cplusplus
}
#endif
#endif
