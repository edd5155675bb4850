/* vsv_python.c — the C core of the Python module `vesuvius`: a thin layer
 * over the public API of vsv_format.h (the reader, decoder, query and
 * writer) with NumPy arrays in and out. Volumes decode straight into the
 * array handed back (no copy beyond the decode); errors are vesuvius.Error
 * carrying the library's message. The friendly layer (namedtuples, xarray,
 * datetime64 conversions) is vesuvius/__init__.py. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#define PY_ARRAY_UNIQUE_SYMBOL vsv_py_numpy_api /* (vsv_python_write.c uses it too) */
#include <numpy/arrayobject.h>

#include "vsv_format.h"
#include "vsv_http.h"

#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <string.h>

static PyObject *VsvError;
PyObject *vsv_py_error(void);
PyObject *vsv_py_error(void) { return VsvError; }

/* A File may be used by several Python threads: reads decode without the
 * GIL, so the decoder and the query (state of their own) are used under
 * `busy`, which close() takes too (it waits for a read in progress). The
 * rule that keeps it free of deadlock: no thread waits for the GIL while it
 * holds `busy` (it is taken around library calls only, and a read lets it
 * go before it takes the GIL back). */
typedef struct {
    PyObject_HEAD vsv_file *f;
    vsv_decoder *d;
    vsv_query *q;
    vsv_file_info info;
    pthread_mutex_t busy;
} FileObject;

static PyObject *fail(const char *msg)
{
    PyErr_SetString(VsvError, msg);
    return NULL;
}

static int check_open(FileObject *self)
{
    if (!self->f) {
        PyErr_SetString(VsvError, "the file is closed");
        return -1;
    }
    return 0;
}

/* The metadata of an open file, or NULL with the exception set. */
static const vsv_meta *meta_of(FileObject *self) { return check_open(self) ? NULL : vsv_file_meta(self->f); }

