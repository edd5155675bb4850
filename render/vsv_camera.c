/* vsv_camera.c — a scene's world geometry (box, cell centres, exaggeration)
 * and the cameras' rays: orbit cameras, the ray of each pixel, and the
 * pixels whose rays can meet the scene. */
#include "vsv_geo.h"

#include <math.h>
#include <string.h>

void vsv_scene_geo(const vsv_scene *sc, vsv_geo *g)
{
    const vsv_meta *m = sc->meta;
    g->nx = m->nx;
    g->ny = m->ny;
    g->nz = m->nz;
    /* world x, y in metres: projected metres, or for a latitude/longitude
     * grid degrees turned into metres on the sphere (plate carree, true at
     * the grid's middle latitude) */
    vsv_scene_units(m, &g->ux, &g->uy);
    g->ox = m->origin[0] * g->ux;
    g->oy = m->origin[1] * g->uy;
    g->dx = m->spacing[0] * g->ux;
    g->dy = m->spacing[1] * g->uy;
    g->idx = 1 / g->dx;
    g->idy = 1 / g->dy;
    /* renderers draw every grid with evenly stacked levels (DESIGN.md §3) */
    if (m->vert_kind == VSV_VERT_EVEN) {
        g->oz = m->origin[2];
        g->dz = m->spacing[2];
    } else if (m->vert_kind == VSV_VERT_NATIVE && m->nheights) {
        /* per-column heights: the even axis the volumes are resampled onto */
        vsv_heights_axis(m, &g->nz, &g->oz, &g->dz);
    } else if (m->vert_kind == VSV_VERT_NATIVE && m->levels && m->nz > 1) {
        g->oz = m->levels[0];
        g->dz = (m->levels[m->nz - 1] - m->levels[0]) / (m->nz - 1);
    } else {
        g->oz = 250;
        g->dz = 500;
    }
    g->E = sc->exaggeration > 0 ? sc->exaggeration : 1;
    g->bmin[0] = g->ox - g->dx / 2;
    g->bmax[0] = g->ox + (g->nx - 0.5) * g->dx;
    g->bmin[1] = g->oy - g->dy / 2;
    g->bmax[1] = g->oy + (g->ny - 0.5) * g->dy;
    g->bmin[2] = (g->oz - g->dz / 2) * g->E;
    g->bmax[2] = (g->oz + (g->nz - 0.5) * g->dz) * g->E;
    g->terrain =
        sc->show_terrain && (m->vert_kind == VSV_VERT_EVEN || m->vert_kind == VSV_VERT_NATIVE) ? m->terrain : NULL;
    g->water = g->terrain ? vsv_meta_water(m) : 0;
    g->landuse = g->water ? m->landuse : NULL;
    if (g->terrain) {
        /* the box reaches below the lowest ground, so rays meet the sea surface
         * inside it rather than on its face */
        float lowest = 0, highest = 0;
        for (size_t c = 0; c < (size_t)g->nx * g->ny; c++) {
            lowest = g->terrain[c] < lowest ? g->terrain[c] : lowest;
            highest = g->terrain[c] > highest ? g->terrain[c] : highest;
        }
        g->ground_top = highest * g->E;
        const double floor_z = (lowest - 10.0) * g->E;
        if (g->bmin[2] > floor_z)
            g->bmin[2] = floor_z;
    }
}

void vsv_scene_units(const vsv_meta *m, double *ux, double *uy)
{
    *ux = *uy = 1;
    if (m->proj.kind == VSV_PROJ_LATLON) {
        const double R = m->proj.radius > 0 ? m->proj.radius : 6370000.0;
        const double mid = m->origin[1] + 0.5 * (m->ny - 1) * m->spacing[1];
        *uy = R * M_PI / 180;
        *ux = *uy * fmax(cos(fmin(fabs(mid), 80.0) * M_PI / 180), 0.05);
    }
}

