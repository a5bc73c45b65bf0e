/* pbw.c: the Parallel Meshing Algorithm (TR-97-17 section 2; Chrisochoides and Sukup 1996):
 * parallel Bowyer-Watson Delaunay refinement of one distributed mesh, data-centric and
 * task-parallel, with remote cavity expansion, locking and undo.
 *
 * MESH.  Every rank builds the same CDT of the input (with an area bound, refined identically
 * on every rank by the sequential refiner, by area only, where the subdomain interfaces run to
 * the size of about 4096 triangles per rank but at least 64 times coarser than the bound, so
 * that every rank owns a piece, and 16 times coarser away from them) and keeps the
 * triangles whose centroid lies in one of its subdomains (the decomposition only distributes the
 * initial mesh; no artificial constraint exists).  A triangle lives in a slot of its owner, and a
 * rank's triangles are the sequential kernel's mesh (seq/mesh.h: the slot numbering of that CDT, so
 * every rank names a triangle alike; links between local triangles are the kernel's edge
 * codes); a neighbour on another rank is named by a packed (rank, slot) reference kept in a
 * side table of edge records, with its ghost (GHOSTS below).  A vertex has a global id: input
 * vertex i is i, the n-th vertex created by rank r is ((r + 1) << 32) | n.  Each rank keeps the
 * coordinates of every vertex its triangles use, so every predicate sees identical doubles on every
 * rank. Constraint edges (subsegments of input segments) carry (segment, dyadic level, index) on
 * both sides.
 *
 * CAVITY (one per Steiner point p).  The owner of a bad triangle t (or of a triangle on an
 * encroached subsegment) starts it: t is a member; every neighbour x of a member across a
 * non-constraint edge is a member iff p lies strictly in its circumcircle (exact incircle);
 * every other neighbour of a member (across a constraint, or not in conflict) is a halo
 * triangle.  Members and halos are locked by the cavity, whichever rank owns them, because a
 * commit deletes the members and rewrites one link of each halo -- except a ghost (GHOSTS
 * below).  A boundary edge of the cavity (member | non-member, or a constraint edge, or the
 * domain boundary) is reported by the rank owning the outside triangle (or the member when
 * there is none or it is a ghost); that rank reserves a slot for the new triangle (a, b, p) on
 * it, so the OWNERSHIP RULE is: the new triangle on a cavity boundary edge belongs to the owner
 * of the triangle on the other side of that edge (the member's owner on the domain boundary
 * and across a ghost).  (Measured, issue 13: giving the new triangles to the starter instead
 * makes the rank boundary twice as long and the RSRs 1.5 times as many; giving them all to the
 * member's owner, 15% longer and 15% more.)  The reporter also evaluates, exactly, whether p
 * is strictly left of the edge (star-shapedness) and whether p encroaches a constraint edge.
 * The members must form a disk with every vertex on its boundary (their dual graph a tree):
 * a member reached a second time across a non-constraint edge means the cavity encloses a
 * vertex (p nearly on it, where the mesh is not Delaunay), and the cavity fails, as
 * mesh_cavity_collect's CAV_CYCLE (the vertex would otherwise vanish from the mesh).
 *
 * MESSAGES.  A cavity that stays on its rank is done at once, with no message.  Otherwise the
 * starter spawns a task which sends the cavity state (header, participants, boundary edges,
 * pending seeds = remote triangles to visit) as an EXPAND request to the owner of the first
 * seed; each rank locks and grows what it owns and FORWARDS the state to the next rank with
 * pending seeds (the chains A->B->C of the paper's Table 1).  The task sits in the blocking
 * queue meanwhile, while its rank goes on with other work.  At most --inflight (default
 * MAX_INFLIGHT, 2) distributed cavities per rank are in flight: more hide latency but conflict
 * with each other (at 16, half of the remote attempts died and the RSRs doubled; measured,
 * issue 13); a further one waits in the slot queue, taken again when a slot is free.
 * THE END GAME.  With a slot's round trip waiting for the other rank to be scheduled (many
 * ranks per core), most cross-rank cavities wait in the slot queue until the rank's own work
 * is done (at 8 ranks on 2 cores, lake 10M: 2,000-4,900 per rank, three quarters of them), and
 * the rank then spent 20-25% of its CPU on them, two at a time, a poll, a sleep and a context
 * switch per round trip.  So once a rank has no bad triangle and no split of its own left, if
 * at least ENDGAME_MIN_WAITING (512) cavities wait, it shuffles them and keeps ENDGAME_FACTOR
 * (8) times --inflight in flight (latched for the rest of the run; not with --phases, the
 * paper's variant as it was).  The queue holds them in the order they were found, and the
 * refinement order (last in, first out) finds neighbours one after the other, so taken in that
 * order the cavities in flight lie close together and kill each other; shuffled, they lie apart
 * along the rank boundary.  Measured (that case, 4 runs alternating, medians): cpu_max 0.395 s
 * with two slots, 0.366 s with 8 (in order; the first end game, 12 and 16 measured no better),
 * 0.351 s with 8 shuffled and 0.348 s with 16 shuffled against 0.366 s with 8 in order in the
 * same run; undone cavities 6,500 (in order) -> 3,000 (8 shuffled) -> 4,600 (16 shuffled), of
 * 5M (most die at their first, local step, which costs no message); RSRs unchanged at 16
 * shuffled, +5% at 32 with 15,000 undone.  A few cavities lie close together and conflict
 * whatever the order: at the paper's size (43K triangles, 8 ranks, 93-190 waiting per rank)
 * more slots raised the RSRs by 40% (replies and wakes of dead cavities); waiting per rank at 8
 * ranks was 680-1,500 at 1M, 1,900-8,200 at 10M and 540-4,100 on the coastline.
 * DECIDE.  The rank where the chain ends knows the whole cavity.  If it is not the starter and
 * the cavity commits (no conflict, star-shaped, no encroachment), it commits there and then:
 * its own part at once, and one COMMIT per other participant with the new triangles it owns
 * (links are fully resolved because every reserved slot is known); the starter's COMMIT is the
 * reply that wakes its task.  So a cavity spanning two ranks costs two messages, EXPAND and
 * COMMIT.  Otherwise the chain REPLIES to the task, which decides: COMMIT, or RELEASE
 * everywhere (undo, after a conflict; or reject: p encroaches a subsegment, which is then split
 * by a SPLIT request to the owner of the triangle on it; the bad triangle is retried after the
 * split's WAKE).
 * Nothing is written until every triangle is locked, so undo is only a release of locks
 * (and the wasted expansion time, which goes to RT_TIME_UNDO).  Locks are held until the
 * owner applies the commit, so nobody follows a link that is being rewritten; a link to a slot
 * reserved by a cavity whose commit has not arrived yet finds that slot locked.
 *
 * GHOSTS (issue 13).  Of the two triangles on a rank boundary edge, the one on the pair's
 * GHOST SIDE (one of the two ranks, the same for all their edges: pbw_ghosts.c) keeps a ghost
 * of the other: its apex (gx, a vertex slot; the edge's vertices are its own), set by the
 * initial distribution and by every commit that makes such an edge (the apex of each new
 * triangle's neighbours is known from the cavity's boundary).  When a cavity's member x on
 * rank A has a neighbour n on rank B with a ghost, A the ghost side of (A, B), A decides n on
 * the ghost, exactly as B would (incircle; across a constraint no test): n in conflict is
 * visited (locked) as before; otherwise n is NOT locked -- A reports the edge itself, with
 * the new triangle T on A, so a cavity whose remote neighbours are all unconflicted stays local.
 * Its commit writes T's link to n and makes x a TOMBSTONE (dead, never reused, keeping across that
 * edge a forward link to T); B is not told (n keeps its link to x), so a ghost commit sends nothing
 * at all. Why the ghost is exact: n only dies in a cavity that has n as a member, expanded on B; B
 * is not the ghost side, so B never uses a ghost of A's side: it locks the triangle across (x, or T
 * through the tombstones), and that cavity's commit rewrites A's link (and ghost) before the
 * lock is released; so while A's triangle is unlocked and links n, n is alive and unchanged.
 * (Both sides deciding on ghosts at once could leave a non-Delaunay edge between the two new
 * fans: hence one ghost side per pair of ranks.  Which side it is moves load: see
 * pbw_ghosts.c.)  Why the stale link is harmless: n links the tombstone x until
 * a cavity of B's rewrites it; an expansion that follows it arrives at A, as it would with a
 * fresh link (x and T are both A's), and A follows the forward links to the live triangle on
 * that edge (pbw_resolve_tomb) and goes on from there; if that triangle is the one the
 * expansion came from (seed.back), the seed is the edge it came in through and is dropped.
 * Nothing else reads a remote link but the end's statistics, which need only its rank.  A
 * chain grows by one each time A replaces the triangle on that edge by a ghost commit, a few
 * local hops at most.  (Measured, issue 13: a one-way LINK message that pointed n at T saved
 * nothing but those hops and was 9-10% of PBW's RSRs at 8 ranks on the Tables 2/3 and 1M
 * runs; without it the CPU time did not change.)
 *
 * CONFLICTS AND PROGRESS (wait-die).  Each cavity has a priority stamp (Lamport clock, rank),
 * kept across retries of the same work item; smaller = older.  When an expansion meets a
 * triangle locked by another cavity D: a cavity that has sent nothing yet (its starter's
 * first, local step) just lets go and is retried later; a distributed cavity C older than D
 * PARKS at that rank (its state waits there, holding its locks) and is resumed, oldest first,
 * the moment D's locks on that rank are released; a C younger than D DIES: it is released on
 * every rank and its work item (keeping its stamp) is deferred until the rank where it died
 * sends a WAKE naming D (D released there; a WAKE that overtakes the task is remembered), or D
 * releases on the starter's own rank.  A cavity rejected for encroachment waits for WAKEs from
 * the splits it asked for, and those splits carry a stamp just older than its own, so the
 * retried cavity can never starve the splits it depends on.
 * Progress: waits only go from older to younger cavities, so no cycle of waits (deadlock)
 * exists; the youngest cavity in any chain of waits is not waiting, so it commits or dies in
 * finite time and releases; hence the oldest cavity holding locks never dies and eventually
 * acquires every triangle it needs (a parked request is served before any newer work on that
 * rank) and finishes.  So while work remains, some cavity commits: no livelock.  Cavities
 * that stay on one rank run to completion in one step and hold nothing across steps.  No
 * rank spins: a deferred item waits for a wake (an RSR) or a local release, and the runtime's
 * termination detector sees a blocked task wherever a cavity is still in flight.
 *
 * RULES.  What is bad, the Steiner point (off-center), encroachment, the shell split point and
 * the forced small angle are seq/rules.h's, the same code ./mesh and ./pcdm run, and so is the
 * queue order (shortest edge first, last in first out inside a bucket).  As in refine.c: a
 * circumcenter (or off-center) that lies beyond or on a constraint edge of its cavity, or
 * encroaches one, is discarded and those subsegments are split; splits use the dyadic midpoint
 * of the original segment, or a concentric shell at a small input corner; skinny triangles
 * whose small angle is forced by such a corner are left alone (unless they exceed the area
 * bound).  TERMINATION (issue 10), as refine.c: no new edge shorter than the length floor of
 * the initial CDT; such a refusal drops the work item (a bad triangle whose split was refused
 * is not retried), and a rank whose refusals pass the budget stops refining; what is left
 * outside the bounds and not forced is counted at the end (pbw_result.unmet) and ./pbw fails.
 * --phases: phase 1 commits only cavities that stay on their rank, phase 2 the rest (the paper's
 * data-parallel variant, Figure 1 bottom). Env PBW_DEBUG=DIR: each rank writes its queue/lock state
 * to DIR/pbw.RANK.log every 2 s.
 *
 * FILES.  pbw.c (this overview and pbw_mesh, the driver), pbw_setup.c (the initial distributed
 * mesh; the end: bounds, output, freeing), pbw_store.c (global vertex ids, slots and links on
 * the kernel's mesh, edge records, the bad-triangle queue on the shared rules), pbw_items.c
 * (work items, deferral, locks), pbw_local.c (the local fast path: a cavity that stays on its
 * rank, inserted by the kernel's mesh_cavity_collect/commit, the code ./mesh runs),
 * pbw_cavity.c (expansion, commit, undo), pbw_proto.c (the RSR handlers, chains, parking, the
 * waiting task), pbw_work.c (rt_run's work step), pbw_check.c (the end check of the Delaunay
 * property where the protocol decided it: a defect fails every rank, nothing is written);
 * pbw_impl.h holds what they share.  The
 * context of one call, pbw_ctx, is passed to every function (no file-level global); the
 * handlers reach it through pbw_attach.  Unit tests without MPI: tests/unit_pbw.c.
 */