static void File_dealloc(FileObject *self)
{
    vsv_query_free(self->q);
    vsv_decoder_free(self->d);
    vsv_file_free(self->f);
    pthread_mutex_destroy(&self->busy);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

static PyObject *File_close(FileObject *self, PyObject *unused)
{
    (void)unused;
    pthread_mutex_lock(&self->busy); /* a read in progress ends first */
    vsv_query_free(self->q);
    vsv_decoder_free(self->d);
    vsv_file_free(self->f);
    self->q = NULL;
    self->d = NULL;
    self->f = NULL;
    pthread_mutex_unlock(&self->busy);
    Py_RETURN_NONE;
}

/* A species by name or index; -1 with an exception set. */
static int species_of(FileObject *self, PyObject *o)
{
    const vsv_meta *m = vsv_file_meta(self->f);
    if (PyLong_Check(o)) {
        long s = PyLong_AsLong(o);
        if (s == -1 && PyErr_Occurred()) /* beyond a C long: out of range too */
            PyErr_Clear(), s = LONG_MIN;
        if (s < 0 || s >= m->nvars) {
            PyErr_Format(VsvError, "species %S out of range (0..%d)", o, m->nvars - 1);
            return -1;
        }
        return (int)s;
    }
    const char *name = PyUnicode_Check(o) ? PyUnicode_AsUTF8(o) : NULL;
    if (!name) {
        PyErr_SetString(PyExc_TypeError, "species: a name or an index");
        return -1;
    }
    const int s = vsv_meta_find_var(m, name);
    if (s < 0) {
        PyErr_Format(VsvError, "no species '%s' in the file", name);
        return -1;
    }
    return s;
}

/* A step from an index or a time string (the library's one time grammar:
 * an ISO time picks the nearest step). -1 with an exception set. */
static int step_of(FileObject *self, PyObject *o)
{
    const int n = self->info.nsteps;
    if (PyLong_Check(o)) {
        long t = PyLong_AsLong(o);
        if (t == -1 && PyErr_Occurred()) /* beyond a C long: out of range too */
            PyErr_Clear(), t = LONG_MIN;
        else if (t < 0)
            t += n;
        if (t < 0 || t >= n) {
            PyErr_Format(VsvError, "time step %S out of range (0..%d)", o, n - 1);
            return -1;
        }
        return (int)t;
    }
    const char *spec = PyUnicode_Check(o) ? PyUnicode_AsUTF8(o) : NULL;
    if (!spec) {
        PyErr_SetString(PyExc_TypeError, "time: a step index or an ISO time string");
        return -1;
    }
    int64_t *times = PyMem_Malloc((size_t)n * sizeof *times);
    if (!times)
        return (PyErr_NoMemory(), -1);
    for (int i = 0; i < n; i++)
        times[i] = vsv_file_time(self->f, i);
    vsv_timesel sel;
    char msg[400];
    const int rc =
        vsv_timesel_parse(spec, times, n, VSV_TIMESEL_ONE | VSV_TIMESEL_CAL(vsv_meta_calendar(vsv_file_meta(self->f))),
                          &sel, msg, sizeof msg);
    PyMem_Free(times);
    if (rc) {
        PyErr_Format(VsvError, "time %s: %s", spec, msg);
        return -1;
    }
    return sel.first;
}

static PyObject *File_read(FileObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"species", "time", NULL};
    PyObject *sp, *tm = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O|O", kwlist, &sp, &tm) || check_open(self))
        return NULL;
    const int s = species_of(self, sp);
    if (s < 0)
        return NULL;
    int t = 0;
    if (tm && (t = step_of(self, tm)) < 0)
        return NULL;
    const vsv_meta *m = vsv_file_meta(self->f);
    npy_intp dims[3] = {m->nz, m->ny, m->nx};
    PyArrayObject *a = (PyArrayObject *)PyArray_SimpleNew(3, dims, NPY_FLOAT32);
    if (!a)
        return NULL;
    int rc;
    char err[512];
    Py_BEGIN_ALLOW_THREADS pthread_mutex_lock(&self->busy);
    rc = self->d ? vsv_decoder_volume(self->d, t, s, (float *)PyArray_DATA(a)) : VSV_EINVAL;
    snprintf(err, sizeof err, "%s", self->d ? vsv_decoder_error(self->d) : "the file is closed");
    pthread_mutex_unlock(&self->busy);
    Py_END_ALLOW_THREADS if (rc)
    {
        Py_DECREF(a);
        return fail(err);
    }
    return (PyObject *)a;
}

static PyObject *File_read_brick(FileObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"species", "time", "brick", NULL};
    PyObject *sp, *tm;
    int b;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OOi", kwlist, &sp, &tm, &b) || check_open(self))
        return NULL;
    const int s = species_of(self, sp), t = s < 0 ? -1 : step_of(self, tm);
    if (t < 0)
        return NULL;
    if (b < 0 || b >= self->info.nbricks)
        return PyErr_Format(VsvError, "brick %d out of range (0..%d)", b, self->info.nbricks - 1);
    const int B = self->info.brick;
    npy_intp dims[3] = {B, B, B};
    PyArrayObject *a = (PyArrayObject *)PyArray_SimpleNew(3, dims, NPY_FLOAT32);
    if (!a)
        return NULL;
    char err[512];
    pthread_mutex_lock(&self->busy); /* (no read holds it waiting for the GIL) */
    const int rc = vsv_decoder_brick(self->d, t, s, b, (float *)PyArray_DATA(a));
    snprintf(err, sizeof err, "%s", vsv_decoder_error(self->d));
    pthread_mutex_unlock(&self->busy);
    if (rc) {
        Py_DECREF(a);
        return fail(err);
    }
    /* the caller keeps the cells inside the grid: [:ez, :ey, :ex] */
    int org[3], ext[3];
    vsv_file_brick_box(self->f, b, org, ext);
    return Py_BuildValue("(N(iii)(iii))", (PyObject *)a, org[2], org[1], org[0], ext[2], ext[1], ext[0]);
}

