/* xwrite: the derived outputs of a mesh -- Triangle's .edge and .neigh (-e, -n), quadratic
 * triangles (-o2: .node/.ele with the edge midpoints as extra nodes, VTK cell type 22), and Gmsh
 * MSH 4.1 ASCII with physical groups -- for one process (./mesh) or for one rank's part of a
 * distributed mesh (par/pextra.c fills the cross-rank fields, then calls the same writers).
 *
 * A mesh_xview is one rank's part (a mesh_flat in local numbering) with its global numbering
 * and its edge topology: half-edge 3t+j is the edge of triangle t opposite its corner j (from
 * tri[3t+(j+1)%3] to tri[3t+(j+2)%3]), as Triangle numbers neighbours ("neighbour j is opposite
 * corner j") and -o2 midpoints ("node 3+j is the midpoint of the edge opposite corner j").  Edge
 * markers follow Triangle's convention: an edge on an input segment carries the segment's
 * marker when it is not 0; otherwise an edge on the boundary of the mesh gets 1, any other 0.
 * Every edge is written once: an interior edge of the part by this rank, an edge between two
 * ranks by the lower.  The midpoint of edge number e (0-based) is node nvtot + e.
 *
 * Gmsh: triangles are grouped into physical surfaces by regional attribute (f->tattr; without
 * it one surface "domain"), the line elements (every edge on an input segment or on the mesh
 * boundary) into physical curves by marker, one elementary entity per physical group.  All
 * nodes sit in surface entity 1.  In parallel the file is one, written collectively (each rank
 * writes its own node and element blocks), which gmsh and meshio read as any other.
 */
#ifndef MESH_IO_XWRITE_H
#define MESH_IO_XWRITE_H

#include <stddef.h>
#include <stdint.h>

#include "io/meshio.h"
#include "io/text.h"

/* Edge flags (mesh_xview.eflag). */
enum {
    XE_WRITE = 1, /* this rank writes the edge (and numbers its midpoint) */
    XE_LINE = 2,  /* a Gmsh line element: on an input segment or on the mesh boundary */
    XE_OPEN = 4,  /* an edge of one local triangle */
    XE_BOUND = 8, /* on the mesh boundary (open, and no other rank has it) */
    XE_SEG = 16,  /* on an input segment */
    XE_OTHER = 32 /* written by another rank (mesh_xview_set_remote; cleared by finish) */
};

typedef struct mesh_xview {
    /* the part and its numbering (borrowed) */
    const mesh_flat *f;
    const uint8_t *artificial;   /* f->nsegs: 1 = not an input constraint (NULL: none) */
    const int64_t *gid;          /* per local vertex its 0-based number (NULL: the local id) */
    int64_t nvtot, ttot, tfirst; /* vertices and triangles (all ranks); this rank's first */
    /* the vertices this rank writes, numbers vfirst, vfirst + 1, ...: nhead head vertices (hxy,
     * hvmarker; in the working scale like f->xy) then nsel local ones (vsel, NULL: 0, 1, ...) */
    int64_t vfirst, nhead, nsel;
    const double *hxy;
    const int32_t *hvmarker;
    const int32_t *vsel;
    int nattr;    /* vertex attributes written (f->vattr; 0 when the head has none) */
    int ele_attr; /* the -o2 .ele's triangle attribute: 0 none, 1 f->tattr (the regional
                   * attribute, -A; the same on every rank; a rank without the array writes 0) */
    /* edge topology (owned; mesh_xview_topo) */
    int32_t *nb;   /* 3 * ntris: the local triangle across half-edge h; -1: none (mesh
                    * boundary); -2 - k: another rank's triangle number otri[k] */
    int64_t *otri; /* notri triangle numbers across rank interfaces */
    int32_t notri, cap_otri;
    int32_t *eid;     /* 3 * ntris: the local edge of half-edge h */
    int32_t ne;       /* local edges */
    int32_t *ehe;     /* ne: a half-edge of each edge (the one of the lowest triangle) */
    int32_t *emark;   /* ne: marker */
    uint8_t *eflag;   /* ne: XE_* */
    int64_t *egid;    /* ne: the edge's global number (-1 until known) */
    int32_t nwe, nwl; /* edges / line elements this rank writes */
    int32_t *we, *wl; /* their local ids, in number order */
    int64_t etot, efirst, ltot, lfirst; /* edges, line elements: all ranks, this rank's first */
    /* Gmsh groups (the same on every rank; mesh_xview_groups) */
    int32_t ncurve, nsurf;
    int32_t *curve_mark;    /* ncurve sorted markers */
    double *surf_attr;      /* nsurf sorted attributes (nsurf == 1 and NULL: no attributes) */
    int32_t *lperm, *tperm; /* written lines / triangles sorted by group */
    int32_t nlblk, ntblk;   /* this rank's element blocks */
    int64_t blocks_tot, nodeblocks_tot; /* element and node blocks in the file (all ranks) */
    double bbox[4];                     /* xmin ymin xmax ymax of the mesh (true scale) */
} mesh_xview;