#include "pbw/pbw_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *const pbw_rsr_kind_name[PBW_RSR_NKINDS] = {"expansion", "reply", "release",
                                                       "commit",    "split", "wake"};

int pbw_mesh(const mesh_bounds *b, const par_config *c, const pslg *in, const pcdm_decomp *d,
             mesh_flat *local, pbw_result *res) {
    pbw_ctx *C = mesh_xcalloc(1, sizeof *C);
    mesh_init(&C->M); /* pbw_setup replaces it by the CDT */
    pbw_attach(C);    /* the handlers' way to the context */
    C->rank = rt_rank();
    C->size = rt_size();
    C->confree = -1;
    C->cursor = NBUCKET + 1;
    C->qhi = -1;
    /* the refining angle (bounds.h); the area bound in the working scale of the coordinates
     * (pslg_check), as refine.c takes it */
    double qa = b->refine_angle;
    if (qa > 60) qa = 60;
    bounds_rules(b, pslg_scaled_area(in->scale_exp, b->max_area), &C->R);
    C->poll_every = c->poll_every > 0 ? c->poll_every : WORK_BATCH;
    C->max_inflight = c->inflight > 0 ? c->inflight : MAX_INFLIGHT;
    C->endgame = c->phases ? -1 : 0; /* the paper's data-parallel variant as it was */
    C->steiner_limit = b->max_steiner >= 0 ? (b->max_steiner + C->size - 1) / C->size : -1;
    memset(local, 0, sizeof *local);
    char err[1024], msg[1200];
    err[0] = 0;
    const char *prog = c->prog ? c->prog : "pbw";
    pbw_setup_opts so = {qa, b->max_area, b->max_steiner, b->offcenter, c->regions, b->region_area};
    int rc = pbw_setup(C, &so, in, d, err, sizeof err);
    snprintf(msg, sizeof msg, "%s: %s", prog, err);
    if (par_fail_any(rc != 0, msg)) {
        pbw_detach();
        pbw_ctx_free(C);
        return -1;
    }
    if (c->phases) {
        double t0 = rt_wtime();
        C->phase1 = 1;
        rt_run(pbw_work, C);
        C->phase1 = 0;
        pbw_item it;
        while (pbw_iv_pop(&C->phase2, &it))
            pbw_iv_push(&C->retryq, &it);
        C->res.phase1_s = rt_wtime() - t0;
    }
    rt_run(pbw_work, C);
    if (C->npk != 0 || C->inflight != 0)
        MESH_BUG("%d parked, %d in flight at the end", C->npk, C->inflight);
    for (int32_t i = 0; i < C->nhd; i++)
        if (C->hd[i].active)
            MESH_BUG("cavity %llx still holds locks", (unsigned long long)C->hd[i].key);
    /* no work is left behind: a rank that stopped (Steiner limit, refusals past the budget)
     * dropped its items; any other item still queued or deferred waits for an event that
     * will never come (a lost WAKE, a hold never released) */
    int32_t left[6] = {C->deferred.n - C->deferred.head,
                       C->retryq.n - C->retryq.head,
                       C->splitq.n - C->splitq.head,
                       C->phase2.n - C->phase2.head,
                       C->ndy,
                       C->slotq.n - C->slotq.head};
    if (left[0] || left[1] || left[2] || left[3] || left[4] || left[5])
        MESH_BUG("work left at the end: %d deferred, %d to retry, %d splits, %d postponed, "
                 "%d dying tasks, %d waiting for a slot",
                 left[0], left[1], left[2], left[3], left[4], left[5]);
    /* the end check of the Delaunay property where the protocol decided it (pbw_check.c): a
     * defect ends every rank with an error, nothing written */
    pbw_test_break_delaunay(C);
    char dmsg[800];
    int64_t dbad = pbw_check_delaunay(C, dmsg, sizeof dmsg, &C->res.endcheck_s);
    snprintf(msg, sizeof msg, "%s: %s: %s", prog, c->input ? c->input : "", dmsg);
    if (par_fail_any(dbad != 0, msg)) {
        pbw_detach();
        pbw_ctx_free(C);
        return -1;
    }
    pbw_test_fault(C);
    /* this rank's part, and in the same pass the count of what is left outside the bounds */
    pbw_to_flat(C, local, res ? &C->res.topen : NULL);
    C->res.ntris = C->nlive;
    C->res.mesh_bytes = pbw_mesh_bytes(C);
    for (int k = 0; k < PBW_RSR_NKINDS; k++) {
        rt_handler_stats hs;
        if (rt_stats_handler(C->hid[k], &hs) == RT_OK) {
            C->res.rsr_sent[k] = hs.sent - hs.sent_self;
            C->res.rsr_self += hs.sent_self;
        }
    }
    if (res) *res = C->res;
    pbw_detach();
    pbw_ctx_free(C);
    return 0;
}