/* The (species, time, brick) arguments of brick_kind and brick_empty: 0,
 * or -1 with the exception set. */
static int brick_args(FileObject *self, PyObject *args, int *s, int *t, int *b)
{
    PyObject *sp, *tm;
    if (!PyArg_ParseTuple(args, "OOi", &sp, &tm, b) || check_open(self))
        return -1;
    *s = species_of(self, sp);
    *t = *s < 0 ? -1 : step_of(self, tm);
    if (*t < 0)
        return -1;
    if (*b < 0 || *b >= self->info.nbricks) {
        PyErr_Format(VsvError, "brick %d out of range (0..%d)", *b, self->info.nbricks - 1);
        return -1;
    }
    return 0;
}

static PyObject *File_brick_kind(FileObject *self, PyObject *args)
{
    int s, t, b;
    if (brick_args(self, args, &s, &t, &b))
        return NULL;
    const int k = vsv_file_brick_kind(self->f, t, s, b);
    if (k < 0)
        return fail(vsv_file_error(self->f));
    return PyLong_FromLong(k);
}

/* Whether brick b of (species, time) holds code 0 in every cell (its
 * octree node's largest code is 0), whatever its kind: an UNCHANGED brick
 * of an empty one, a delta to nothing. */
static PyObject *File_brick_empty(FileObject *self, PyObject *args)
{
    int s, t, b;
    if (brick_args(self, args, &s, &t, &b))
        return NULL;
    const unsigned char *oct = vsv_file_octree(self->f, t, s, NULL);
    if (!oct)
        return fail(vsv_file_error(self->f));
    unsigned mn, mx;
    vsv_octree_node(oct, (size_t)b, &mn, &mx);
    return PyBool_FromLong(mx == 0);
}

/* The values of species at a point, every step: (cell, lat, lon, height,
 * {name: float32 array over steps}). */
static PyObject *File_query(FileObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"lat", "lon", "height", "cell", "interp", NULL};
    double lat = NAN, lon = NAN;
    PyObject *hobj = Py_None, *cobj = Py_None;
    int interp = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "|ddOOp", kwlist, &lat, &lon, &hobj, &cobj, &interp) || check_open(self))
        return NULL;
    const vsv_meta *m = vsv_file_meta(self->f);
    vsv_point p;
    char msg[512];
    int rc, relocate = 0;
    double h = NAN;
    if (cobj != Py_None) {
        int i, j, k = -1;
        if (!PyArg_ParseTuple(cobj, "ii|i", &i, &j, &k))
            return NULL;
        rc = vsv_point_cell(m, i, j, k, &p, msg, sizeof msg);
    } else {
        if (isnan(lat) || isnan(lon))
            return PyErr_Format(PyExc_TypeError, "query: lat and lon, or cell=(i, j[, k])");
        h = hobj == Py_None ? NAN : PyFloat_AsDouble(hobj);
        if (PyErr_Occurred())
            return NULL;
        rc = vsv_point_locate_at(m, vsv_file_time(self->f, 0), lat, lon, h, &p, msg, sizeof msg);
        /* a moving nest may reach the point only later: its first step there */
        for (int t = 1; rc == VSV_ERANGE && m->nmoves && t < self->info.nsteps; t++)
            if (!vsv_point_locate_at(m, vsv_file_time(self->f, t), lat, lon, h, &p, NULL, 0))
                rc = 0;
        /* per-column heights move a height's level in time; a moving nest its cells */
        relocate = (!isnan(h) && m->nheights > 1) || m->nmoves;
    }
    if (rc)
        return fail(msg);
    PyObject *vals = PyDict_New();
    if (!vals)
        return NULL;
    npy_intp n = self->info.nsteps;
    for (int s = 0; s < m->nvars; s++) {
        PyArrayObject *a = (PyArrayObject *)PyArray_SimpleNew(1, &n, NPY_FLOAT32);
        if (!a) {
            Py_DECREF(vals);
            return NULL;
        }
        float *out = PyArray_DATA(a);
        for (int t = 0; t < n; t++) {
            vsv_point pt = p;
            const int lrc =
                relocate ? vsv_point_locate_at(m, vsv_file_time(self->f, t), lat, lon, h, &pt, msg, sizeof msg) : 0;
            out[t] = NAN; /* where a moving nest has left the point: no data */
            if (lrc == VSV_ERANGE && m->nmoves)
                continue;
            pthread_mutex_lock(&self->busy);
            const int qrc =
                lrc ? lrc
                    : vsv_query_sample(self->q, t, s, pt.pos, interp ? VSV_INTERP_LINEAR : VSV_INTERP_NEAREST, &out[t]);
            if (qrc && !lrc)
                snprintf(msg, sizeof msg, "%s", vsv_query_error(self->q));
            pthread_mutex_unlock(&self->busy);
            if (qrc) {
                Py_DECREF(a);
                Py_DECREF(vals);
                return fail(msg);
            }
        }
        PyDict_SetItemString(vals, m->vars[s].name, (PyObject *)a);
        Py_DECREF(a);
    }
    return Py_BuildValue("((iii)dddN(ddd))", p.cell[0], p.cell[1], p.cell[2], p.lat, p.lon, p.height, vals, p.pos[0],
                         p.pos[1], p.pos[2]);
}