int vsv_scene_latlon(const vsv_meta *m, double x, double y, double *lat, double *lon)
{
    double ux, uy;
    vsv_scene_units(m, &ux, &uy);
    return vsv_proj_inverse(&m->proj, x / ux, y / uy, lat, lon);
}

int vsv_scene_world(const vsv_meta *m, double lat, double lon, double *x, double *y)
{
    double ux, uy;
    vsv_scene_units(m, &ux, &uy);
    const int rc = vsv_proj_forward(&m->proj, lat, lon, x, y);
    *x *= ux;
    *y *= uy;
    return rc;
}

void vsv_scene_bounds(const vsv_scene *sc, double mn[3], double mx[3])
{
    vsv_geo g;
    vsv_scene all = *sc; /* a moving nest: every place it stands */
    const vsv_meta span = vsv_meta_span(sc->meta);
    all.meta = &span;
    vsv_scene_geo(&all, &g);
    memcpy(mn, g.bmin, sizeof g.bmin);
    memcpy(mx, g.bmax, sizeof g.bmax);
}

void vsv_camera_orbit(vsv_camera *cam, const vsv_scene *sc, double az, double el, double dist, int width, int height)
{
    double mn[3], mx[3], c[3];
    vsv_scene_bounds(sc, mn, mx);
    for (int a = 0; a < 3; a++)
        c[a] = 0.5 * (mn[a] + mx[a]);
    c[2] = mn[2] + 0.3 * (mx[2] - mn[2]);
    memset(cam, 0, sizeof *cam);
    cam->fov_deg = 35;
    cam->width = width;
    cam->height = height;
    if (!(dist > 0)) {
        const double r = 0.5 * sqrt((mx[0] - mn[0]) * (mx[0] - mn[0]) + (mx[1] - mn[1]) * (mx[1] - mn[1]) +
                                    (mx[2] - mn[2]) * (mx[2] - mn[2]));
        dist = 1.15 * r / tan(cam->fov_deg * M_PI / 360);
    }
    const double a = az * M_PI / 180, e = el * M_PI / 180;
    /* azimuth clockwise from north (+y); the camera sits at that bearing from the centre */
    const double off[3] = {sin(a) * cos(e), cos(a) * cos(e), sin(e)};
    for (int i = 0; i < 3; i++) {
        cam->pos[i] = c[i] + dist * off[i];
        cam->dir[i] = -off[i];
    }
    cam->up[0] = cam->up[1] = 0;
    cam->up[2] = 1;
    cam->znear = 0;
    cam->zfar = INFINITY;
}

