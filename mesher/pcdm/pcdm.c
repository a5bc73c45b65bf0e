/* pcdm.c: one rank of the Parallel Constrained Delaunay Meshing algorithm (TR-97-17 section 3,
 * "Parallel Constrained Meshing Algorithm"; the runtime of section 4 carries the requests),
 * asynchronous mode; the deterministic rounds (./pcdm --deterministic) are in pcdm_det.c and share
 * the build below (pcdm_build_mesh).
 *
 * Build: pcdm_build.c (pcdm_build_mesh).
 *
 * Refine: rt_run's local work step is mesh_refine with a poll hook that stops it every
 * poll_every insertions (resumable), so the scheduler services incoming split requests between
 * steps and flushes the requests this step produced (aggregated per destination).  The kernel
 * calls on_split(seg, level, k) when it splits an interface subsegment by its own decision
 * (encroachment by a rejected circumcenter, or by a split point): the request goes to the owner
 * of the subdomain on the other side, unless that is this rank (then the two subdomains share
 * this mesh and the one edge already is split for both).  The handler calls
 * mesh_split_subsegment_named: both sides compute the split point from the name and the original
 * segment's endpoints, so the vertex is bit-identical; ALREADY (split here before) is counted
 * and dropped.  A split may encroach further subsegments; the kernel splits them and on_split
 * fires again, so cascades cross ranks as RSRs.
 * Invariants: no locks, no blocking; splits are never undone; every interface subsegment split
 * on one side is eventually split on the other (each local split sends exactly one request),
 * so at termination both sides hold the same chain of subsegments and the merged mesh
 * conforms -- unless the receiver could not make a split (its triangles put the point off the
 * line, at the precision limit): pcdm_part_figures counts those (mesh_iface_defects) and
 * ./pcdm then fails on every rank.  When refinement is over each mesh is made a constrained
 * Delaunay triangulation again by Lawson's flips (pcdm_mesh_restore_delaunay): a split point
 * rounded off its line, with a far apex beside the subsegment (a split received from another
 * rank has a cavity of that one triangle), leaves a new edge from the apex that is not locally
 * Delaunay; refinement removes it (its two triangles are skinny), but not when it stopped first
 * (the Steiner limit; tests/fuzz/regress/iface_fan_steiner_limit.poly at 8 ranks: a fan of
 * interface pieces at a tiny feature).  Flips add no vertex and leave every constraint edge, input
 * or interface, as it is, so the parts still conform; they change nothing in a mesh that already is
 * one.  A decomposition whose interfaces meet another segment
 * below 1/MESH_RULES_IFACE_MAX_PIECES radian is refused at build (check_angles).  The work function
 * returns IDLE only when mesh_refine returned DONE (or hit the Steiner limit) and no request
 * arrived since, honouring rt_run's termination contract.
 */
#include "pcdm/pcdm_impl.h"

#include "base/base.h"
#include "geom/geom.h"
#include "seq/kernel.h"
#include "seq/rules.h"

#include "rt.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The handler is registered once per process with a fixed argument; the part being refined is
 * published here for the duration of pcdm_part_refine (one part per process at a time). */
typedef struct pcdm_slot {
    int handler; /* id of "pcdm_split", -1 before pcdm_register */
    pcdm_part *active;
} pcdm_slot;

static pcdm_slot slot = {-1, NULL};

static void split_handler(const rt_msg *msg, void *arg) {
    pcdm_slot *s = arg;
    pcdm_part *p = s->active;
    if (!p) {
        MESH_BUG("split request from rank %d outside refinement", msg->src);
    }
    pcdm_split_msg r;
    memcpy(&r, msg->data, sizeof r);
    p->split_recv++;
    switch (mesh_split_subsegment_named(&p->m, r.seg, r.level, r.k)) {
    case MESH_SPLIT_DONE:
        p->split_done++;
        p->dirty = 1;
        break;
    case MESH_SPLIT_ALREADY:
        p->split_ignored++;
        p->dirty = 1; /* cheap; a cascade of named splits may have queued work */
        break;
    case MESH_SPLIT_NOT_FOUND:
        p->split_notfound++;
        fprintf(stderr,
                "pcdm: rank %d: split request from rank %d for segment %d (%d, %lld): "
                "not in this rank's mesh\n",
                rt_rank(), msg->src, (int)r.seg, (int)r.level, (long long)r.k);
        break;
    }
}

int pcdm_register(void) {
    int id = rt_handler_register("pcdm_split", split_handler, &slot, RT_NONTHREADED,
                                 (uint32_t)sizeof(pcdm_split_msg));
    if (id < 0) return id;
    slot.handler = id;
    return pcdm_det_register();
}