static PyObject *File_times(FileObject *self, void *unused)
{
    (void)unused;
    if (check_open(self))
        return NULL;
    npy_intp n = self->info.nsteps;
    PyArrayObject *a = (PyArrayObject *)PyArray_SimpleNew(1, &n, NPY_INT64);
    if (!a)
        return NULL;
    int64_t *t = PyArray_DATA(a);
    for (npy_intp i = 0; i < n; i++)
        t[i] = vsv_file_time(self->f, (int)i);
    return (PyObject *)a;
}

/* One end of a species' range: a float, or None when the writer saw no
 * finite value (a new reference). */
static PyObject *range_end(int seen, double v) { return seen ? PyFloat_FromDouble(v) : (Py_INCREF(Py_None), Py_None); }

static PyObject *File_species(FileObject *self, void *unused)
{
    (void)unused;
    const vsv_meta *m = meta_of(self);
    if (!m)
        return NULL;
    PyObject *l = PyList_New(m->nvars);
    if (!l)
        return NULL;
    for (int s = 0; s < m->nvars; s++) {
        const vsv_quant *q = vsv_file_quant(self->f, s);
        /* no finite value seen (every cell no data): None, not inf and -inf */
        const int seen = q->data_min <= q->data_max;
        PyObject *o =
            Py_BuildValue("(sssdNNdiss)", m->vars[s].name, m->vars[s].units, m->vars[s].description, q->max_abs_error,
                          range_end(seen, q->data_min), range_end(seen, q->data_max), q->threshold, q->bits,
                          q->scale == VSV_SCALE_LOG ? "log" : "linear", q->missing ? "nan" : "zero");
        if (!o) {
            Py_DECREF(l);
            return NULL;
        }
        PyList_SET_ITEM(l, s, o);
    }
    return l;
}

static const char *vert_name(int k)
{
    static const char *const n[] = {"even", "native", "index", "coord"};
    return k >= 0 && k < 4 ? n[k] : "unknown";
}

