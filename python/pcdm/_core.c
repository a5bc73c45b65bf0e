/* _core.c: the Python extension module pcdm._core -- the C half of the pcdm package
 * (python/pcdm/__init__.py is the other): libpcdm's sequential call (include/pcdm.h) on numpy
 * arrays, the command line's switch parser, the validator, and ./mesh as `python -m pcdm`.
 *
 * Built from the tree with the sequential library's sources (mesher/seq_sources.txt) and the
 * programs' front end (apps/cli.c, apps/cli_tables.c): no MPI.  The switch string a caller
 * gives is read by the very parser ./mesh uses (cli_parse with ./mesh's table), so the letters,
 * the numbers' syntax and every message ("option -D in '-pD' is not supported ...") are the
 * command line's.  Meshing runs with the GIL released (pcdm_triangulate keeps no global state:
 * two Python threads mesh at once); a size callable is called back with the GIL taken again,
 * while a background mesh given as size= is a rule in C (_bgsize.h: a quadtree and the exact
 * orient2d locate the point) that needs no GIL.
 * The arrays the library returns are handed to numpy without a copy (each owned by a capsule
 * that frees it).  Nothing here prints, exits or aborts on bad input: every failure is a Python
 * exception (ValueError with the library's or the parser's one-line message).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include "pcdm.h"

#include "bounds/bounds.h"
#include "bounds/sizefield.h"
#include "check/validate.h"
#include "cli.h"
#include "geom/geom.h"
#include "geom/pslg.h"
#include "geom/tloc.h"
#include "io/meshio.h"
#include "io/xwrite.h"
#include "run/run.h"

/* after the project's headers: numpy's pulls in <complex.h>, whose macro I is a parameter name
 * in seq/rules.h */
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "_arrays.h"
#include "_bgsize.h"

/* ---- the switch parser ----------------------------------------------------------------- */

/* The text of a FILE opened with open_memstream, without the program's prefix "mesh: ", the
 * usage hint " (try --help)" and the final newline: the command line's message itself. */
static void clean_message(char *s) {
    size_t n = strlen(s);
    while (n && (s[n - 1] == '\n' || s[n - 1] == ' '))
        s[--n] = '\0';
    static const char hint[] = " (try --help)";
    size_t h = sizeof hint - 1;
    if (n >= h && strcmp(s + n - h, hint) == 0) s[n -= h] = '\0';
    static const char prefix[] = "mesh: ";
    size_t p = sizeof prefix - 1;
    if (strncmp(s, prefix, p) == 0) memmove(s, s + p, n - p + 1);
}

/* cli_parse of argv (argc of them) with ./mesh's table, the messages (usage error or
 * warnings) into *msg (malloc'd, cleaned); returns cli_parse's value. */
static int parse_argv(int argc, char **argv, cli_opts *o, int *code, char **msg) {
    size_t len = 0;
    *msg = NULL;
    FILE *err = open_memstream(msg, &len);
    if (!err) return -1;
    int stop = cli_parse(&cli_mesh, argc, argv, NULL, err, o, code);
    fclose(err);
    if (stop) { /* the error is the last line; warnings may come before it */
        size_t n = strlen(*msg);
        while (n && (*msg)[n - 1] == '\n')
            (*msg)[--n] = '\0';
        char *last = strrchr(*msg, '\n');
        if (last) memmove(*msg, last + 1, strlen(last + 1) + 1);
    }
    clean_message(*msg);
    return stop;
}

/* parse(switches: str) -> dict: the switch string read by ./mesh's parser (Triangle's syntax,
 * "pq30a0.01"; a leading '-' is optional).  Keys: the settings (min_angle, max_area,
 * max_steiner, circumcenters, convex_hull, region_attributes, region_areas, edges, neighbors,
 * order2, refine, quiet, verbose, no_node, no_ele, no_poly), q_given and a_given (whether the
 * string sets the angle, and the area as a number: it is read twice, after -q1 -a1 and after
 * -q2 -a2, and a value that follows them was set by the string), and "warnings" (the parser's
 * warnings, one per line, or "").  A usage error raises ValueError with its message. */
