/* _arrays.h: numpy arrays in and out of the package's extensions (_core.c, _par.c): borrowed
 * input data with its shape checked, and library buffers handed to numpy without a copy.
 * Include after <Python.h>, <numpy/arrayobject.h> and pcdm.h. */
#ifndef PCDM_PY_ARRAYS_H
#define PCDM_PY_ARRAYS_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ---- arrays ------------------------------------------------------------------------------ */

/* The data of o, a C-contiguous numpy array of type type with cols columns (cols 0: one
 * dimension), or NULL when o is None; *n gets its rows.  Sets a TypeError and returns NULL with
 * *bad = 1 otherwise (the Python half converts every input first, so this is a contract). */
static inline void *arr_data(PyObject *o, int type, int cols, const char *name, npy_intp *n,
                             int *bad) {
    *n = 0;
    if (o == Py_None) return NULL;
    if (!PyArray_Check(o) || PyArray_TYPE((PyArrayObject *)o) != type ||
        !PyArray_IS_C_CONTIGUOUS((PyArrayObject *)o) ||
        PyArray_NDIM((PyArrayObject *)o) != (cols ? 2 : 1) ||
        (cols && PyArray_DIM((PyArrayObject *)o, 1) != cols)) {
        PyErr_Format(PyExc_TypeError, "_core: %s: not a contiguous array of the expected type",
                     name);
        *bad = 1;
        return NULL;
    }
    *n = PyArray_DIM((PyArrayObject *)o, 0);
    return PyArray_DATA((PyArrayObject *)o);
}

/* in from the input arrays as the Python half passes them (vertices, vertex_markers,
 * vertex_attributes, segments, segment_markers, holes, regions; None where absent), the data
 * borrowed from them.  0, or -1 with an exception set (who names the module in it). */
static inline int arr_input(PyObject *ov, PyObject *ovm, PyObject *ova, PyObject *os, PyObject *osm,
                            PyObject *oh, PyObject *orr, const char *who, pcdm_input *in) {
    int bad = 0;
    npy_intp nv, nvm, nva = 0, ns, nsm, nh, nr;
    memset(in, 0, sizeof *in);
    in->points = arr_data(ov, NPY_DOUBLE, 2, "vertices", &nv, &bad);
    in->pointmarkers = arr_data(ovm, NPY_INT32, 0, "vertex_markers", &nvm, &bad);
    int k = 0;
    if (ova != Py_None && PyArray_Check(ova) && PyArray_NDIM((PyArrayObject *)ova) == 2)
        k = (int)PyArray_DIM((PyArrayObject *)ova, 1);
    in->pointattr = k ? arr_data(ova, NPY_DOUBLE, k, "vertex_attributes", &nva, &bad) : NULL;
    in->segments = arr_data(os, NPY_INT32, 2, "segments", &ns, &bad);
    in->segmentmarkers = arr_data(osm, NPY_INT32, 0, "segment_markers", &nsm, &bad);
    in->holes = arr_data(oh, NPY_DOUBLE, 2, "holes", &nh, &bad);
    in->regions = arr_data(orr, NPY_DOUBLE, 4, "regions", &nr, &bad);
    if (bad) return -1;
    if (nv > INT32_MAX || ns > INT32_MAX || nh > INT32_MAX || nr > INT32_MAX ||
        (in->pointmarkers && nvm != nv) || (in->pointattr && nva != nv) ||
        (in->segmentmarkers && nsm != ns)) {
        PyErr_Format(PyExc_ValueError, "%s: array lengths do not match", who);
        return -1;
    }
    in->npoints = (int32_t)nv;
    in->npointattr = in->pointattr ? k : 0;
    in->nsegments = (int32_t)ns;
    in->nholes = (int32_t)nh;
    in->nregions = (int32_t)nr;
    return 0;
}

static inline void capsule_free(PyObject *cap) {
    free(PyCapsule_GetPointer(cap, "pcdm.buffer"));
}

