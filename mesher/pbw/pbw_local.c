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