static PyObject *py_parse(PyObject *self, PyObject *args) {
    const char *sw;
    if (!PyArg_ParseTuple(args, "s", &sw)) return NULL;
    size_t n = strlen(sw);
    char *arg = malloc(n + 2);
    if (!arg) return PyErr_NoMemory();
    arg[0] = '-';
    memcpy(arg + 1, sw[0] == '-' ? sw + 1 : sw, n + 1);
    char prog[] = "mesh", input[] = "input", q1[] = "-q1", a1[] = "-a1", q2[] = "-q2", a2[] = "-a2";
    int none = n == 0 || (n == 1 && sw[0] == '-'); /* no switches */
    char *argv1[6] = {prog, q1, a1, none ? input : arg, none ? NULL : input, NULL};
    char *argv2[6] = {prog, q2, a2, none ? input : arg, none ? NULL : input, NULL};
    int argc = none ? 4 : 5;
    cli_opts o, o2;
    int code = 0, code2 = 0;
    char *msg = NULL, *msg2 = NULL;
    int stop = parse_argv(argc, argv1, &o, &code, &msg);
    int stop2 = stop ? 1 : parse_argv(argc, argv2, &o2, &code2, &msg2);
    free(arg);
    free(msg2);
    if (stop < 0 || !msg) {
        free(msg);
        return PyErr_NoMemory();
    }
    if (stop || stop2) {
        PyErr_SetString(PyExc_ValueError, code == 0 && stop ? "--help: not a switch" : msg);
        free(msg);
        return NULL;
    }
    const par_opts *p = &o.par;
    int q_given = o.par.min_angle == o2.par.min_angle;
    int a_given = o.par.max_area == o2.par.max_area;
    PyObject *d = Py_BuildValue(
        "{s:d,s:d,s:L,s:i,s:i,s:i,s:i,s:i,s:i,s:i,s:i,s:i,s:i,s:i,s:i,s:i,s:O,s:O,s:s}",
        "min_angle", q_given ? p->min_angle : 0.0, "max_area", a_given ? p->max_area : 0.0,
        "max_steiner", (long long)p->max_steiner, "circumcenters", p->circumcenters, "convex_hull",
        p->convex_hull, "region_attributes", p->region_attr, "region_areas", p->region_area,
        "edges", p->edges, "neighbors", p->neighbors, "order2", p->order2, "refine", p->refine,
        "quiet", p->quiet, "verbose", p->verbose, "no_node", p->no_node, "no_ele", p->no_ele,
        "no_poly", p->no_poly, "q_given", q_given ? Py_True : Py_False, "a_given",
        a_given ? Py_True : Py_False, "warnings", msg);
    free(msg);
    return d;
}

/* ---- triangulate ------------------------------------------------------------------------ */

/* S (zeroed) as -r's .area rule (bounds/sizefield.h) over the old mesh (vertices xy, triangles
 * tri, each oriented counter-clockwise here) with bound area[t] per old triangle (<= 0 or not
 * finite: none), in the caller's coordinates.  Indices are checked by the caller.  Returns 0,
 * or -1 (tloc could not index them). */
static int areas_field(size_field *S, const double *xy, npy_intp nv, const int32_t *tri, int32_t nt,
                       const double *area) {
    (void)nv;
    S->ont = nt;
    S->oxy = malloc(6 * (size_t)nt * sizeof(double) + 1);
    S->otri = malloc(3 * (size_t)nt * sizeof(int32_t) + 1);
    S->oarea = malloc((size_t)nt * sizeof(double) + 1);
    if (!S->oxy || !S->otri || !S->oarea) return -1;
    for (int32_t t = 0; t < nt; t++) {
        const double *p[3];
        for (int k = 0; k < 3; k++)
            p[k] = xy + 2 * (size_t)tri[3 * (size_t)t + k];
        if (geom_orient2d(p[0], p[1], p[2]) < 0) {
            const double *x = p[1];
            p[1] = p[2];
            p[2] = x;
        }
        for (int k = 0; k < 3; k++) {
            S->oxy[6 * (size_t)t + 2 * k] = p[k][0];
            S->oxy[6 * (size_t)t + 2 * k + 1] = p[k][1];
            S->otri[3 * (size_t)t + k] = 3 * t + k;
        }
        double a = area[t];
        S->oarea[t] = a > 0 && a < HUGE_VAL ? a : 0;
    }
    S->active = 1;
    return tloc_build(&S->old, S->oxy, S->otri, S->ont);
}

/* boundary(vertices, triangles) -> (segments, holes): the boundary edges of the mesh as
 * segments and a hole point beside every chain of them, as ./mesh -r makes them for a mesh
 * without a .poly (io/meshio.h: meshio_boundary_pslg); indices checked by the caller. */