/* Refuses a decomposition whose interfaces meet another segment at an angle so small that the
 * splits along the two would cascade practically forever (MESH_RULES_IFACE_MAX_PIECES, rules.h:
 * a degenerate input the coarse mesh could not resolve, e.g. a domain of one sliver triangle
 * cut in three).  The same decision on every rank (same d). */
static int check_angles(const pcdm_decomp *d, char *err, size_t errlen) {
    double ang = d->iface_min_deg, /* found where d was drawn */
        lim = 57.29577951308232 / MESH_RULES_IFACE_MAX_PIECES;
    if (ang >= lim) return 0;
    snprintf(err, errlen,
             "%.400s: cannot decompose: a subdomain interface meets another segment at %.3g "
             "degrees (below %.2g, the splits along the two would never end); the input is too "
             "degenerate for %d subdomains: ask for fewer (--subdomains, fewer ranks or threads), "
             "or mesh it with ./mesh",
             d->g.path[0] ? d->g.path : "(input)", ang, lim, (int)d->nsub);
    return -1;
}

/* The part's fields before its mesh is built (both modes). */
static void part_init(pcdm_part *p, const pcdm_decomp *d, int rank) {
    memset(p, 0, sizeof *p);
    p->d = d;
    p->rank = rank;
    const char *fault = getenv("PCDM_TEST_DROP_SPLIT");
    if (fault && rank == 1) p->fault_drop = (int32_t)atoi(fault);
    for (int32_t s = 0; s < d->nsub; s++)
        if (d->sub_owner[s] == rank) p->nsub_owned++;
}

int pcdm_part_build(pcdm_part *p, const pcdm_decomp *d, int rank, char *err, size_t errlen) {
    return pcdm_part_build_regions(p, d, rank, PCDM_REGIONS_NONE, err, errlen);
}

int pcdm_part_build_regions(pcdm_part *p, const pcdm_decomp *d, int rank, int regions, char *err,
                            size_t errlen) {
    part_init(p, d, rank);
    if (check_angles(d, err, errlen) != 0) return -1;
    return pcdm_build_mesh(&p->m, d, rank, -1, regions, err, errlen);
}

int pcdm_part_build_det(pcdm_part *p, const pcdm_decomp *d, int rank, int regions, int threads,
                        char *err, size_t errlen) {
    part_init(p, d, rank);
    p->regions = regions;
    p->threads = threads; /* the subdomains are built on the rank's threads */
    mesh_init(&p->m);     /* stays empty */
    if (check_angles(d, err, errlen) != 0) return -1;
    return pcdm_det_build(p, err, errlen);
}

/* ---- refinement -------------------------------------------------------------------------- */

static void on_split(void *ctx, int32_t seg, int32_t level, int64_t k, unsigned flags) {
    pcdm_part *p = ctx;
    const pcdm_decomp *d = p->d;
    if (!(flags & MESH_SPLIT_INTERFACE) || seg < 0 || seg >= d->g.nsegs || !d->seg_iface[seg])
        return;
    pcdm_split_msg r;
    memset(&r, 0, sizeof r);
    r.seg = seg;
    r.level = level;
    r.k = k;
    int sent_to = -1;
    if (p->fault_drop > 0) { /* test-only fault (PCDM_TEST_DROP_SPLIT): lose this request */
        p->fault_drop--;
        return;
    }
    for (int side = 0; side < 2; side++) {
        int32_t sub = d->seg_sub[2 * (size_t)seg + side];
        if (sub < 0) continue;
        int owner = d->sub_owner[sub];
        if (owner == p->rank || owner == sent_to) continue;
        rt_rsr(owner, slot.handler, &r, (uint32_t)sizeof r);
        p->split_sent++;
        sent_to = owner;
    }
}

static int poll_stop(void *ctx) {
    pcdm_part *p = ctx;
    if (p->progress) {
        double t = rt_wtime();
        if (t - p->t_last >= 2.0) {
            p->t_last = t;
            fprintf(stderr, "pcdm: rank %d: %.1f s  %ld triangles  %llu splits sent\n", p->rank,
                    t - p->t_start, (long)p->m.nlive, (unsigned long long)p->split_sent);
        }
    }
    return 1; /* back to the scheduler: service requests, flush ours */
}

static int work(void *ctx) {
    pcdm_part *p = ctx;
    if (!p->dirty) return RT_WORK_IDLE;
    mesh_refine_result r = mesh_refine(&p->m);
    p->work_steps++;
    if (r == MESH_REFINE_STOPPED) return RT_WORK_BUSY;
    if (r == MESH_REFINE_STEINER_LIMIT) p->limit_hit = 1;
    p->dirty = 0;
    return RT_WORK_BUSY; /* did work in this call; the next call reports IDLE */
}