static PyObject *File_grid(FileObject *self, void *unused)
{
    (void)unused;
    const vsv_meta *m = meta_of(self);
    if (!m)
        return NULL;
    PyObject *levels = Py_None;
    Py_INCREF(Py_None);
    if (m->levels) {
        Py_DECREF(Py_None);
        npy_intp n = m->nz;
        levels = PyArray_SimpleNew(1, &n, NPY_FLOAT64);
        if (!levels)
            return NULL;
        memcpy(PyArray_DATA((PyArrayObject *)levels), m->levels, (size_t)n * sizeof(double));
    }
    PyObject *moves = PyList_New(0); /* a moving nest's later placements: (time, x, y) */
    for (int i = 0; moves && i < m->nmoves; i++) {
        PyObject *mv =
            Py_BuildValue("(Ldd)", (long long)m->moves[i].time, m->moves[i].origin[0], m->moves[i].origin[1]);
        if (!mv || PyList_Append(moves, mv))
            Py_CLEAR(moves);
        Py_XDECREF(mv);
    }
    if (!moves) {
        Py_DECREF(levels);
        return NULL;
    }
    return Py_BuildValue("{s:i,s:i,s:i,s:(ddd),s:(ddd),s:s,s:s,s:s,s:N,s:N,s:s,s:s,s:s,s:i,s:i,s:N}", "nx", m->nx, "ny",
                         m->ny, "nz", m->nz, "origin", m->origin[0], m->origin[1], m->origin[2], "spacing",
                         m->spacing[0], m->spacing[1], m->spacing[2], "vertical", vert_name(m->vert_kind), "vert_units",
                         vsv_meta_height_units(m), "datum", vsv_meta_above_ground(m) ? "ground" : "sea level", "levels",
                         levels, "column_heights", PyBool_FromLong(m->nheights > 0), "calendar",
                         vsv_calendar_name(vsv_meta_calendar(m)), "model", m->model, "run", m->run, "brick",
                         self->info.brick, "nbricks", self->info.nbricks, "moves", moves);
}

static PyObject *File_projection(FileObject *self, void *unused)
{
    (void)unused;
    if (check_open(self))
        return NULL;
    const vsv_proj *p = &vsv_file_meta(self->f)->proj;
    return Py_BuildValue("{s:s,s:d,s:d,s:d,s:d,s:d}", "kind", vsv_proj_name(p->kind), "lat0", p->lat0, "lon0", p->lon0,
                         "lat1", p->lat1, "lat2", p->lat2, "radius", p->radius > 0 ? p->radius : 6370000.0);
}

/* lat (closure NULL) or lon (non-NULL) of every column: float64 (ny, nx). */
static PyObject *File_latlon(FileObject *self, void *lon)
{
    const vsv_meta *m = meta_of(self);
    if (!m)
        return NULL;
    npy_intp dims[2] = {m->ny, m->nx};
    PyArrayObject *a = (PyArrayObject *)PyArray_SimpleNew(2, dims, NPY_FLOAT64);
    if (!a)
        return NULL;
    double *o = PyArray_DATA(a);
    for (int j = 0; j < m->ny; j++)
        for (int i = 0; i < m->nx; i++) {
            double la = NAN, lo = NAN;
            if (vsv_meta_cell_latlon(m, i, j, &la, &lo))
                la = lo = NAN;
            o[(size_t)j * m->nx + i] = lon ? lo : la;
        }
    return (PyObject *)a;
}

/* Heights of the levels: (nz,) (the same in every column). */
static PyObject *File_height(FileObject *self, void *unused)
{
    (void)unused;
    const vsv_meta *m = meta_of(self);
    if (!m)
        return NULL;
    npy_intp n = m->nz;
    PyArrayObject *a = (PyArrayObject *)PyArray_SimpleNew(1, &n, NPY_FLOAT64);
    if (!a)
        return NULL;
    double *o = PyArray_DATA(a);
    for (int k = 0; k < m->nz; k++)
        o[k] = vsv_meta_cell_height(m, 0, 0, k);
    return (PyObject *)a;
}

/* Heights of every cell at a step: (nz, ny, nx), the file's per-column
 * heights where it has them, else each level's height in every column. */