static PyObject *py_boundary(PyObject *self, PyObject *args) {
    PyObject *ov, *ot;
    if (!PyArg_ParseTuple(args, "OO", &ov, &ot)) return NULL;
    int bad = 0;
    npy_intp nv, nt;
    const double *xy = arr_data(ov, NPY_DOUBLE, 2, "vertices", &nv, &bad);
    const int32_t *tri = arr_data(ot, NPY_INT32, 3, "triangles", &nt, &bad);
    if (bad) return NULL;
    if (nv > INT32_MAX || nt > INT32_MAX / 3) {
        PyErr_SetString(PyExc_ValueError, "triangles: too many");
        return NULL;
    }
    mesh_flat m;
    memset(&m, 0, sizeof m);
    m.nverts = (int32_t)nv;
    m.xy = (double *)xy;
    m.ntris = (int32_t)nt;
    m.tri = malloc(3 * (size_t)nt * sizeof(int32_t) + 1);
    if (!m.tri) return PyErr_NoMemory();
    memcpy(m.tri, tri, 3 * (size_t)nt * sizeof(int32_t));
    pslg g;
    memset(&g, 0, sizeof g);
    int rc;
    Py_BEGIN_ALLOW_THREADS;
    meshio_flat_orient_ccw(&m);
    rc = meshio_boundary_pslg(&m, &g);
    Py_END_ALLOW_THREADS;
    free(m.tri);
    if (rc != 0) {
        pslg_free(&g);
        PyErr_SetString(PyExc_ValueError, "triangles: too many to index");
        return NULL;
    }
    PyObject *s = arr_own(g.seg, g.nsegs, 2, NPY_INT32);
    PyObject *h = arr_own(g.holes, g.nholes, 2, NPY_DOUBLE);
    g.seg = NULL;
    g.holes = NULL;
    pslg_free(&g);
    if (!s || !h) {
        Py_XDECREF(s);
        Py_XDECREF(h);
        return NULL;
    }
    return Py_BuildValue("NN", s, h);
}

/* ---- size= as a background mesh (_bgsize.h) ---------------------------------------------- */

/* B from the Python half's tuple (vertices float64 (n, 2), triangles int32 (m, 3), values
 * float64 (n,) or (m,), per_triangle; shapes and finiteness checked there), after checking
 * the indices, the values (positive) and the triangles (bg_build).  0, or -1 with a
 * ValueError naming the array and the index. */
static int bg_from(PyObject *obg, bg_size *B) {
    PyObject *bv, *bt, *bval;
    int per_triangle, bad = 0;
    npy_intp bnv, bnt, bnval;
    if (!PyArg_ParseTuple(obg, "OOOp", &bv, &bt, &bval, &per_triangle)) return -1;
    const double *bxy = arr_data(bv, NPY_DOUBLE, 2, "size vertices", &bnv, &bad);
    const int32_t *btri = arr_data(bt, NPY_INT32, 3, "size triangles", &bnt, &bad);
    const double *bvalue = arr_data(bval, NPY_DOUBLE, 0, "size values", &bnval, &bad);
    if (bad) return -1;
    if (!bxy || !btri || !bvalue || bnval != (per_triangle ? bnt : bnv)) {
        PyErr_SetString(PyExc_ValueError, "_core: array lengths do not match");
        return -1;
    }
    for (npy_intp k = 0; k < 3 * bnt; k++)
        if (btri[k] < 0 || btri[k] >= bnv) {
            PyErr_Format(PyExc_ValueError,
                         "size[\"triangles\"][%zd]: vertex %d out of range (0..%zd)",
                         (Py_ssize_t)(k / 3), btri[k], (Py_ssize_t)bnv - 1);
            return -1;
        }
    for (npy_intp k = 0; k < bnval; k++)
        if (!(bvalue[k] > 0 && bvalue[k] < HUGE_VAL)) {
            char num[32];
            snprintf(num, sizeof num, "%g", bvalue[k]);
            PyErr_Format(PyExc_ValueError, "size[\"%s\"][%zd]: %s is not a positive number",
                         per_triangle ? "triangle_max_area" : "vertex_sizes", (Py_ssize_t)k, num);
            return -1;
        }
    if (bnt < 1 || bnt > INT32_MAX / 3) {
        PyErr_SetString(PyExc_ValueError, bnt < 1 ? "size[\"triangles\"]: no triangles"
                                                  : "size[\"triangles\"]: too many");
        return -1;
    }
    return bg_build(B, bxy, btri, (int32_t)bnt, bvalue, per_triangle);
}

