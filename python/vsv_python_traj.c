/* vsv_python_traj.c — File.trajectory's C core (vsv_traj.h): one path as
 * lists of numbers that vesuvius/__init__.py makes NumPy arrays of (no
 * NumPy C API here: that is vsv_python.c's, which calls this with the
 * File's open vsv_file). */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include "vsv_format.h"
#include "vsv_traj.h"

#include <stddef.h>
#include <string.h>

PyObject *vsv_py_trajectory(vsv_file *f, PyObject *args);

/* A time of f from a step index (int) or an ISO time (str) into *t: NULL
 * on success, else the reason (static or in msg). */
static const char *time_of(vsv_file *f, PyObject *o, double *t, char *msg, size_t cap)
{
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    if (PyLong_Check(o)) {
        const long s = PyLong_AsLong(o);
        if (s < 0 || s >= info.nsteps) {
            PyErr_Clear();
            snprintf(msg, cap, "step %ld is outside the file's steps 0..%d", s, info.nsteps - 1);
            return msg;
        }
        *t = (double)vsv_file_time(f, (int)s);
        return NULL;
    }
    const char *s = PyUnicode_Check(o) ? PyUnicode_AsUTF8(o) : NULL;
    int64_t v;
    if (!s || vsv_cal_parse(vsv_meta_calendar(vsv_file_meta(f)), s, &v)) {
        PyErr_Clear();
        return "a time is a step index or an ISO time (YYYY-MM-DDTHH:MM:SSZ)";
    }
    *t = (double)v;
    return NULL;
}

/* _trajectory(lat, lon, height, start, end, every) -> (dict of lists, end)
 * or the library's message (str): Python raises it as vesuvius.Error. */
PyObject *vsv_py_trajectory(vsv_file *f, PyObject *args)
{
    double lat, lon, h, every, from, to, seed[3];
    PyObject *a, *b;
    if (!PyArg_ParseTuple(args, "dddOOd", &lat, &lon, &h, &a, &b, &every))
        return NULL;
    char msg[512];
    const char *why = time_of(f, a, &from, msg, sizeof msg);
    if (!why)
        why = time_of(f, b, &to, msg, sizeof msg);
    if (why)
        return PyUnicode_FromString(why);
    const vsv_meta *m = vsv_file_meta(f);
    if (m->proj.kind == VSV_PROJ_NONE)
        return PyUnicode_FromString("the grid has no map projection: no latitude/longitude is known");
    if (vsv_proj_forward(&m->proj, lat, lon, &seed[0], &seed[1]))
        return PyUnicode_FromString("the latitude/longitude has no place in the grid's projection");
    seed[2] = h;
    vsv_traj *t = NULL;
    vsv_traj_path p = {0};
    int rc = vsv_traj_create(f, &t);
    if (!rc)
        rc = vsv_traj_run(t, seed, from, to, every, &p);
    if (rc) {
        PyObject *e = PyUnicode_FromString(
            rc == VSV_ENOTFOUND
                ? "no wind stored (convert from a file with U and V, without --no-winds, or with --winds FILE)"
                : vsv_traj_error(t));
        vsv_traj_free(t);
        return e;
    }
    vsv_traj_free(t);
    static const char *const names[] = {"seconds", "lat", "lon", "height", "x", "y", "east", "north", "up"};
    static const size_t offs[] = {
        offsetof(vsv_traj_point, t),    offsetof(vsv_traj_point, lat),   offsetof(vsv_traj_point, lon),
        offsetof(vsv_traj_point, z),    offsetof(vsv_traj_point, x),     offsetof(vsv_traj_point, y),
        offsetof(vsv_traj_point, east), offsetof(vsv_traj_point, north), offsetof(vsv_traj_point, up)};
    PyObject *d = PyDict_New();
    for (int c = 0; d && c < 9; c++) {
        PyObject *l = PyList_New(p.n);
        for (int i = 0; l && i < p.n; i++) {
            const char *q = (const char *)&p.pts[i] + offs[c];
            double v;
            if (c >= 6) { /* the wind is float */
                float fv;
                memcpy(&fv, q, sizeof fv);
                v = fv;
            } else {
                memcpy(&v, q, sizeof v);
            }
            PyObject *x = PyFloat_FromDouble(v);
            if (!x)
                Py_CLEAR(l);
            else
                PyList_SET_ITEM(l, i, x);
        }
        if (!l || PyDict_SetItemString(d, names[c], l))
            Py_CLEAR(d);
        Py_XDECREF(l);
    }
    static const char *const ends[] = {"time", "edge", "ground", "top", "data"};
    const int end = p.end;
    vsv_traj_path_clear(&p);
    return d ? Py_BuildValue("(Ns)", d, ends[end]) : NULL;
}
