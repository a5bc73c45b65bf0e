/* meshio: a flat, pointer-free view of a finished mesh and its writers.
 *
 * Every mesher (./mesh, ./pcdm, ./pbw) ends by filling a mesh_flat: global vertex numbering,
 * counter-clockwise triangles, the constrained edges (subsegments) with their markers, and for
 * pictures the owning rank of each triangle.  The writers produce Triangle's .node/.ele/.poly,
 * legacy VTK (unstructured grid, readable by ParaView and meshio) and SVG.  Each file is
 * written to a temporary name in the same directory and renamed, so a reader never sees half a
 * file.  All functions return 0, or -1 with "FILE: problem" in err.
 */
#ifndef MESHIO_H
#define MESHIO_H

#include "base/base.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

typedef struct mesh_flat {
    int32_t nverts;
    double *xy;       /* 2 * nverts */
    int32_t nvin;     /* vin's length: vertices nvin .. nverts - 1 are no input vertices */
    int32_t *vin;     /* nvin: the input vertex each vertex is (its 0-based number in the
                       * input) or -1; NULL: found by coordinates (a part that holds the input's
                       * vertices in input order first is recognised without a search) */
    int32_t *vmarker; /* nverts (may be NULL) */
    int nattr;
    double *vattr; /* nattr * nverts (may be NULL) */
    int32_t ntris;
    int32_t *tri;   /* 3 * ntris, counter-clockwise, 0-based */
    int32_t *trank; /* ntris owning rank (may be NULL: all 0) */
    double *tattr;  /* ntris regional attribute (-A; may be NULL: not asked).  Written as the
                     * .ele's one attribute column (in place of trank) and as VTK cell data */
    int32_t nsegs;
    int32_t *seg;        /* 2 * nsegs subsegment endpoints */
    int32_t *smarker;    /* nsegs (may be NULL) */
    int32_t *sinterface; /* nsegs: 1 if an artificial (interface) constraint (may be NULL) */
    int scale_exp;       /* xy holds the true coordinates times 2^scale_exp (pslg_check's scaling);
                          * the writers undo it exactly.  0 for meshes read from files. */
    /* the input's holes and regions, written into the .poly so that meshing it again meshes the
     * same domain (Triangle does the same); scaled like xy (region areas by 2^(2 scale_exp));
     * may be 0 / NULL (meshio_flat_domain fills them) */
    int32_t nholes, nregions;
    double *holes;   /* 2 * nholes */
    double *regions; /* 4 * nregions: x, y, attribute, maximum area */
} mesh_flat;

/* Triangle t's hash for the mesh hash (a sum of these mod 2^64 over every triangle): its
 * vertices' coordinate bits, starting at the smallest (x, y) and kept counter-clockwise, so the
 * sum is independent of numbering and of how the triangles are split among parts.  Local, pure. */
static inline uint64_t meshio_tri_hash(const mesh_flat *f, int64_t t) {
    const int32_t *v = f->tri + 3 * (size_t)t;
    int first = 0;
    for (int i = 1; i < 3; i++) {
        const double *p = f->xy + 2 * (size_t)v[i], *q = f->xy + 2 * (size_t)v[first];
        if (p[0] < q[0] || (p[0] == q[0] && p[1] < q[1])) first = i;
    }
    uint64_t h = 0x243f6a8885a308d3ULL;
    for (int i = 0; i < 3; i++) {
        const double *p = f->xy + 2 * (size_t)v[(first + i) % 3];
        h = mesh_hash64(h ^ mesh_dbits(p[0]));
        h = mesh_hash64(h ^ (mesh_dbits(p[1]) * 0x9e3779b97f4a7c15ULL));
    }
    return h;
}

struct pslg;

/* Copies g's holes and regions (pslg_check's scaled values) into m.  Returns 0 (it cannot
 * fail: the int is kept for callers that test it). */
int meshio_flat_domain(mesh_flat *m, const struct pslg *g);

/* The end of a .poly: the holes section and, when there are regions, the regions section
 * (coordinates divided by 2^scale_exp, areas by 2^(2 scale_exp)), formatted at q, which has
 * room for meshio_domain_maxlen bytes; returns the new end.  The sequential and the parallel
 * .poly writers both end with it. */