/* The size callable's context: the callable, and the first exception it raised (then every
 * later triangle is taken as small enough, so refinement ends soon). */
typedef struct size_ctx {
    PyObject *fn; /* None: none */
    PyObject *exc;
    size_field *areas; /* r's triangle_max_area (caller's coordinates), or NULL */
    bg_size *bg;       /* size= as a background mesh, or NULL */
} size_ctx;

static int size_call(void *ctx, const double *const corner[3], double area) {
    size_ctx *c = ctx;
    if (c->areas && size_field_unsuitable(c->areas, corner, area)) return 1;
    if (c->bg && bg_unsuitable(c->bg, corner, area)) return 1;
    if (c->fn == Py_None) return 0;
    PyGILState_STATE gs = PyGILState_Ensure();
    int big = 0;
    if (!c->exc) {
        npy_intp dims[2] = {3, 2};
        PyObject *v = PyArray_SimpleNew(2, dims, NPY_DOUBLE);
        PyObject *r = NULL;
        if (v) {
            double *q = PyArray_DATA((PyArrayObject *)v);
            for (int k = 0; k < 3; k++)
                q[2 * k] = corner[k][0], q[2 * k + 1] = corner[k][1];
            r = PyObject_CallFunction(c->fn, "Od", v, area);
            Py_DECREF(v);
        }
        if (r) {
            big = PyObject_IsTrue(r);
            Py_DECREF(r);
        }
        if (!r || big < 0) {
            PyObject *t, *val, *tb;
            PyErr_Fetch(&t, &val, &tb);
            PyErr_NormalizeException(&t, &val, &tb);
            Py_XDECREF(t);
            Py_XDECREF(tb);
            c->exc = val;
            big = 0;
        }
    }
    PyGILState_Release(gs);
    return big;
}

/* Triangle's edges (every edge once, with its marker: the segment's when not 0, else 1 on the
 * boundary, else 0) and neighbours (neighbour j opposite corner j, -1 on the boundary) of m,
 * from the writers' edge topology (io/xwrite.h).  Arrays from malloc, or NULL when not asked. */
static void topology(const pcdm_mesh *m, int want_e, int want_n, int32_t **edges, int32_t *ne,
                     int32_t **emark, int32_t **neigh) {
    mesh_flat f;
    memset(&f, 0, sizeof f);
    f.nverts = m->npoints;
    f.xy = m->points;
    f.ntris = m->ntriangles;
    f.tri = m->triangles;
    f.nsegs = m->nsegments;
    f.seg = m->segments;
    f.smarker = m->segmentmarkers;
    mesh_xview x;
    mesh_xview_topo(&x, &f, NULL);
    mesh_xview_finish(&x);
    *ne = 0;
    if (want_e) {
        *ne = x.ne;
        *edges = malloc(2 * (size_t)x.ne * sizeof(int32_t) + 1);
        *emark = malloc((size_t)x.ne * sizeof(int32_t) + 1);
        if (*edges && *emark)
            for (int32_t e = 0; e < x.ne; e++) {
                int32_t h = x.ehe[e], t = h / 3, j = h % 3;
                (*edges)[2 * e] = m->triangles[3 * t + (j + 1) % 3];
                (*edges)[2 * e + 1] = m->triangles[3 * t + (j + 2) % 3];
                (*emark)[e] = x.emark[e];
            }
    }
    if (want_n) {
        size_t nh = 3 * (size_t)m->ntriangles;
        *neigh = malloc(nh * sizeof(int32_t) + 1);
        if (*neigh) memcpy(*neigh, x.nb, nh * sizeof(int32_t));
    }
    mesh_xview_free(&x);
}

static const char *const tri_kw[] = {"vertices",
                                     "vertex_markers",
                                     "vertex_attributes",
                                     "segments",
                                     "segment_markers",
                                     "holes",
                                     "regions",
                                     "min_angle",
                                     "max_area",
                                     "max_steiner",
                                     "circumcenters",
                                     "convex_hull",
                                     "region_attributes",
                                     "region_areas",
                                     "no_refine",
                                     "lenses",
                                     "size",
                                     "refine_areas",
                                     "edges",
                                     "neighbors",
                                     "background",
                                     "threads",
                                     NULL};