/* Local.  Sets x to the part f (borrowed) and builds its edge topology: local neighbours, local
 * edges, which are open, which lie on an input segment (f's segments not flagged in artificial)
 * and their markers.  Every open edge is taken as mesh boundary (XE_BOUND) until
 * mesh_xview_set_remote says otherwise.  The numbering fields are left for the caller. */
void mesh_xview_topo(mesh_xview *x, const mesh_flat *f, const uint8_t *artificial);

/* Local.  The global number of the triangle across half-edge h, or -1 (mesh boundary). */
static inline int64_t mesh_xview_neighbour(const mesh_xview *x, int32_t h) {
    int32_t n = x->nb[h];
    return n >= 0 ? x->tfirst + n : n == -1 ? -1 : x->otri[-2 - n];
}

/* Local.  Half-edge h (open) lies against rank orank's triangle number gtri: not mesh boundary,
 * neighbour gtri, written here only when rank < orank. */
void mesh_xview_set_remote(mesh_xview *x, int32_t h, int rank, int orank, int64_t gtri);

/* Local.  After the remote sides are known: markers, XE_WRITE / XE_LINE, the lists we and wl
 * (local edge order), egid of the written edges from x->efirst (a caller that learns its
 * efirst later renumbers them: egid[we[k]] = efirst + k). */
void mesh_xview_finish(mesh_xview *x);

/* Local.  Gmsh groups from the (sorted, distinct) markers and attributes of every rank (attrs
 * NULL: one surface); sorts this rank's lines and triangles by group and counts its blocks. */
void mesh_xview_groups(mesh_xview *x, const int32_t *marks, int32_t nmarks, const double *attrs,
                       int32_t nattrs);

/* Local.  This rank's distinct line markers (*nm) and triangle attributes (*na, 0 without
 * tattr), sorted, as new arrays (free with free()). */
void mesh_xview_local_groups(const mesh_xview *x, int32_t **marks, int32_t *nm, double **attrs,
                             int32_t *na);

/* Local.  Frees what x owns. */
void mesh_xview_free(mesh_xview *x);

/* What to write (paths NULL: not). */
typedef struct mesh_xreq {
    const char *prefix; /* PREFIX.edge / .neigh / (-o2) .node .ele */
    int edges, neighbors, order2;
    const char *msh; /* Gmsh 4.1 */
    const char *vtk; /* quadratic legacy VTK (order2 only) */
    unsigned skip;   /* -o2: MESHIO_SKIP_NODE / _ELE leave that file out (Triangle's -N, -E) */
    struct meshio_set *set; /* the run's output set (io/oset.h; NULL: each file renamed at once) */
} mesh_xreq;

/* out == NULL: Local (x is the whole mesh, one process writes); else Collective over out's
 * writers (io/ptext.h's meshio_ptext_out) with every field of x filled.  Writes what r asks;
 * returns 0, or -1 with "FILE: problem" in err (on every rank). */
int mesh_xview_write(const mesh_xview *x, const mesh_text_out *out, const mesh_xreq *r, char *err,
                     size_t errlen);

/* Local.  The whole of ./mesh's part: builds the view of m (sequential numbering), writes what
 * r asks.  Returns 0, or -1 with err. */
int meshio_write_extras(const mesh_flat *m, const mesh_xreq *r, char *err, size_t errlen);

#endif