/* A numpy array (rows x cols, cols 0: one dimension) over p, a buffer from malloc that the
 * array then owns (freed with it); p NULL: an empty array.  NULL with an exception set. */
static inline PyObject *arr_own(void *p, npy_intp rows, npy_intp cols, int type) {
    npy_intp dims[2] = {rows, cols};
    int nd = cols ? 2 : 1;
    if (!p || rows == 0) {
        free(p);
        return PyArray_ZEROS(nd, dims, type, 0);
    }
    PyObject *a = PyArray_SimpleNewFromData(nd, dims, type, p);
    if (!a) {
        free(p);
        return NULL;
    }
    PyObject *cap = PyCapsule_New(p, "pcdm.buffer", capsule_free);
    if (!cap) {
        Py_DECREF(a);
        free(p);
        return NULL;
    }
    if (PyArray_SetBaseObject((PyArrayObject *)a, cap) < 0) { /* steals cap */
        Py_DECREF(a);
        return NULL;
    }
    return a;
}

/* d[key] = v (stolen); 0, or -1 with an exception (v NULL: one is set already). */
static inline int put(PyObject *d, const char *key, PyObject *v) {
    if (!v) return -1;
    int rc = PyDict_SetItemString(d, key, v);
    Py_DECREF(v);
    return rc;
}

/* Hands the mesh's arrays over to the dict d (numpy takes each buffer without a copy and m's
 * pointer is cleared, so pcdm_mesh_free(m) afterwards frees only what was not handed over):
 * vertices float64 (n, 2), vertex_markers int32 (n, 1), vertex_attributes float64 (n, k) when
 * k > 0, triangles int32 (t, 3), triangle_attributes float64 (t, 1) when the library gives
 * them, segments int32 (s, 2), segment_markers int32 (s, 1).  0, or -1 with an exception. */
static inline int arr_put_mesh(PyObject *d, pcdm_mesh *m) {
    int rc = 0;
    rc = rc || put(d, "vertices", arr_own(m->points, m->npoints, 2, NPY_DOUBLE));
    m->points = NULL;
    rc = rc || put(d, "vertex_markers", arr_own(m->pointmarkers, m->npoints, 1, NPY_INT32));
    m->pointmarkers = NULL;
    if (m->npointattr > 0)
        rc = rc || put(d, "vertex_attributes",
                       arr_own(m->pointattr, m->npoints, m->npointattr, NPY_DOUBLE));
    m->pointattr = NULL;
    rc = rc || put(d, "triangles", arr_own(m->triangles, m->ntriangles, 3, NPY_INT32));
    m->triangles = NULL;
    if (m->triangleattr)
        rc = rc ||
             put(d, "triangle_attributes", arr_own(m->triangleattr, m->ntriangles, 1, NPY_DOUBLE));
    m->triangleattr = NULL;
    rc = rc || put(d, "segments", arr_own(m->segments, m->nsegments, 2, NPY_INT32));
    m->segments = NULL;
    rc = rc || put(d, "segment_markers", arr_own(m->segmentmarkers, m->nsegments, 1, NPY_INT32));
    m->segmentmarkers = NULL;
    return rc;
}

/* *o: the defaults (pcdm_options_default) with the bounds and switches both calls take. */
static inline void arr_options(pcdm_options *o, double min_angle, double max_area,
                               long long max_steiner, int circumcenters, int convex_hull) {
    pcdm_options_default(o);
    o->min_angle = min_angle;
    o->max_area = max_area;
    o->max_steiner = max_steiner;
    o->circumcenters = circumcenters;
    o->convex_hull = convex_hull;
}

/* The extensions' return value (code, message, d), d taken over (its reference dropped); rc
 * nonzero (building d failed, an exception set) or d NULL: NULL. */
static inline PyObject *arr_result(int code, const pcdm_status *st, PyObject *d, int rc) {
    PyObject *r = rc || !d ? NULL : Py_BuildValue("isO", code, st->message, d);
    Py_XDECREF(d);
    return r;
}

#endif