/* triangulate(vertices, vertex_markers, vertex_attributes, segments, segment_markers, holes,
 * regions, min_angle, max_area, max_steiner, circumcenters, convex_hull, region_attributes,
 * region_areas, no_refine, lenses, size, refine_areas, edges, neighbors, background[, threads]) ->
 * (code, message, dict); refine_areas: None or (old vertices, old triangles (int32 (t, 3)), their
 * bounds (float64 (t,))), r's triangle_max_area rule; background: None or size= as a
 * background mesh (vertices float64 (n, 2), triangles int32 (m, 3), values float64 (n,) or
 * (m,), per_triangle), its indices, values and triangles checked here (bg_from); the arrays as
 * the Python half converted them (float64 (n, 2), int32 (n,), float64 (n, k), int32 (m, 2), int32
 * (m,), float64 (h, 2), float64 (r, 4); None: absent), pcdm_options' fields, the size callable
 * (or None), whether edges and neighbours are wanted, and pcdm_options.threads (0: the
 * sequential mesher; T >= 1: the subdomain mesher on T threads, where the build has it).  code is
 * pcdm_triangulate's (0 or PCDM_ESTEINER with the mesh; else the dict is None and message says
 * why). */
static PyObject *py_triangulate(PyObject *self, PyObject *args, PyObject *kw) {
    PyObject *ov, *ovm, *ova, *os, *osm, *oh, *orr, *size, *rareas, *obg;
    double min_angle, max_area;
    long long max_steiner;
    int circumcenters, convex_hull, rattr, rarea, no_refine, lenses, want_e, want_n, threads = 0;
    if (!PyArg_ParseTupleAndKeywords(
            args, kw, "OOOOOOOddLppppppOOppO|i", (char **)tri_kw, &ov, &ovm, &ova, &os, &osm, &oh,
            &orr, &min_angle, &max_area, &max_steiner, &circumcenters, &convex_hull, &rattr, &rarea,
            &no_refine, &lenses, &size, &rareas, &want_e, &want_n, &obg, &threads))
        return NULL;
    pcdm_input in;
    if (arr_input(ov, ovm, ova, os, osm, oh, orr, "_core", &in)) return NULL;
    pcdm_options o;
    arr_options(&o, min_angle, max_area, max_steiner, circumcenters, convex_hull);
    o.region_attributes = rattr;
    o.region_areas = rarea;
    o.no_refine = no_refine;
    o.lenses = lenses;
    o.threads = threads;
    size_ctx sc = {size, NULL, NULL, NULL};
    bg_size B;
    memset(&B, 0, sizeof B);
    size_field S;
    memset(&S, 0, sizeof S);
    if (size != Py_None && !PyCallable_Check(size)) {
        PyErr_SetString(PyExc_TypeError, "size: not callable");
        return NULL;
    }
    if (rareas != Py_None) { /* (old vertices, old triangles, their areas): r with a alone */
        PyObject *rv, *rt, *ra;
        npy_intp onv, ont, ona;
        int bad = 0;
        if (!PyArg_ParseTuple(rareas, "OOO", &rv, &rt, &ra)) return NULL;
        const double *oxy = arr_data(rv, NPY_DOUBLE, 2, "refine vertices", &onv, &bad);
        const int32_t *otri = arr_data(rt, NPY_INT32, 3, "refine triangles", &ont, &bad);
        const double *oar = arr_data(ra, NPY_DOUBLE, 0, "triangle_max_area", &ona, &bad);
        if (bad) return NULL;
        if (ona != ont || ont > INT32_MAX / 3) {
            PyErr_SetString(PyExc_ValueError, "_core: array lengths do not match");
            return NULL;
        }
        if (areas_field(&S, oxy, onv, otri, (int32_t)ont, oar) != 0) {
            size_field_free(&S);
            PyErr_SetString(PyExc_ValueError, "triangles: too many to index");
            return NULL;
        }
        sc.areas = &S;
    }
    if (obg != Py_None) {
        if (bg_from(obg, &B) != 0) {
            size_field_free(&S);
            return NULL;
        }
        sc.bg = &B;
    }
    if (size != Py_None || sc.areas || sc.bg) {
        o.unsuitable = size_call;
        o.unsuitable_ctx = &sc;
    }
    pcdm_mesh m;
    pcdm_status st;
    int32_t *edges = NULL, *emark = NULL, *neigh = NULL, ne = 0;
    int code;
    Py_BEGIN_ALLOW_THREADS;
    code = pcdm_triangulate(&in, &o, &m, &st);
    if ((code == PCDM_OK || code == PCDM_ESTEINER) && (want_e || want_n))
        topology(&m, want_e, want_n, &edges, &ne, &emark, &neigh);
    Py_END_ALLOW_THREADS;
    size_field_free(&S);
    bg_free(&B);
    if (sc.exc) { /* the size callable raised: that exception, whatever the mesh */
        if (code == PCDM_OK || code == PCDM_ESTEINER) pcdm_mesh_free(&m);
        free(edges), free(emark), free(neigh);
        PyErr_SetObject((PyObject *)Py_TYPE(sc.exc), sc.exc);
        Py_DECREF(sc.exc);
        return NULL;
    }
    if (code != PCDM_OK && code != PCDM_ESTEINER)
        return Py_BuildValue("isO", code, st.message, Py_None);
    if ((want_e && (!edges || !emark)) || (want_n && !neigh)) {
        pcdm_mesh_free(&m);
        free(edges), free(emark), free(neigh);
        return PyErr_NoMemory();
    }
    PyObject *d = PyDict_New();
    int rc = d ? 0 : -1;
    rc = rc || arr_put_mesh(d, &m);
    if (want_e) {
        rc = rc || put(d, "edges", arr_own(edges, ne, 2, NPY_INT32));
        edges = NULL;
        rc = rc || put(d, "edge_markers", arr_own(emark, ne, 1, NPY_INT32));
        emark = NULL;
    }
    if (want_n) {
        rc = rc || put(d, "neighbors", arr_own(neigh, m.ntriangles, 3, NPY_INT32));
        neigh = NULL;
    }
    pcdm_mesh_free(&m);
    free(edges), free(emark), free(neigh);
    return arr_result(code, &st, d, rc);
}