static PyObject *File_heights(FileObject *self, PyObject *args)
{
    PyObject *tm;
    if (!PyArg_ParseTuple(args, "O", &tm) || check_open(self))
        return NULL;
    const int t = step_of(self, tm);
    if (t < 0)
        return NULL;
    const vsv_meta *m = vsv_file_meta(self->f);
    npy_intp dims[3] = {m->nz, m->ny, m->nx};
    PyArrayObject *a = (PyArrayObject *)PyArray_SimpleNew(3, dims, NPY_FLOAT64);
    if (!a)
        return NULL;
    double *o = PyArray_DATA(a);
    const int64_t time = vsv_file_time(self->f, t);
    for (int k = 0; k < m->nz; k++)
        for (int j = 0; j < m->ny; j++)
            for (int i = 0; i < m->nx; i++)
                *o++ = vsv_meta_cell_height_at(m, time, i, j, k);
    return (PyObject *)a;
}

static PyObject *File_terrain(FileObject *self, void *unused)
{
    (void)unused;
    const vsv_meta *m = meta_of(self);
    if (!m)
        return NULL;
    if (!m->terrain)
        Py_RETURN_NONE;
    npy_intp dims[2] = {m->ny, m->nx};
    PyArrayObject *a = (PyArrayObject *)PyArray_SimpleNew(2, dims, NPY_FLOAT32);
    if (a)
        memcpy(PyArray_DATA(a), m->terrain, (size_t)m->nx * m->ny * sizeof(float));
    return (PyObject *)a;
}

static PyObject *File_attrs(FileObject *self, void *unused)
{
    (void)unused;
    const vsv_meta *m = meta_of(self);
    if (!m)
        return NULL;
    PyObject *d = PyDict_New();
    for (int i = 0; d && i < m->nattrs; i++) {
        PyObject *v = PyUnicode_FromString(m->attr_values[i]);
        if (!v || PyDict_SetItemString(d, m->attr_keys[i], v)) {
            Py_XDECREF(v);
            Py_DECREF(d);
            return NULL;
        }
        Py_DECREF(v);
    }
    return d;
}

PyObject *vsv_py_trajectory(vsv_file *f, PyObject *args); /* vsv_python_traj.c */
static PyObject *File_traj(FileObject *s, PyObject *a) { return check_open(s) ? NULL : vsv_py_trajectory(s->f, a); }

static PyMethodDef File_methods[] = {
    {"read", (PyCFunction)(void (*)(void))File_read, METH_VARARGS | METH_KEYWORDS,
     "read(species, time=0) -> float32 array (nz, ny, nx): the decoded volume"},
    {"_read_brick", (PyCFunction)(void (*)(void))File_read_brick, METH_VARARGS | METH_KEYWORDS,
     "read_brick(species, time, brick) -> (float32 array (B, B, B), (k0, j0, i0), (ez, ey, ex))"},
    {"heights", (PyCFunction)File_heights, METH_VARARGS,
     "heights(time) -> float64 (nz, ny, nx): every cell's height at that step (per-column where the file has them)"},
    {"brick_kind", (PyCFunction)File_brick_kind, METH_VARARGS,
     "brick_kind(species, time, brick) -> 0 EMPTY .. 3 DELTA"},
    {"brick_empty", (PyCFunction)File_brick_empty, METH_VARARGS,
     "brick_empty(species, time, brick) -> True when every cell holds code 0 (nothing there)"},
    {"_query", (PyCFunction)(void (*)(void))File_query, METH_VARARGS | METH_KEYWORDS, "the point query core"},
    {"_trajectory", (PyCFunction)File_traj, METH_VARARGS, "the trajectory core (vsv_python_traj.c)"},
    {"close", (PyCFunction)File_close, METH_NOARGS, "close() releases the mapping"},
    {NULL, NULL, 0, NULL}};