/* ---- the Delaunay property after refinement ------------------------------------------------- */

/* 1 iff edge e of a live triangle has a live neighbour across, is no constraint, touches no
 * ghost vertex and is not locally Delaunay (the neighbour's apex strictly inside e's triangle's
 * circumcircle, exact) while its flip gives two counter-clockwise triangles. */
static int flippable(const mesh *m, int32_t e) {
    int32_t f = m->tn[e];
    if (f < 0 || mesh_edge_constrained(m, e) || !mesh_tri_alive(m, e / 3) ||
        !mesh_tri_alive(m, f / 3))
        return 0;
    int32_t u = mesh_org(m, e), v = mesh_dest(m, e), w = mesh_apex(m, e), z = mesh_apex(m, f);
    if (u < 0 || v < 0 || w < 0 || z < 0) return 0;
    const double *U = mesh_vertex_xy(m, u), *V = mesh_vertex_xy(m, v), *W = mesh_vertex_xy(m, w),
                 *Z = mesh_vertex_xy(m, z);
    return geom_incircle(U, V, W, Z) > 0 && geom_orient2d(W, U, Z) > 0 &&
           geom_orient2d(Z, V, W) > 0;
}

/* Pushes edge e onto the stack (grown as needed). */
static void push_edge(int32_t **stack, int32_t *n, int32_t *cap, int32_t e) {
    if (*n == *cap) {
        *cap = *cap ? 2 * *cap : 64;
        *stack = mesh_xrealloc(*stack, (size_t)*cap, sizeof **stack);
    }
    (*stack)[(*n)++] = e;
}

int64_t pcdm_mesh_restore_delaunay(mesh *m) {
    int32_t *stack = NULL, n = 0, cap = 0;
    int64_t flips = 0;
    /* Bowyer-Watson leaves every edge locally Delaunay but the spokes of a point outside its
     * cavity's kernel, which only a subsegment's split point can be (off its line): the edges
     * at vertices on segments are the seeds, found by rotating around each */
    for (int32_t v = 0; v < m->nv; v++) {
        int32_t t0 = m->vseg[v] >= 0 ? m->vtri[v] : -1;
        if (t0 < 0 || !mesh_tri_alive(m, t0)) continue;
        int j = m->tv[3 * t0] == v       ? 0
                : m->tv[3 * t0 + 1] == v ? 1
                : m->tv[3 * t0 + 2] == v ? 2
                                         : -1;
        if (j < 0) continue;
        int32_t e0 = 3 * t0 + j; /* v -> dest */
        for (int dir = 0; dir < 2; dir++) {
            int32_t e = e0;
            for (int32_t steps = 0; steps <= m->nt; steps++) {
                if (flippable(m, e)) push_edge(&stack, &n, &cap, e);
                int32_t f = dir ? m->tn[e]                  /* dest -> v in the next triangle */
                                : m->tn[mesh_edge_prev(e)]; /* v -> apex's twin */
                if (f < 0) break;
                e = dir ? mesh_edge_next(f) : f;
                if (e == e0) { /* closed fan: every edge seen */
                    dir = 2;
                    break;
                }
            }
        }
    }
    while (n > 0) {
        int32_t e = stack[--n];
        if (!flippable(m, e)) continue; /* flipped away, or Delaunay since */
        int32_t t1 = e / 3, t2 = m->tn[e] / 3;
        mesh_flip(m, e); /* t1 = (w, u, z), t2 = (z, v, w): their outer edges 0 and 1 */
        flips++;
        push_edge(&stack, &n, &cap, 3 * t1);
        push_edge(&stack, &n, &cap, 3 * t1 + 1);
        push_edge(&stack, &n, &cap, 3 * t2);
        push_edge(&stack, &n, &cap, 3 * t2 + 1);
    }
    free(stack);
    return flips;
}

int pcdm_part_refine(pcdm_part *p, const mesh_quality *q, int32_t poll_every) {
    p->poll_every = poll_every > 0 ? poll_every : 300;
    if (p->det) {
        p->t_start = p->t_last = rt_wtime();
        pcdm_det_refine(p, q);
        return 0;
    }
    mesh_set_quality(&p->m, q);
    mesh_hooks h;
    memset(&h, 0, sizeof h);
    h.on_split = on_split;
    h.poll = poll_stop;
    h.poll_every = p->poll_every;
    h.ctx = p;
    mesh_set_hooks(&p->m, &h);
    p->dirty = 1;
    p->t_start = p->t_last = rt_wtime();
    if (slot.handler < 0) {
        MESH_BUG("pcdm_register was not called");
    }
    slot.active = p;
    rt_run(work, p);
    slot.active = NULL;
    p->flips += (uint64_t)pcdm_mesh_restore_delaunay(&p->m);
    return 0;
}