/* ---- check ------------------------------------------------------------------------------- */

static double *dup_d(const double *p, size_t n) {
    double *q = malloc(n * sizeof(double) + 1);
    if (q && n) memcpy(q, p, n * sizeof(double));
    return q;
}

static int32_t *dup_i(const int32_t *p, size_t n) { /* p NULL: zeros */
    int32_t *q = calloc(n + 1, sizeof(int32_t));
    if (q && p && n) memcpy(q, p, n * sizeof(int32_t));
    return q;
}

static const char *const check_kw[] = {"vertices",
                                       "vertex_markers",
                                       "segments",
                                       "segment_markers",
                                       "holes",
                                       "regions",
                                       "mesh_vertices",
                                       "mesh_triangles",
                                       "mesh_segments",
                                       "mesh_segment_markers",
                                       "triangle_attributes",
                                       "min_angle",
                                       "max_area",
                                       "convex_hull",
                                       "region_attributes",
                                       "region_areas",
                                       NULL};

/* check(vertices, vertex_markers, segments, segment_markers, holes, regions, mesh_vertices,
 * mesh_triangles, mesh_segments, mesh_segment_markers, triangle_attributes, min_angle,
 * max_area, convex_hull, region_attributes, region_areas) -> dict: ./meshcheck on arrays (the
 * input prepared as the meshers prepare it, crossing segments split, with convex_hull its hull
 * enclosed), the validator's report as a dict.  Bad input raises ValueError. */