static PyGetSetDef File_getset[] = {
    {"_times", (getter)File_times, NULL, "seconds since 1970 of each step", NULL},
    {"_species", (getter)File_species, NULL, "species tuples", NULL},
    {"grid", (getter)File_grid, NULL, "the grid: sizes, origin, spacing, vertical axis", NULL},
    {"projection", (getter)File_projection, NULL, "the map projection", NULL},
    {"lat", (getter)File_latlon, NULL, "latitude of every column's centre, (ny, nx)", NULL},
    {"lon", (getter)File_latlon, NULL, "longitude of every column's centre, (ny, nx)", (void *)"lon"},
    {"height", (getter)File_height, NULL, "height of every level's centre, (nz,)", NULL},
    {"terrain", (getter)File_terrain, NULL, "terrain height (ny, nx) or None", NULL},
    {"attrs", (getter)File_attrs, NULL, "run metadata", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PyTypeObject FileType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "vesuvius._vesuvius.File",
    .tp_basicsize = sizeof(FileObject),
    .tp_dealloc = (destructor)File_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE,
    .tp_doc = "An open .vsv file (memory-mapped).",
    .tp_methods = File_methods,
    .tp_getset = File_getset,
    .tp_new = PyType_GenericNew,
};

static PyObject *mod_open(PyObject *mod, PyObject *args)
{
    (void)mod;
    PyObject *pathobj;
    const char *cache_dir = NULL;
    if (!PyArg_ParseTuple(args, "O&|z", PyUnicode_FSConverter, &pathobj, &cache_dir))
        return NULL;
    FileObject *self = (FileObject *)PyObject_CallObject((PyObject *)&FileType, NULL);
    if (!self) {
        Py_DECREF(pathobj);
        return NULL;
    }
    pthread_mutex_init(&self->busy, NULL); /* (zeroed memory before: PTHREAD_MUTEX_INITIALIZER on glibc) */
    vsv_file *f = NULL;
    int rc;
    Py_BEGIN_ALLOW_THREADS vsv_http_opts http;
    vsv_http_opts_init(&http);
    http.cache_dir = cache_dir;
    rc = vsv_file_open_any(PyBytes_AS_STRING(pathobj), &http, &f);
    Py_END_ALLOW_THREADS if (rc)
    {
        PyErr_SetString(VsvError, f ? vsv_file_error(f) : vsv_strerror(rc));
        vsv_file_free(f);
        Py_DECREF(pathobj);
        Py_DECREF(self);
        return NULL;
    }
    Py_DECREF(pathobj);
    self->f = f;
    vsv_file_info_get(f, &self->info);
    if (vsv_decoder_create(f, &self->d) || vsv_query_create(f, &self->q)) {
        Py_DECREF(self);
        return PyErr_NoMemory();
    }
    return (PyObject *)self;
}

/* vsv_python_write.c: vesuvius.write's C core */
PyObject *vsv_py_write(PyObject *mod, PyObject *args);

/* vsv_python_names.c: a projection's kind by name, the CF export's words */
PyObject *vsv_py_proj_kind(PyObject *mod, PyObject *arg);
PyObject *vsv_py_cf(PyObject *mod, PyObject *args);

static PyMethodDef mod_methods[] = {
    {"_cf", vsv_py_cf, METH_VARARGS, "the CF export's units and standard name of a species"},
    {"open", mod_open, METH_VARARGS, "open(path[, cache_dir]) -> File"},
    {"_write", vsv_py_write, METH_VARARGS, "the writer core (see vesuvius.write)"},
    {"_proj_kind", vsv_py_proj_kind, METH_O, "projection kind of a name, or -1"},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef moddef = {
    PyModuleDef_HEAD_INIT, "_vesuvius", "The C core of vesuvius.", -1, mod_methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__vesuvius(void)
{
    import_array();
    if (PyType_Ready(&FileType) < 0)
        return NULL;
    PyObject *m = PyModule_Create(&moddef);
    if (!m)
        return NULL;
    VsvError = PyErr_NewExceptionWithDoc("vesuvius.Error", "An error of the Vesuvius library (its message says where).",
                                         NULL, NULL);
    Py_INCREF(&FileType);
    if (!VsvError || PyModule_AddObject(m, "Error", VsvError) || PyModule_AddObject(m, "File", (PyObject *)&FileType) ||
        PyModule_AddStringConstant(m, "version", VSV_VERSION_STRING)) {
        Py_DECREF(m);
        return NULL;
    }
    Py_INCREF(VsvError);
    return m;
}
