/* mesh_impl: declarations internal to mesher/seq/ (mesh*.c, cdt.c, refine.c), beyond the
 * kernel interface (kernel.h) the layers above use.  See mesh.h for the data structure. */
#ifndef MESH_IMPL_H
#define MESH_IMPL_H

#include "base/base.h"
#include "geom/geom.h"
#include "seq/kernel.h"
#include "seq/mesh.h"

#include <stdio.h>
#include <stdlib.h>

/* Index (0..2) of the ghost vertex of t, or -1. */
static inline int mesh_ghost_index(const mesh *m, int32_t t) {
    const int32_t *v = m->tv + 3 * (size_t)t;
    return v[0] == MESH_GHOST ? 0 : v[1] == MESH_GHOST ? 1 : v[2] == MESH_GHOST ? 2 : -1;
}

/* The debug tier's test of live triangle t (MESH_ASSERT; mesh.h's invariants): every
 * neighbour link is an involution (tn[tn[e]] == e) onto a live triangle's edge with the same
 * endpoints reversed and the same constraint bit, and t is counter-clockwise (exact orient2d)
 * unless it is a ghost.  Links below 0 (the boundary, a caller's fence) are not followed. */
static inline int mesh_tri_consistent(const mesh *m, int32_t t) {
    for (int j = 0; j < 3; j++) {
        int32_t e = 3 * t + j, f = m->tn[e];
        if (f < 0) continue;
        if (m->tn[f] != e || !mesh_tri_alive(m, f / 3)) return 0;
        if (m->tv[f] != mesh_dest(m, e) || mesh_dest(m, f) != m->tv[e]) return 0;
        if (mesh_edge_constrained(m, e) != mesh_edge_constrained(m, f)) return 0;
    }
    const int32_t *v = m->tv + 3 * (size_t)t;
    return mesh_ghost_index(m, t) >= 0 ||
           geom_orient2d(m->xy + 2 * v[0], m->xy + 2 * v[1], m->xy + 2 * v[2]) > 0;
}

/* 1 iff every live triangle of m is mesh_tri_consistent (the debug tier, after a whole build;
 * O(triangles)). */
int mesh_consistent(const mesh *m);

uint64_t mesh_rand(mesh *m);

int mesh_tri_is_ghost(const mesh *m, int32_t t);

/* Walk toward p from triangle t.  avoid_constraints: 0 = plain walk (ghost triangles allowed:
 * returns a ghost whose outer half-plane holds p when p is outside the hull); 1 = never cross
 * a constraint edge: returns -1 and sets *blocked to a constraint edge code of the last
 * triangle with p strictly beyond it when every way forward is a constraint. */
int32_t mesh_walk(mesh *m, const double p[2], int32_t t, int avoid_constraints, int32_t *blocked);

void mesh_set_constrained(mesh *m, int32_t e);

/* subsegment side table (mesh_subseg.c; mesh_ss_add, _del, _find_pair: kernel.h) */
int32_t mesh_ss_find_name(const mesh *m, int32_t seg, int32_t level, int64_t k);
void mesh_ss_prune(mesh *m); /* drops records whose edge is no longer in the mesh */

#endif