int pcdm_part_flat(const pcdm_part *p, mesh_flat *f) {
    if (mesh_to_flat(&p->m, f) != 0) return -1;
    f->trank = mesh_xmalloc((size_t)f->ntris + 1, sizeof(int32_t));
    if (!f->trank) {
        mesh_flat_free(f);
        return -1;
    }
    for (int32_t t = 0; t < f->ntris; t++)
        f->trank[t] = p->rank;
    return 0;
}

/* Each live triangle slot's subdomain (-1: dead slot, or a region with no subsegment record):
 * regions between constraint edges lie in one subdomain, found by the side of one bounding
 * subsegment (as pcdm_part_build). */
static int32_t *slot_subdomains(const pcdm_part *p) {
    const mesh *m = &p->m;
    const pcdm_decomp *d = p->d;
    int32_t *label = mesh_xmalloc((size_t)m->nt + 1, sizeof(int32_t));
    int32_t nreg = mesh_label_regions(m, label);
    int32_t *regsub = mesh_xmalloc((size_t)nreg + 1, sizeof(int32_t));
    for (int32_t r = 0; r < nreg; r++)
        regsub[r] = -1;
    for (int32_t t = 0; t < m->nt; t++) {
        if (!mesh_tri_alive(m, t) || !(m->tf[t] & 7) || regsub[label[t]] >= 0) continue;
        for (int j = 0; j < 3; j++) {
            int32_t e = 3 * t + j;
            if (!mesh_edge_constrained(m, e)) continue;
            const mesh_subseg *s = mesh_subseg_of_edge(m, e);
            if (!s || s->seg < 0 || s->seg >= d->g.nsegs) continue;
            int side = mesh_org(m, e) == s->u ? 0 : 1;
            regsub[label[t]] = d->seg_sub[2 * (size_t)s->seg + side];
            break;
        }
    }
    for (int32_t t = 0; t < m->nt; t++)
        label[t] = label[t] >= 0 ? regsub[label[t]] : -1;
    free(regsub);
    return label;
}

void pcdm_part_take_flat(pcdm_part *p, mesh_flat *f, int32_t **tsub, uint8_t **topen) {
    int32_t *sub = tsub ? slot_subdomains(p) : NULL;
    if (sub) { /* compacted like the triangles (slot order, live only) */
        int32_t n = 0;
        for (int32_t t = 0; t < p->m.nt; t++)
            if (mesh_tri_alive(&p->m, t)) sub[n++] = sub[t];
        *tsub = sub;
    }
    mesh_take_flat(&p->m, f, topen);
}

uint8_t *pcdm_part_artificial(const pcdm_part *p) {
    uint8_t *a = mesh_xmalloc((size_t)p->m.ss_live + 1, 1);
    int32_t ns = 0;
    for (int32_t r = 0; r < p->m.nss; r++) /* the order of mesh_to_flat's subsegments */
        if (p->m.ss[r].level != -2) a[ns++] = p->m.ss[r].seg >= p->d->nboundary;
    return a;
}

void pcdm_part_figures(pcdm_part *p, pcdm_figures *f) {
    if (p->det) {
        pcdm_det_figures(p, f);
        return;
    }
    memset(f, 0, sizeof *f);
    f->ntris = p->m.nlive;
    f->nverts = p->m.nv;
    f->inserted = p->m.stats.inserted;
    f->mesh_bytes = mesh_memory_bytes(&p->m);
    f->unmet = mesh_count_unmet(&p->m, NULL);
    f->refused = p->m.stats.unresolved;
    f->iface_enc = mesh_iface_defects(&p->m, &f->iface_remote);
}

void pcdm_part_take(pcdm_part *p, mesh_flat *f, uint8_t **artificial, int32_t **tsub,
                    uint8_t **topen) {
    if (p->det) {
        pcdm_det_take(p, f, artificial, tsub, topen);
        return;
    }
    *artificial = pcdm_part_artificial(p);
    pcdm_part_take_flat(p, f, tsub, topen);
}

void pcdm_part_free(pcdm_part *p) {
    pcdm_det_free(p);
    mesh_free(&p->m);
    memset(p, 0, sizeof *p);
}