char *meshio_fmt_domain(char *q, int32_t nholes, const double *holes, int32_t nregions,
                        const double *regions, int scale_exp);
size_t meshio_domain_maxlen(int32_t nholes, int32_t nregions);

/* Writes PREFIX.node, PREFIX.ele and PREFIX.poly (1-based, as Triangle writes them; the .poly
 * lists the segments but not the interface ones (sinterface), then m's holes and regions). */
int meshio_write_triangle(const mesh_flat *m, const char *prefix, char *err, size_t errlen);

/* The Triangle files a writer may leave out (Triangle's -N, -E, -P), or-ed together. */
enum { MESHIO_SKIP_NODE = 1, MESHIO_SKIP_ELE = 2, MESHIO_SKIP_POLY = 4, MESHIO_SKIP_ALL = 7 };

/* meshio_write_triangle without the files skip names (MESHIO_SKIP_ALL: writes nothing). */
struct meshio_set;
int meshio_write_triangle_some(const mesh_flat *m, struct meshio_set *set, const char *prefix,
                               unsigned skip, char *err, size_t errlen);

/* Reads PREFIX.node and PREFIX.ele (and PREFIX.poly when present: segments, holes, regions)
 * back into m.  The .ele's first attribute goes into tattr (and into trank too when every value
 * is a non-negative integer). */
int meshio_read_triangle(const char *prefix, mesh_flat *m, char *err, size_t errlen);

/* Reads the mesh to refine (-r NAME; NAME, NAME.node or NAME.ele) into g as a PSLG (meshin.c;
 * *g zeroed first; on failure it holds nothing): the mesh's vertices (attributes and markers
 * included) are the PSLG's vertices, so the refined mesh keeps every one of them.  Segments and
 * holes come from NAME.poly when it exists (0 vertices, as Triangle and these meshers write
 * it); otherwise the mesh's boundary edges become segments (marker 1), and a hole point is put
 * just outside every chain of boundary edges (at the midpoint of one of its edges, moved away
 * from the triangle inside; kept only if it is, by exact tests, on the outer side of the edge
 * and in no triangle of the mesh), so the holes of the old mesh stay holes.  Returns 0, or -1
 * with "FILE:LINE: problem" in err. */
int meshio_read_mesh_pslg(const char *name, struct pslg *g, char *err, size_t errlen);

/* Local.  The boundary of m (counter-clockwise triangles: meshio_flat_orient_ccw) as the
 * segments of g (marker 1; g must have no segments or holes yet: they are set) with a
 * hole point beside every chain of boundary edges, as meshio_read_mesh_pslg makes them when
 * there is no NAME.poly (the -r of arrays: the Python package).  Returns 0, or -1 (too many
 * triangles to index). */
int meshio_boundary_pslg(const mesh_flat *m, struct pslg *g);

/* NAME without a trailing .node, .ele, .poly or .area into out (n bytes).  Returns 0, or -1
 * with a message in err when it does not fit. */
int meshio_mesh_prefix(const char *name, char *out, size_t n, char *err, size_t errlen);

/* Makes every non-degenerate triangle of m counter-clockwise (files may list either). */
void meshio_flat_orient_ccw(mesh_flat *m);

/* Legacy VTK unstructured grid, with the rank (and with tattr the regional attribute,
 * "region_attr") as cell scalars and the boundary marker as a point scalar.  binary: the format's
 * BINARY encoding (big-endian doubles and 32-bit ints, as VTK, ParaView and meshio read it; 12
 * bytes of text per number fewer, and no formatting); else ASCII (coordinates in the fewest digits
 * that read back to the same bits). */
int meshio_write_vtk(const mesh_flat *m, struct meshio_set *set, int binary, const char *path,
                     char *err, size_t errlen);

/* SVG picture: triangles filled by owning rank, constraint edges drawn thick, interface
 * constraints in a contrasting colour. */
int meshio_write_svg(const mesh_flat *m, struct meshio_set *set, const char *path, char *err,
                     size_t errlen);

void mesh_flat_free(mesh_flat *m);

#endif