static void cross(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

void vsv_rays_init(vsv_rays *R, const vsv_camera *cam)
{
    double *f = R->f, *r = R->r, *u = R->u;
    for (int i = 0; i < 3; i++)
        f[i] = cam->dir[i];
    vsv_normalize(f);
    cross(f, cam->up, r);
    if (r[0] == 0 && r[1] == 0 && r[2] == 0) {
        const double alt[3] = {0, 1, 0};
        cross(f, alt, r);
    }
    vsv_normalize(r);
    cross(r, f, u);
    const double aspect = (double)cam->width / cam->height;
    for (int i = 0; i < 3; i++)
        R->o[i] = cam->pos[i] + cam->eye_offset * r[i];
    R->persp = cam->fov_deg > 0;
    const double t = R->persp ? tan(cam->fov_deg * M_PI / 360) : cam->ortho_height / 2;
    R->kx = t * aspect;
    R->ky = t;
    R->cx = R->cy = 0;
    if (R->persp && cam->window[0] != cam->window[1] && cam->window[2] != cam->window[3]) {
        R->kx = 0.5 * (cam->window[1] - cam->window[0]);
        R->cx = 0.5 * (cam->window[1] + cam->window[0]);
        R->ky = 0.5 * (cam->window[3] - cam->window[2]);
        R->cy = 0.5 * (cam->window[3] + cam->window[2]);
    }
    R->w = cam->width;
    R->h = cam->height;
    R->x0 = R->y0 = 0, R->x1 = cam->width - 1, R->y1 = cam->height - 1;
}

void vsv_rays_get(const vsv_rays *R, int px, int py, double o[3], double d[3])
{
    const double sx = R->cx + R->kx * (2 * (px + 0.5) / R->w - 1), sy = R->cy + R->ky * (1 - 2 * (py + 0.5) / R->h);
    if (R->persp) {
        for (int i = 0; i < 3; i++) {
            o[i] = R->o[i];
            d[i] = R->f[i] + sx * R->r[i] + sy * R->u[i];
        }
        vsv_normalize(d);
    } else {
        for (int i = 0; i < 3; i++) {
            o[i] = R->o[i] + sx * R->r[i] + sy * R->u[i];
            d[i] = R->f[i];
        }
    }
}

/* The pixels whose rays can meet the box [mn, mx]: the bounding rectangle
 * of its corners on the screen (a pixel of margin), or every pixel when a
 * corner is not in front of the eye. */
void vsv_rays_cull(vsv_rays *R, const double mn[3], const double mx[3])
{
    R->x0 = 0, R->x1 = (int)R->w - 1, R->y0 = 0, R->y1 = (int)R->h - 1;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int c = 0; c < 8; c++) {
        const double p[3] = {c & 1 ? mx[0] : mn[0], c & 2 ? mx[1] : mn[1], c & 4 ? mx[2] : mn[2]};
        double v[3], z = 0, s[2] = {0, 0};
        for (int i = 0; i < 3; i++) {
            v[i] = p[i] - R->o[i];
            z += v[i] * R->f[i];
            s[0] += v[i] * R->r[i];
            s[1] += v[i] * R->u[i];
        }
        if (R->persp) {
            if (!(z > 0))
                return;
            s[0] /= z, s[1] /= z;
        }
        /* the inverse of vsv_rays_get's screen position */
        const double px = ((s[0] - R->cx) / R->kx + 1) * R->w / 2 - 0.5,
                     py = (1 - (s[1] - R->cy) / R->ky) * R->h / 2 - 0.5;
        lo[0] = fmin(lo[0], px), hi[0] = fmax(hi[0], px);
        lo[1] = fmin(lo[1], py), hi[1] = fmax(hi[1], py);
    }
    if (!(hi[0] >= lo[0] && hi[1] >= lo[1]))
        return;
    R->x0 = lo[0] - 1 > 0 ? (int)(lo[0] - 1) : 0;
    R->y0 = lo[1] - 1 > 0 ? (int)(lo[1] - 1) : 0;
    R->x1 = hi[0] + 1 < R->w - 1 ? (int)ceil(hi[0] + 1) : (int)R->w - 1;
    R->y1 = hi[1] + 1 < R->h - 1 ? (int)ceil(hi[1] + 1) : (int)R->h - 1;
}

void vsv_pixel_ray(const vsv_camera *cam, int px, int py, double o[3], double d[3])
{
    vsv_rays R;
    vsv_rays_init(&R, cam);
    vsv_rays_get(&R, px, py, o, d);
}