static PyObject *py_check(PyObject *self, PyObject *args, PyObject *kw) {
    PyObject *ov, *ovm, *os, *osm, *oh, *orr, *mv, *mt, *ms, *msm, *mta;
    double min_angle, max_area;
    int hull, rattr, rarea;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OOOOOOOOOOOddppp", (char **)check_kw, &ov, &ovm,
                                     &os, &osm, &oh, &orr, &mv, &mt, &ms, &msm, &mta, &min_angle,
                                     &max_area, &hull, &rattr, &rarea))
        return NULL;
    int bad = 0;
    npy_intp nv, nvm, ns, nsm, nh, nr, mnv, mnt, mns, mnsm, mnta;
    const double *xy = arr_data(ov, NPY_DOUBLE, 2, "vertices", &nv, &bad);
    const int32_t *vm = arr_data(ovm, NPY_INT32, 0, "vertex_markers", &nvm, &bad);
    const int32_t *seg = arr_data(os, NPY_INT32, 2, "segments", &ns, &bad);
    const int32_t *sm = arr_data(osm, NPY_INT32, 0, "segment_markers", &nsm, &bad);
    const double *holes = arr_data(oh, NPY_DOUBLE, 2, "holes", &nh, &bad);
    const double *regions = arr_data(orr, NPY_DOUBLE, 4, "regions", &nr, &bad);
    double *mxy = arr_data(mv, NPY_DOUBLE, 2, "mesh vertices", &mnv, &bad);
    int32_t *mtri = arr_data(mt, NPY_INT32, 3, "mesh triangles", &mnt, &bad);
    int32_t *mseg = arr_data(ms, NPY_INT32, 2, "mesh segments", &mns, &bad);
    int32_t *msm_ = arr_data(msm, NPY_INT32, 0, "mesh segment markers", &mnsm, &bad);
    double *mta_ = arr_data(mta, NPY_DOUBLE, 0, "triangle attributes", &mnta, &bad);
    if (bad) return NULL;
    if ((vm && nvm != nv) || (sm && nsm != ns) || (msm_ && mnsm != mns) || (mta_ && mnta != mnt) ||
        nv > INT32_MAX || mnv > INT32_MAX || mnt > INT32_MAX || mns > INT32_MAX) {
        PyErr_SetString(PyExc_ValueError, "_core: array lengths do not match");
        return NULL;
    }
    for (npy_intp s = 0; s < 2 * ns; s++)
        if (seg[s] < 0 || seg[s] >= nv)
            return PyErr_Format(PyExc_ValueError, "segments[%zd]: vertex %d out of range (0..%zd)",
                                (Py_ssize_t)(s / 2), seg[s], (Py_ssize_t)nv - 1);
    for (npy_intp t = 0; t < 3 * mnt; t++)
        if (mtri[t] < 0 || mtri[t] >= mnv)
            return PyErr_Format(PyExc_ValueError,
                                "mesh triangles[%zd]: vertex %d out of range (0..%zd)",
                                (Py_ssize_t)(t / 3), mtri[t], (Py_ssize_t)mnv - 1);
    for (npy_intp s = 0; s < 2 * mns; s++)
        if (mseg[s] < 0 || mseg[s] >= mnv)
            return PyErr_Format(PyExc_ValueError,
                                "mesh segments[%zd]: vertex %d out of range (0..%zd)",
                                (Py_ssize_t)(s / 2), mseg[s], (Py_ssize_t)mnv - 1);
    pslg g;
    memset(&g, 0, sizeof g);
    g.nverts = (int32_t)nv;
    g.xy = dup_d(xy, 2 * (size_t)nv);
    g.vmarker = dup_i(vm, (size_t)nv);
    g.vline = dup_i(NULL, (size_t)nv);
    g.nsegs = (int32_t)ns;
    g.seg = dup_i(seg, 2 * (size_t)ns);
    g.smarker = dup_i(sm, (size_t)ns);
    g.sline = dup_i(NULL, (size_t)ns);
    g.nholes = (int32_t)nh;
    g.holes = dup_d(holes, 2 * (size_t)nh);
    g.nregions = (int32_t)nr;
    g.regions = dup_d(regions, 4 * (size_t)nr);
    g.quiet = 1;
    snprintf(g.path, sizeof g.path, "input");
    snprintf(g.segpath, sizeof g.segpath, "input");
    if (!g.xy || !g.vmarker || !g.vline || !g.seg || !g.smarker || !g.sline || !g.holes ||
        !g.regions) {
        pslg_free(&g);
        return PyErr_NoMemory();
    }
    /* the mesh, borrowed (the validator only reads it) */
    mesh_flat f;
    memset(&f, 0, sizeof f);
    f.nverts = (int32_t)mnv;
    f.xy = mxy;
    f.ntris = (int32_t)mnt;
    f.tri = mtri;
    f.nsegs = (int32_t)mns;
    f.seg = mseg;
    f.smarker = msm_;
    f.tattr = mta_;
    validate_opts vo = {
        .min_angle = min_angle, .max_area = max_area, .region_attr = rattr, .region_area = rarea};
    validate_report r;
    char err[1024] = "";
    int rc;
    Py_BEGIN_ALLOW_THREADS;
    rc = pslg_check_ex(&g, PSLG_SPLIT | (hull ? PSLG_HULL : 0u), err, sizeof err);
    if (rc == 0) mesh_validate(&g, &f, &vo, &r);
    Py_END_ALLOW_THREADS;
    pslg_free(&g);
    if (rc != 0) {
        PyErr_SetString(PyExc_ValueError, err);
        return NULL;
    }
    char line[1024] = "";
    FILE *s = fmemopen(line, sizeof line - 1, "w");
    if (s) {
        validate_report_print(&r, s);
        fclose(s);
    }
    line[strcspn(line, "\n")] = '\0';
    return Py_BuildValue(
        "{s:O,s:s,s:s,s:l,s:l,s:d,s:d,s:d,s:d,s:d,s:l,s:l,s:l,s:l,s:l,s:l,s:l,s:l,s:l,s:l,s:l}",
        "ok", r.ok ? Py_True : Py_False, "summary", line, "first_problem", r.first_problem,
        "triangles", r.ntris, "vertices", r.nverts, "min_angle", r.min_angle, "max_area",
        r.max_area, "min_angle_unforced", r.min_angle_unforced, "area", r.mesh_area, "domain_area",
        r.domain_area, "bad_orientation", r.bad_orient, "bad_conformity", r.bad_conform,
        "missing_vertices", r.missing_verts, "missing_segments", r.missing_segs,
        "stray_boundary_edges", r.stray_boundary, "non_delaunay", r.non_delaunay, "bad_angle",
        r.bad_angle, "bad_area", r.bad_area, "bad_region", r.bad_region, "area_mismatch",
        r.area_mismatch, "exempt", r.nexempt);
}

