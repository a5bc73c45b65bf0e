/* pwrite: writing a distributed mesh without gathering it (design.md "output").
 *
 * Each rank holds a part of the mesh in global numbering and writes that part itself:
 *  - Triangle's PREFIX.node/.ele/.poly as single files, written collectively with MPI-IO: each
 *    rank formats its lines chunk by chunk and writes them at the byte offset an MPI_Exscan of
 *    the byte counts gives.  Ranks write in rank order, so a rank's vertices (and triangles and
 *    segments) must carry consecutive global numbers, rank 0's first: vertex i of rank r is
 *    number (sum of nverts of ranks < r) + i.  The bytes are the same as meshio_write_triangle
 *    writes for the gathered mesh.
 *  - ParaView's PREFIX.pvtu: one XML piece PREFIX_R.vtu per rank (binary appended data or
 *    ASCII), with the rank and the subdomain as cell data and the boundary marker as point data.
 * Every file appears whole or not at all: the data goes to a temporary name and rank 0 renames
 * it only after every rank reports success -- or, given an output set (oset.h; NULL: none),
 * leaves it in the set, which the caller commits with the run's other files
 * (meshio_pset_commit).
 *
 * The Collective functions (over comm) return the same status on every rank: 0, or -1
 * with the message (of the first rank that failed) in err on every rank.
 */
#ifndef MESH_IO_PWRITE_H
#define MESH_IO_PWRITE_H

#include <mpi.h>
#include <stddef.h>
#include <stdint.h>

#include "io/meshio.h"

/* One rank's part of a distributed mesh, in global 0-based numbering.  Arrays are borrowed.
 * Vertices: the first nhead come from the head arrays (e.g. the input's vertices, which rank 0
 * writes), the other nverts - nhead from xy/vmarker/vattr, picked through vsel (or in order).
 * Triangles: global numbers in tri, or (tri NULL) local vertex ids in ltri mapped through gid;
 * so the writer never needs a global copy of the part. */
typedef struct mesh_part {
    int64_t nverts;          /* vertices this rank writes, head included (numbers: see above) */
    int64_t nhead;           /* head vertices (0: none) */
    const double *hxy;       /* 2 * nhead */
    const int32_t *hvmarker; /* nhead (NULL: all 0) */
    const double *hvattr;    /* nattr * nhead (NULL: all 0) */
    const double *xy;        /* 2 * (local vertices) */
    const int32_t *vmarker;  /* per local vertex (NULL: all 0) */
    const int32_t *vsel;     /* nverts - nhead local ids (NULL: 0, 1, 2, ...) */
    int nattr;               /* vertex attributes per vertex (same on every rank) */
    const double *vattr;     /* nattr per local vertex (NULL when nattr == 0) */
    int64_t ntris;
    const int64_t *tri;   /* 3 * ntris global vertex numbers, counter-clockwise; or NULL: */
    const int32_t *ltri;  /* 3 * ntris local vertex ids ... */
    const int64_t *gid;   /* ... and each local vertex's global number */
    int64_t nlocal;       /* entries of gid (0: unknown; then the writer caches no numbers) */
    const int32_t *trank; /* ntris triangle attribute (NULL: none; same choice on every rank) */
    const double *tattr;  /* ntris regional attributes (-A), written in trank's place (NULL:
                           * none; same choice on every rank) */
    int64_t nsegs;
    const int64_t *seg;       /* 2 * nsegs global vertex numbers */
    const int32_t *smarker;   /* nsegs (NULL: all 0) */
    int32_t nholes, nregions; /* the .poly's holes and regions sections (meshio_fmt_domain; */
    const double *holes;      /* scaled like xy; the last rank writes them) */
    const double *regions;
    int scale_exp; /* xy holds the true coordinates times 2^scale_exp (pslg.scale_exp: an input
                    * pslg_check scaled); the writer undoes it exactly, head vertices included.
                    * 0: unscaled */
    size_t keep;   /* bytes of .node text pass 1 may format ahead and keep for pass 2 (beyond
                    * one chunk), saving their second formatting; 0: one chunk */
    unsigned skip; /* MESHIO_SKIP_* (io/meshio.h): files not written (the same on every rank) */
    int threads;   /* threads that format this rank's text (0/1: the calling thread alone);
                    * the bytes are the same for any count.  Only the calling thread calls MPI */
} mesh_part;

/* Collective.  Writes PREFIX.node, PREFIX.ele and PREFIX.poly from every rank's part.  Memory:
 * one chunk per file plus p->keep bytes per rank (and, with ltri and nlocal, 9 bytes per local
 * vertex: its number's digits, formatted once), never the part's whole text: each rank first
 * counts its bytes (formatting and keeping its first chunk of each file and keep bytes more of
 * the .node text, counting the rest), an MPI_Exscan gives its offsets, then it writes what it
 * kept and formats and writes the rest chunk after chunk (independent MPI_File_write_at), rank
 * r starting with file r mod 3 so that ranks fill different files at once. */
int meshio_pwrite_triangle(MPI_Comm comm, struct meshio_set *set, const mesh_part *p,
                           const char *prefix, char *err, size_t errlen);

/* Local.  Sets the writers' chunk size in bytes (0: the default, 1 MiB); tests shrink it so
 * that every path of the chunked writers runs on small meshes. */
void meshio_pwrite_set_chunk(size_t bytes);

/* Local.  Writes one VTK XML unstructured grid (.vtu) of m: points, triangles, cell data "rank"
 * (m->trank, or all `rank`) and "subdomain" (tsub, ntris entries, when not NULL), point data
 * "marker".  binary: raw appended data (little-endian, UInt64 headers); else ASCII.  Written
 * in chunks (no copy of the mesh). */
int meshio_write_vtu(const mesh_flat *m, struct meshio_set *set, int rank, const int32_t *tsub,
                     int binary, const char *path, char *err, size_t errlen);

/* Collective.  Each rank writes its local mesh as PREFIX_R.vtu (R = its rank in comm) and rank
 * 0 writes PREFIX.pvtu naming every piece (file names relative to the .pvtu's folder).  tsub:
 * as meshio_write_vtu; NULL or not on every rank alike. */
int meshio_pwrite_pvtu(MPI_Comm comm, struct meshio_set *set, const mesh_flat *local,
                       const int32_t *tsub, int binary, const char *prefix, char *err,
                       size_t errlen);

#endif
