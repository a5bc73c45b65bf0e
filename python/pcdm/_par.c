/* _par.c: the Python extension module pcdm._par -- libpcdm's parallel call
 * (include/pcdm_par.h: pcdm_triangulate_par, PCDM or PBW Collective over a communicator) on
 * numpy arrays, for mpi4py users (python/pcdm/parallel.py is its Python half).
 *
 * Built only where MPI is (setup.py: mpicc's flags, METIS), from every source of the library;
 * the default module pcdm._core never links MPI.  The communicator arrives as its Fortran handle
 * (mpi4py's comm.py2f()), turned back with MPI_Comm_f2c, so no mpi4py header is needed at build
 * time.  Each rank gets its part as the library returns it: local vertices with their global
 * numbers and ownership, triangles in local numbering, the part's first global triangle number
 * and the whole mesh's counts; or, with root >= 0, the whole mesh on that rank.  The GIL is
 * released during the call (it is MPI's main thread that calls, as the library requires).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include "pcdm_par.h"

#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#include "_arrays.h"

#include <stdint.h>
#include <string.h>

static const char *const kw[] = {"comm",           "vertices",
                                 "vertex_markers", "vertex_attributes",
                                 "segments",       "segment_markers",
                                 "holes",          "regions",
                                 "min_angle",      "max_area",
                                 "max_steiner",    "circumcenters",
                                 "convex_hull",    "method",
                                 "subdomains",     "root",
                                 "threads",        NULL};

/* triangulate(comm, vertices, vertex_markers, vertex_attributes, segments, segment_markers,
 * holes, regions, min_angle, max_area, max_steiner, circumcenters, convex_hull, method,
 * subdomains, root, threads) -> (code, message, dict or None).  Collective over comm (a Fortran
 * handle).  The arrays as pcdm._core.triangulate takes them. */
static PyObject *py_triangulate(PyObject *self, PyObject *args, PyObject *kwargs) {
    long long fcomm, max_steiner;
    PyObject *ov, *ovm, *ova, *os, *osm, *oh, *orr;
    double min_angle, max_area;
    int circumcenters, convex_hull, method, subdomains, root, threads;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "LOOOOOOOddLppiiii", (char **)kw, &fcomm, &ov,
                                     &ovm, &ova, &os, &osm, &oh, &orr, &min_angle, &max_area,
                                     &max_steiner, &circumcenters, &convex_hull, &method,
                                     &subdomains, &root, &threads))
        return NULL;
    pcdm_input in;
    if (arr_input(ov, ovm, ova, os, osm, oh, orr, "_par", &in)) return NULL;
    pcdm_options o;
    arr_options(&o, min_angle, max_area, max_steiner, circumcenters, convex_hull);
    o.method = method;
    o.subdomains = subdomains;
    o.threads = threads;
    o.root = root;
    MPI_Comm comm = MPI_Comm_f2c((MPI_Fint)fcomm);
    pcdm_mesh m;
    pcdm_status st;
    int code;
    Py_BEGIN_ALLOW_THREADS;
    code = pcdm_triangulate_par(comm, &in, &o, &m, &st);
    Py_END_ALLOW_THREADS;
    if (code != PCDM_OK && code != PCDM_ESTEINER)
        return Py_BuildValue("isO", code, st.message, Py_None);
    PyObject *d = PyDict_New();
    int rc = d ? 0 : -1;
    rc = rc || arr_put_mesh(d, &m);
    if (m.pointglobal) {
        rc = rc || put(d, "vertex_global", arr_own(m.pointglobal, m.npoints, 0, NPY_INT64));
        m.pointglobal = NULL;
        rc = rc || put(d, "vertex_owned", arr_own(m.pointowned, m.npoints, 0, NPY_BOOL));
        m.pointowned = NULL;
    }
    rc = rc || put(d, "triangle_first", PyLong_FromLongLong(m.trianglefirst));
    rc = rc || put(d, "global_vertices", PyLong_FromLongLong(m.nglobalpoints));
    rc = rc || put(d, "global_triangles", PyLong_FromLongLong(m.nglobaltriangles));
    rc = rc || put(d, "global_segments", PyLong_FromLongLong(m.nglobalsegments));
    pcdm_mesh_free(&m);
    return arr_result(code, &st, d, rc);
}

static PyMethodDef methods[] = {
    {"triangulate", (PyCFunction)(void (*)(void))py_triangulate, METH_VARARGS | METH_KEYWORDS,
     "triangulate(comm_f, ...) -> (code, message, dict or None): pcdm_triangulate_par"},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT,
                                    "pcdm._par",
                                    "libpcdm's parallel call (MPI)",
                                    -1,
                                    methods,
                                    NULL,
                                    NULL,
                                    NULL,
                                    NULL};

PyMODINIT_FUNC PyInit__par(void);
PyMODINIT_FUNC PyInit__par(void) {
    import_array();
    return PyModule_Create(&module);
}