void vsv_camera_fit(vsv_camera *cam, const vsv_scene *sc, double az, double el, int width, int height)
{
    vsv_camera_orbit(cam, sc, az, el, 1, width, height);
    double mn[3], mx[3], c[3], f[3], r[3], u[3];
    vsv_scene_bounds(sc, mn, mx);
    for (int a = 0; a < 3; a++) {
        c[a] = 0.5 * (mn[a] + mx[a]);
        f[a] = cam->dir[a];
    }
    vsv_normalize(f);
    cross(f, cam->up, r);
    vsv_normalize(r);
    cross(r, f, u);
    const double ky = tan(cam->fov_deg * M_PI / 360), kx = ky * width / height;
    /* the eye on the view axis through the box's centre, as near as lets
     * every corner of the box into the frame (with a 4 % margin); the
     * frame's centre then moves to the middle of the corners' extent */
    double dist = 0;
    for (int k = 0; k < 8; k++) {
        double p[3];
        for (int a = 0; a < 3; a++)
            p[a] = ((k >> a & 1) ? mx[a] : mn[a]) - c[a];
        const double pf = p[0] * f[0] + p[1] * f[1] + p[2] * f[2];
        const double pr = fabs(p[0] * r[0] + p[1] * r[1] + p[2] * r[2]);
        const double pu = fabs(p[0] * u[0] + p[1] * u[1] + p[2] * u[2]);
        const double need = fmax(pr * 1.04 / kx, pu * 1.04 / ky) - pf;
        dist = need > dist ? need : dist;
    }
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int k = 0; k < 8; k++) {
        double p[3];
        for (int a = 0; a < 3; a++)
            p[a] = ((k >> a & 1) ? mx[a] : mn[a]) - c[a];
        const double depth = dist + p[0] * f[0] + p[1] * f[1] + p[2] * f[2];
        const double sx = (p[0] * r[0] + p[1] * r[1] + p[2] * r[2]) / depth,
                     sy = (p[0] * u[0] + p[1] * u[1] + p[2] * u[2]) / depth;
        lo[0] = fmin(lo[0], sx), hi[0] = fmax(hi[0], sx);
        lo[1] = fmin(lo[1], sy), hi[1] = fmax(hi[1], sy);
    }
    /* a symmetric frustum aimed at the middle of that extent: turn the view */
    const double mxs = 0.5 * (lo[0] + hi[0]), mys = 0.5 * (lo[1] + hi[1]);
    for (int a = 0; a < 3; a++) {
        cam->pos[a] = c[a] - f[a] * dist;
        cam->dir[a] = f[a] + mxs * r[a] + mys * u[a];
    }
}

void vsv_camera_plan(vsv_camera *cam, const vsv_scene *sc, int width, int height)
{
    static const int none[4] = {0, 0, 0, 0};
    vsv_camera_plan_inset(cam, sc, width, height, none);
}

void vsv_camera_plan_inset(vsv_camera *cam, const vsv_scene *sc, int width, int height, const int inset[4])
{
    double mn[3], mx[3];
    vsv_scene_bounds(sc, mn, mx);
    memset(cam, 0, sizeof *cam);
    cam->width = width;
    cam->height = height;
    /* the free rectangle, at least a quarter of each side */
    const int fw = width - inset[0] - inset[2] > width / 4 ? width - inset[0] - inset[2] : width / 4;
    const int fh = height - inset[1] - inset[3] > height / 4 ? height - inset[1] - inset[3] : height / 4;
    const double w = mx[0] - mn[0], h = mx[1] - mn[1];
    const double per_px = fmax(h / fh, w / fw) * 1.02; /* metres a pixel */
    cam->ortho_height = per_px * height;
    /* the domain's centre at the free rectangle's: the eye off the image's */
    const double cx = inset[0] + 0.5 * fw - 0.5 * width, cy = inset[1] + 0.5 * fh - 0.5 * height;
    cam->pos[0] = 0.5 * (mn[0] + mx[0]) - cx * per_px;
    cam->pos[1] = 0.5 * (mn[1] + mx[1]) + cy * per_px;
    cam->pos[2] = mx[2] + 1000;
    cam->dir[2] = -1;
    cam->up[1] = 1;
    cam->znear = 0;
    cam->zfar = INFINITY;
}

int vsv_view_preset(const char *name, double *az, double *el)
{
    static const struct {
        const char *name;
        double az, el;
    } views[] = {{"plan", 0, 89.9}, {"south", 180, 8}, {"west", 270, 8}, {"oblique", 225, 30}};
    for (size_t i = 0; name && i < sizeof views / sizeof *views; i++)
        if (!strcmp(name, views[i].name)) {
            *az = views[i].az, *el = views[i].el;
            return i == 0;
        }
    return -1;
}