/* ---- the command line -------------------------------------------------------------------- */

/* main(argv: list[str]) -> int: ./mesh with these arguments (argv[0] the program's name): the
 * same options, messages, files and exit status; the GIL released while it runs. */
static PyObject *py_main(PyObject *self, PyObject *args) {
    PyObject *list;
    if (!PyArg_ParseTuple(args, "O!", &PyList_Type, &list)) return NULL;
    Py_ssize_t n = PyList_GET_SIZE(list);
    char **argv = calloc((size_t)n + 1, sizeof(char *));
    if (!argv) return PyErr_NoMemory();
    for (Py_ssize_t i = 0; i < n; i++) {
        const char *s = PyUnicode_AsUTF8(PyList_GET_ITEM(list, i));
        if (!s || !(argv[i] = strdup(s))) {
            for (Py_ssize_t k = 0; k < i; k++)
                free(argv[k]);
            free(argv);
            return s ? PyErr_NoMemory() : NULL;
        }
    }
    int code = 0;
    Py_BEGIN_ALLOW_THREADS;
    cli_opts o;
    if (!cli_parse(&cli_mesh, (int)n, argv, stdout, stderr, &o, &code)) {
        run_job j;
        run_job_init(&j, RUN_SEQ, &o.par);
        j.lens = o.lens;
        j.cdt_only = o.cdt_only;
        code = run_mesh(&j);
    }
    fflush(stdout);
    fflush(stderr);
    Py_END_ALLOW_THREADS;
    for (Py_ssize_t i = 0; i < n; i++)
        free(argv[i]);
    free(argv);
    return PyLong_FromLong(code);
}

static PyObject *py_version(PyObject *self, PyObject *noargs) {
    return PyUnicode_FromString(pcdm_version());
}

static PyMethodDef methods[] = {
    {"parse", py_parse, METH_VARARGS, "parse(switches) -> dict: the command line's reading"},
    {"triangulate", (PyCFunction)(void (*)(void))py_triangulate, METH_VARARGS | METH_KEYWORDS,
     "triangulate(...) -> (code, message, dict or None)"},
    {"check", (PyCFunction)(void (*)(void))py_check, METH_VARARGS | METH_KEYWORDS,
     "check(...) -> dict: the validator's report"},
    {"main", py_main, METH_VARARGS, "main(argv) -> int: ./mesh"},
    {"boundary", py_boundary, METH_VARARGS, "boundary(vertices, triangles) -> (segments, holes)"},
    {"version", py_version, METH_NOARGS, "version() -> str: libpcdm's version"},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT,
                                    "pcdm._core",
                                    "libpcdm's sequential call, parser and validator",
                                    -1,
                                    methods,
                                    NULL,
                                    NULL,
                                    NULL,
                                    NULL};

PyMODINIT_FUNC PyInit__core(void);
PyMODINIT_FUNC PyInit__core(void) {
    import_array();
    geom_init();
    PyObject *mod = PyModule_Create(&module);
    if (mod &&
        (PyModule_AddObject(mod, "DEFAULT_MIN_ANGLE", PyFloat_FromDouble(BOUNDS_DEFAULT_ANGLE)) !=
             0 ||
         PyModule_AddObject(mod, "ANGLE_LIMIT", PyFloat_FromDouble(BOUNDS_ANGLE_LIMIT)) != 0)) {
        Py_DECREF(mod);
        return NULL;
    }
    return mod;
}
