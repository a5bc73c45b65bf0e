/* pbw_local.c: the local fast path of a Steiner point -- the shared kernel's Bowyer-Watson
 * insertion (seq/mesh.c: mesh_cavity_collect, mesh_cavity_commit, the code ./mesh runs), on
 * this rank's part of the mesh, without the travelling cavity state.
 *
 * Most cavities (over 90% at 8 ranks, all on one rank) touch only this rank's unlocked
 * triangles.  For those the general protocol (pbw_cavity.c: seeds, reserved slots, boundary
 * records, the fan built through hash maps, then applied as a commit) is bookkeeping that
 * decides nothing.  Here the kernel collects the cavity depth-first from the bad triangle (a
 * neighbour is a member iff p lies strictly in its circumcircle, exact incircle; never across a
 * constraint edge), checks it star-shaped (exact orient2d) and stops at anything that is not
 * purely local: a slot with a role (locked by a distributed cavity, reserved, a tombstone: the
 * role lives in tf's MESH_FENCE bits) or an edge to another rank (tn below -1, a record), as
 * member or neighbour (CAV_FENCED); a member reached twice (the cavity encloses a vertex:
 * CAV_CYCLE).  Here p must also encroach no subsegment on the boundary (PBW splits those
 * first, as the general path decides).  Then the kernel writes the fan over the members'
 * slots; the new triangles keep the boundary edges' links, constraint bits and regions.
 *
 * Anything else goes to the general path, which decides it exactly as before.  Nothing is
 * written before that decision, and the kernel's marks are cleared (mesh_cavity_abort), so
 * falling back costs only the search.
 *
 * A subsegment split takes the same path (pbw_local_split): the kernel's cavity opened across
 * the subsegment (both triangles on it join, as refine.c splits), the halves named as the general
 * path names them (dyadic level and index, or none past a shell split).  The far side's
 * off-line test (mesh_rules_off_line_fan with its apex, CYC_OFF_LINE) is asked here as its owner
 * would; a point that fails it, or any cavity that is not purely local and star-shaped, goes to
 * the general path, which fails or distributes it as before.  (Measured: on Great Britain's
 * coastline at 2 ranks a rank made 3,806 splits, each a general cavity of about 9,000
 * instructions.)
 */
#include "pbw/pbw_impl.h"

int pbw_local_insert(pbw_ctx *C, const double p[2], int32_t t) {
    mesh *m = &C->M;
    C->fast_fenced = 1;
    if (m->tf[t] & MESH_FENCE) return 0; /* locked (a locked slot has a role) */
    int st = mesh_cavity_collect(m, p, t, -1, NULL);
    C->fast_fenced = st == CAV_FENCED;
    for (int32_t i = 0; st == CAV_OK && i < m->nbnd; i++) {
        const mesh_bedge *b = &m->bnd[i];
        if (b->cons && mesh_rules_encroaches(&C->R, VX(C, b->org), VX(C, b->dest), p))
            st = CAV_NOT_STAR;
    }
    if (st != CAV_OK) {
        mesh_cavity_abort(m);
        return 0;
    }
    int64_t pgid = ((int64_t)(C->rank + 1) << 32) | C->nvown;
    int32_t pv = pbw_vt_add(C, pgid, p[0], p[1], -1);
    C->nvown++;
    C->res.steiner++;
    int32_t nm = m->ncav;
    mesh_cavity_commit(m, pv, -1, -1);
    C->nlive += m->nnewt - nm;
    C->res.cavities_local++;
    C->res.inserted++;
    for (int32_t i = 0; i < m->nnewt; i++)
        pbw_check_new_triangle(C, m->newt[i]);
    return 1;
}

int pbw_local_split(pbw_ctx *C, const double p[2], int32_t t, int j, int32_t sseg, int32_t clev,
                    int64_t ka, int64_t kb) {
    mesh *m = &C->M;
    if (m->tf[t] & MESH_FENCE) return 0; /* locked */
    int32_t e = 3 * t + j, la = m->tv[e], lb = m->tv[mesh_edge_next(e)];
    int32_t f = m->tn[e];
    if (f < -1) return 0; /* the far side is another rank's */
    if (f >= 0) {         /* the far side's off-line test, with its apex (as its owner would) */
        const int32_t *tx = m->tv + 3 * (size_t)(f / 3);
        int jf = f % 3;
        if (mesh_rules_off_line_fan(VX(C, tx[jf]), VX(C, tx[(jf + 1) % 3]), p,
                                    VX(C, tx[(jf + 2) % 3]), NULL))
            return 0;
    }
    if (mesh_cavity_collect(m, p, t, e, NULL) != CAV_OK) {
        mesh_cavity_abort(m);
        return 0;
    }
    int64_t pgid = ((int64_t)(C->rank + 1) << 32) | C->nvown;
    int32_t pv = pbw_vt_add(C, pgid, p[0], p[1], sseg);
    C->nvown++;
    C->res.steiner++;
    int32_t nm = m->ncav;
    mesh_cavity_commit(m, pv, la, lb);
    /* the halves' names: the old pair never forms an edge again */
    int32_t r = mesh_ss_find_pair(m, la, lb);
    if (r >= 0) mesh_ss_del(m, r);
    mesh_ss_add(m, la, pv, sseg, clev, clev < 0 ? 0 : ka);
    mesh_ss_add(m, pv, lb, sseg, clev, clev < 0 ? 0 : kb);
    C->nlive += m->nnewt - nm;
    C->res.cavities_local++;
    C->res.splits++;
    for (int32_t i = 0; i < m->nnewt; i++)
        pbw_check_new_triangle(C, m->newt[i]);
    return 1;
}
