/* vsv_python_write.c — vesuvius.write's C core: the grid, species,
 * levels, terrain and heights into a vsv_meta, then the writer fed a step at
 * a time from the float32 arrays (the GIL let go while it encodes). The
 * NumPy C API is vsv_python.c's, shared through PY_ARRAY_UNIQUE_SYMBOL. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#define PY_ARRAY_UNIQUE_SYMBOL vsv_py_numpy_api
#define NO_IMPORT_ARRAY
#include <numpy/arrayobject.h>

#include "vsv_format.h"

#include <string.h>

PyObject *vsv_py_error(void);
PyObject *vsv_py_write(PyObject *mod, PyObject *args);

/* _write(path, grid, projection, times, names, units, descriptions, arrays,
 *        terrain, levels, heights, bits, scale): arrays are C-contiguous
 *        float32 (nt, nz, ny, nx); heights a list of (time, bytes of nz*ny*nx
 *        float32): each column's level heights from that time on. */
PyObject *vsv_py_write(PyObject *mod, PyObject *args)
{
    (void)mod;
    PyObject *pathobj, *grid, *proj, *times, *names, *units, *descs, *arrays, *terrain, *levels, *hts;
    int bits, scale;
    if (!PyArg_ParseTuple(args, "O&O!O!OO!O!O!O!OOO!ii", PyUnicode_FSConverter, &pathobj, &PyTuple_Type, &grid,
                          &PyTuple_Type, &proj, &times, &PyList_Type, &names, &PyList_Type, &units, &PyList_Type,
                          &descs, &PyList_Type, &arrays, &terrain, &levels, &PyList_Type, &hts, &bits, &scale))
        return NULL;
    vsv_meta m;
    vsv_meta_init(&m);
    vsv_writer *w = NULL;
    PyArrayObject *tarr = NULL;
    PyObject *result = NULL;
    const float **fields = NULL;
    vsv_pack_var *vars = NULL;
    int vk = 0;
    if (!PyArg_ParseTuple(grid, "iii(ddd)(ddd)i", &m.nx, &m.ny, &m.nz, &m.origin[0], &m.origin[1], &m.origin[2],
                          &m.spacing[0], &m.spacing[1], &m.spacing[2], &vk) ||
        !PyArg_ParseTuple(proj, "iddddd", &m.proj.kind, &m.proj.lat0, &m.proj.lon0, &m.proj.lat1, &m.proj.lat2,
                          &m.proj.radius))
        goto done;
    m.vert_kind = vk;
    snprintf(m.vert_units, sizeof m.vert_units, "%s", vk == VSV_VERT_INDEX ? "" : "m");
    snprintf(m.model, sizeof m.model, "Python");
    snprintf(m.run, sizeof m.run, "written by vesuvius.write");
    const Py_ssize_t nv = PyList_GET_SIZE(names);
    for (Py_ssize_t v = 0; v < nv; v++) {
        const char *n = PyUnicode_AsUTF8(PyList_GET_ITEM(names, v)), *u = PyUnicode_AsUTF8(PyList_GET_ITEM(units, v)),
                   *d = PyUnicode_AsUTF8(PyList_GET_ITEM(descs, v));
        if (!n || !u || !d)
            goto done;
        if (strlen(n) > 63 || strlen(u) > 63 || strlen(d) > 127) {
            PyErr_Format(vsv_py_error(),
                         "species '%s': names and units are at most 63 bytes, descriptions 127 (%zu, %zu, %zu)", n,
                         strlen(n), strlen(u), strlen(d));
            goto done;
        }
        if (vsv_meta_add_var(&m, n, u, d) < 0) {
            PyErr_Format(vsv_py_error(), "cannot add species '%s'", n);
            goto done;
        }
    }
    if (levels != Py_None) {
        PyArrayObject *la = (PyArrayObject *)PyArray_FROMANY(levels, NPY_FLOAT64, 1, 1, NPY_ARRAY_CARRAY);
        if (!la)
            goto done;
        if (PyArray_DIM(la, 0) != m.nz || vsv_meta_alloc_levels(&m)) {
            Py_DECREF(la);
            PyErr_SetString(vsv_py_error(), "levels: one height per level (nz)");
            goto done;
        }
        memcpy(m.levels, PyArray_DATA(la), (size_t)m.nz * sizeof(double));
        Py_DECREF(la);
    }
    if (terrain != Py_None) {
        PyArrayObject *ta =
            (PyArrayObject *)PyArray_FROMANY(terrain, NPY_FLOAT32, 2, 2, NPY_ARRAY_CARRAY | NPY_ARRAY_FORCECAST);
        if (!ta)
            goto done;
        if (PyArray_DIM(ta, 0) != m.ny || PyArray_DIM(ta, 1) != m.nx || vsv_meta_alloc_terrain(&m)) {
            Py_DECREF(ta);
            PyErr_SetString(vsv_py_error(), "terrain: an (ny, nx) array");
            goto done;
        }
        memcpy(m.terrain, PyArray_DATA(ta), (size_t)m.nx * m.ny * sizeof(float));
        Py_DECREF(ta);
    }
    for (Py_ssize_t i = 0; i < PyList_GET_SIZE(hts); i++) {
        long long ht;
        Py_buffer zb;
        if (!PyArg_ParseTuple(PyList_GET_ITEM(hts, i), "Ly*", &ht, &zb))
            goto done;
        const int bad = zb.len != (Py_ssize_t)((size_t)m.nx * m.ny * m.nz * sizeof(float)) ||
                        vsv_meta_add_heights(&m, ht, zb.buf, NULL, NULL);
        PyBuffer_Release(&zb);
        if (bad) {
            PyErr_SetString(vsv_py_error(), "heights: (times, nz, ny, nx) finite, increasing up every column");
            goto done;
        }
    }
    char msg[512];
    if (vsv_meta_validate(&m, msg, sizeof msg)) {
        PyErr_SetString(vsv_py_error(), msg);
        goto done;
    }
    tarr = (PyArrayObject *)PyArray_FROMANY(times, NPY_INT64, 1, 1, NPY_ARRAY_CARRAY);
    if (!tarr)
        goto done;
    const npy_intp nt = PyArray_DIM(tarr, 0);
    const size_t cells = (size_t)m.nx * m.ny * m.nz;
    for (Py_ssize_t v = 0; v < nv; v++) {
        PyArrayObject *a = (PyArrayObject *)PyList_GET_ITEM(arrays, v);
        if (!PyArray_Check(a) || PyArray_TYPE(a) != NPY_FLOAT32 || !PyArray_IS_C_CONTIGUOUS(a) ||
            PyArray_NDIM(a) != 4 || PyArray_DIM(a, 0) != nt || PyArray_DIM(a, 1) != m.nz || PyArray_DIM(a, 2) != m.ny ||
            PyArray_DIM(a, 3) != m.nx) {
            PyErr_Format(vsv_py_error(), "field '%s': expected float32 (%ld, %d, %d, %d) (times, nz, ny, nx)",
                         m.vars[v].name, (long)nt, m.nz, m.ny, m.nx);
            goto done;
        }
    }
    fields = PyMem_Calloc((size_t)nv + 1, sizeof *fields);
    vars = PyMem_Calloc((size_t)nv + 1, sizeof *vars);
    if (!fields || !vars) {
        PyErr_NoMemory();
        goto done;
    }
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    for (Py_ssize_t v = 0; v < nv; v++) {
        vsv_pack_var_init(&vars[v]);
        vars[v].bits = bits;
        vars[v].scale = scale;
    }
    o.vars = vars;
    const char *path = PyBytes_AS_STRING(pathobj);
    int rc = vsv_writer_create(path, &m, &o, &w);
    const int64_t *tv = PyArray_DATA(tarr);
    for (npy_intp t = 0; !rc && t < nt; t++) {
        for (Py_ssize_t v = 0; v < nv; v++)
            fields[v] = (const float *)PyArray_DATA((PyArrayObject *)PyList_GET_ITEM(arrays, v)) + (size_t)t * cells;
        Py_BEGIN_ALLOW_THREADS rc = vsv_writer_add_step(w, tv[t], fields);
        Py_END_ALLOW_THREADS
    }
    if (!rc) {
        Py_BEGIN_ALLOW_THREADS rc = vsv_writer_finish(w, NULL, NULL);
        Py_END_ALLOW_THREADS
    }
    if (rc) {
        PyErr_SetString(vsv_py_error(), w ? vsv_writer_error(w) : vsv_strerror(rc));
        goto done;
    }
    result = Py_None;
    Py_INCREF(result);
done:
    vsv_writer_free(w);
    PyMem_Free(fields);
    PyMem_Free(vars);
    Py_XDECREF(tarr);
    vsv_meta_clear(&m);
    Py_DECREF(pathobj);
    return result;
}
