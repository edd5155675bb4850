/* vsv_python_names.c — the module's lookups by name: a projection's kind
 * and the words the CF export gives a species (no NumPy C API here: that
 * is vsv_python.c's, whose method table holds these). */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include "vsv_format.h"

#include <string.h>

PyObject *vsv_py_proj_kind(PyObject *mod, PyObject *arg);
PyObject *vsv_py_cf(PyObject *mod, PyObject *args);

/* _proj_kind(name) -> the VSV_PROJ_* kind, or -1 for a name of none
 * (vesuvius.write says which names there are). */
PyObject *vsv_py_proj_kind(PyObject *mod, PyObject *arg)
{
    (void)mod;
    const char *name = PyUnicode_AsUTF8(arg);
    if (!name)
        return NULL;
    for (int k = 0; k < VSV_PROJ_COUNT; k++)
        if (!strcmp(name, vsv_proj_name(k)))
            return PyLong_FromLong(k);
    return PyLong_FromLong(-1);
}

/* _cf(model, name, units) -> (UDUNITS units, standard_name or None,
 * comment or None): the export's words for a species (vsv_cf_names.c). */
PyObject *vsv_py_cf(PyObject *mod, PyObject *args)
{
    (void)mod;
    const char *model, *name, *units, *comment;
    if (!PyArg_ParseTuple(args, "sss", &model, &name, &units))
        return NULL;
    const char *sn = vsv_cf_standard_name(model, name, units, &comment);
    return Py_BuildValue("(szz)", vsv_cf_units(units), sn, comment);
}
