/* xwrite.c: the text of the derived outputs (xwrite.h), as sections of records (text.h) so
 * that one set of formatting functions serves ./mesh (one process) and every rank of ./pcdm and
 * ./pbw (one shared file, MPI-IO, through the writer ptext.h gives).
 *
 * Formats (public documentation): Triangle's .edge ("N 1", then "e a b marker"), .neigh ("N 3",
 * then "t n0 n1 n2", -1 for none, neighbour j opposite corner j), -o2 .node (the vertices, then
 * the midpoint of every edge, numbered after all vertices, with the edge's marker) and .ele
 * ("N 6 A": three corners, then the midpoints opposite corners 0, 1, 2); legacy VTK
 * unstructured grid with cell type 22 (VTK_QUADRATIC_TRIANGLE: corners, then the midpoints of
 * edges 01, 12, 20); Gmsh MSH 4.1 ASCII ($MeshFormat, $PhysicalNames, $Entities, $Nodes,
 * $Elements; element types 1/8 lines and 2/9 triangles, type 9's node order as VTK's).
 * Numbers in the files are 1-based except VTK's; coordinates are written in the fewest digits
 * that read back to the same bits (fmt_dbl), unscaled exactly (ldexp by -scale_exp); midpoints
 * are (a + b) / 2 of the working coordinates, the same on both sides of a rank interface.
 */
#include "io/xwrite.h"

#include "base/base.h"
#include "io/fmt.h"
#include "io/text.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct wctx {
    const mesh_xview *x;
    int rank, size, o2;
    int32_t *lgrp, *tgrp; /* group of each sorted line / triangle */
    int32_t *lcnt, *tcnt; /* this rank's count per group */
} wctx;

static long long vnum(const mesh_xview *x, int32_t v) {
    return x->gid ? (long long)x->gid[v] : (long long)v;
}

/* The local ends of half-edge h (the edge opposite corner h % 3 of triangle h / 3). */
static void he_ends(const mesh_xview *x, int32_t h, int32_t *a, int32_t *b) {
    const int32_t *t = x->f->tri + 3 * (size_t)(h / 3);
    *a = t[(h % 3 + 1) % 3];
    *b = t[(h % 3 + 2) % 3];
}

static long long mid_num(const mesh_xview *x, int32_t t, int j) {
    return (long long)(x->nvtot + x->egid[x->eid[3 * (size_t)t + (size_t)j]]);
}

static char *put_xy(const mesh_xview *x, char *q, const double *xy, const char *sep) {
    int s = x->f->scale_exp;
    q = fmt_dbl(q, s ? ldexp(xy[0], -s) : xy[0]);
    *q++ = ' ';
    q = fmt_dbl(q, s ? ldexp(xy[1], -s) : xy[1]);
    while (*sep)
        *q++ = *sep++;
    return q;
}

/* Vertex i of those this rank writes: coordinates, marker, attributes (or NULL). */
static const double *wvert(const mesh_xview *x, int64_t i, int32_t *mk, const double **at) {
    *at = NULL;
    if (i < x->nhead) {
        *mk = x->hvmarker ? x->hvmarker[i] : 0;
        return x->hxy + 2 * i;
    }
    int64_t v = x->vsel ? x->vsel[i - x->nhead] : i - x->nhead;
    *mk = x->f->vmarker ? x->f->vmarker[v] : 0;
    if (x->nattr && x->f->vattr) *at = x->f->vattr + (size_t)v * (size_t)x->nattr;
    return x->f->xy + 2 * v;
}

/* Midpoint of written edge k: working coordinates into m[2]. */
static int32_t wmid(const mesh_xview *x, int64_t k, double m[2], int32_t *a, int32_t *b) {
    int32_t e = x->we[k];
    he_ends(x, x->ehe[e], a, b);
    const double *p = x->f->xy + 2 * (size_t)*a, *r = x->f->xy + 2 * (size_t)*b;
    m[0] = (p[0] + r[0]) / 2;
    m[1] = (p[1] + r[1]) / 2;
    return e;
}

static char *tail_pcdm(void *c, char *q) {
    wctx *w = c;
    if (w->rank == w->size - 1) q += sprintf(q, "# written by pcdm\n");
    return q;
}

/* ---- .edge, .neigh ------------------------------------------------------------------------ */

static char *edge_head(void *c, char *q) {
    wctx *w = c;
    if (w->rank == 0) q += sprintf(q, "%lld 1\n", (long long)w->x->etot);
    return q;
}

static char *edge_rec(void *c, int64_t i, char *q) {
    const mesh_xview *x = ((wctx *)c)->x;
    int32_t e = x->we[i], a, b;
    he_ends(x, x->ehe[e], &a, &b);
    q = fmt_int(q, (long long)x->egid[e] + 1);
    *q++ = ' ';
    q = fmt_int(q, vnum(x, a) + 1);
    *q++ = ' ';
    q = fmt_int(q, vnum(x, b) + 1);
    *q++ = ' ';
    q = fmt_int(q, x->emark[e]);
    *q++ = '\n';
    return q;
}

static char *neigh_head(void *c, char *q) {
    wctx *w = c;
    if (w->rank == 0) q += sprintf(q, "%lld 3\n", (long long)w->x->ttot);
    return q;
}

static char *neigh_rec(void *c, int64_t t, char *q) {
    const mesh_xview *x = ((wctx *)c)->x;
    q = fmt_int(q, (long long)(x->tfirst + t) + 1);
    for (int j = 0; j < 3; j++) {
        int64_t n = mesh_xview_neighbour(x, (int32_t)(3 * t + j));
        *q++ = ' ';
        q = fmt_int(q, n < 0 ? -1 : (long long)n + 1);
    }
    *q++ = '\n';
    return q;
}

/* ---- -o2 .node and .ele ------------------------------------------------------------------- */

static char *node2_head(void *c, char *q) {
    wctx *w = c;
    if (w->rank == 0)
        q += sprintf(q, "%lld 2 %d 1\n", (long long)(w->x->nvtot + w->x->etot), w->x->nattr);
    return q;
}

static char *node2_vrec(void *c, int64_t i, char *q) {
    const mesh_xview *x = ((wctx *)c)->x;
    int32_t mk;
    const double *at, *xy = wvert(x, i, &mk, &at);
    q = fmt_int(q, (long long)(x->vfirst + i) + 1);
    *q++ = ' ';
    q = put_xy(x, q, xy, "");
    for (int k = 0; k < x->nattr; k++) {
        *q++ = ' ';
        q = fmt_dbl(q, at ? at[k] : 0.0);
    }
    *q++ = ' ';
    q = fmt_int(q, mk);
    *q++ = '\n';
    return q;
}

static char *node2_mrec(void *c, int64_t k, char *q) {
    const mesh_xview *x = ((wctx *)c)->x;
    double m[2];
    int32_t a, b, e = wmid(x, k, m, &a, &b);
    q = fmt_int(q, (long long)(x->nvtot + x->egid[e]) + 1);
    *q++ = ' ';
    q = put_xy(x, q, m, "");
    for (int j = 0; j < x->nattr; j++) { /* attributes interpolated linearly */
        const double *va = x->f->vattr;
        *q++ = ' ';
        q = fmt_dbl(q, va ? (va[(size_t)a * (size_t)x->nattr + (size_t)j] +
                             va[(size_t)b * (size_t)x->nattr + (size_t)j]) /
                                2
                          : 0.0);
    }
    *q++ = ' ';
    q = fmt_int(q, x->emark[e]);
    *q++ = '\n';
    return q;
}

static char *ele2_head(void *c, char *q) {
    wctx *w = c;
    if (w->rank == 0) q += sprintf(q, "%lld 6 %d\n", (long long)w->x->ttot, w->x->ele_attr ? 1 : 0);
    return q;
}

static char *ele2_rec(void *c, int64_t t, char *q) {
    const mesh_xview *x = ((wctx *)c)->x;
    const mesh_flat *f = x->f;
    q = fmt_int(q, (long long)(x->tfirst + t) + 1);
    for (int k = 0; k < 3; k++) {
        *q++ = ' ';
        q = fmt_int(q, vnum(x, f->tri[3 * t + k]) + 1);
    }
    for (int j = 0; j < 3; j++) {
        *q++ = ' ';
        q = fmt_int(q, mid_num(x, (int32_t)t, j) + 1);
    }
    if (x->ele_attr) {
        *q++ = ' ';
        q = fmt_dbl(q, f->tattr ? f->tattr[t] : 0.0);
    }
    *q++ = '\n';
    return q;
}

/* ---- quadratic legacy VTK ----------------------------------------------------------------- */

static char *vtk_head(void *c, char *q) {
    wctx *w = c;
    if (w->rank == 0)
        q += sprintf(q,
                     "# vtk DataFile Version 3.0\npcdm quadratic triangles\nASCII\n"
                     "DATASET UNSTRUCTURED_GRID\nPOINTS %lld double\n",
                     (long long)(w->x->nvtot + w->x->etot));
    return q;
}

static char *vtk_vrec(void *c, int64_t i, char *q) {
    const mesh_xview *x = ((wctx *)c)->x;
    int32_t mk;
    const double *at;
    return put_xy(x, q, wvert(x, i, &mk, &at), " 0\n");
}

static char *vtk_mrec(void *c, int64_t k, char *q) {
    const mesh_xview *x = ((wctx *)c)->x;
    double m[2];
    int32_t a, b;
    wmid(x, k, m, &a, &b);
    return put_xy(x, q, m, " 0\n");
}

static char *vtk_cells_head(void *c, char *q) {
    wctx *w = c;
    if (w->rank == 0)
        q += sprintf(q, "CELLS %lld %lld\n", (long long)w->x->ttot, 7 * (long long)w->x->ttot);
    return q;
}

/* VTK's and Gmsh's midpoint order: edges 01, 12, 20 = opposite corners 2, 0, 1. */
static const int mid_order[3] = {2, 0, 1};

static char *vtk_cell(void *c, int64_t t, char *q) {
    const mesh_xview *x = ((wctx *)c)->x;
    *q++ = '6';
    for (int k = 0; k < 3; k++) {
        *q++ = ' ';
        q = fmt_int(q, vnum(x, x->f->tri[3 * t + k]));
    }
    for (int k = 0; k < 3; k++) {
        *q++ = ' ';
        q = fmt_int(q, mid_num(x, (int32_t)t, mid_order[k]));
    }
    *q++ = '\n';
    return q;
}

static char *vtk_types_head(void *c, char *q) {
    wctx *w = c;
    if (w->rank == 0) q += sprintf(q, "CELL_TYPES %lld\n", (long long)w->x->ttot);
    return q;
}

static char *vtk_type(void *c, int64_t t, char *q) {
    memcpy(q, "22\n", 3);
    return q + 3;
}

static char *vtk_cdata_head(void *c, char *q) {
    wctx *w = c;
    if (w->rank == 0)
        q += sprintf(q, "CELL_DATA %lld\nSCALARS rank int 1\nLOOKUP_TABLE default\n",
                     (long long)w->x->ttot);
    return q;
}

static char *vtk_crank(void *c, int64_t t, char *q) {
    wctx *w = c;
    q = fmt_int(q, w->x->f->trank ? w->x->f->trank[t] : w->rank);
    *q++ = '\n';
    return q;
}

static char *vtk_pdata_head(void *c, char *q) {
    wctx *w = c;
    if (w->rank == 0)
        q += sprintf(q, "POINT_DATA %lld\nSCALARS marker int 1\nLOOKUP_TABLE default\n",
                     (long long)(w->x->nvtot + w->x->etot));
    return q;
}

static char *vtk_vmark(void *c, int64_t i, char *q) {
    int32_t mk;
    const double *at;
    wvert(((wctx *)c)->x, i, &mk, &at);
    q = fmt_int(q, mk);
    *q++ = '\n';
    return q;
}

static char *vtk_mmark(void *c, int64_t k, char *q) {
    q = fmt_int(q, ((wctx *)c)->x->emark[((wctx *)c)->x->we[k]]);
    *q++ = '\n';
    return q;
}

/* ---- Gmsh MSH 4.1 ------------------------------------------------------------------------- */

static size_t msh_headmax(const mesh_xview *x) {
    return 1024 + 256 * ((size_t)x->ncurve + (size_t)x->nsurf);
}

static long long msh_nnodes(const wctx *w) {
    return (long long)(w->x->nvtot + (w->o2 ? w->x->etot : 0));
}

static char *msh_head(void *c, char *q) {
    wctx *w = c;
    const mesh_xview *x = w->x;
    if (w->rank == 0) {
        q += sprintf(q, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n%d\n",
                     (int)(x->ncurve + x->nsurf));
        for (int32_t i = 0; i < x->ncurve; i++)
            q += sprintf(q, "1 %d \"marker %d\"\n", (int)i + 1, (int)x->curve_mark[i]);
        for (int32_t i = 0; i < x->nsurf; i++) {
            if (!x->surf_attr) {
                q += sprintf(q, "2 %d \"domain\"\n", (int)i + 1);
                continue;
            }
            q += sprintf(q, "2 %d \"region ", (int)i + 1);
            q = fmt_dbl(q, x->surf_attr[i]);
            q += sprintf(q, "\"\n");
        }
        q += sprintf(q, "$EndPhysicalNames\n$Entities\n0 %d %d 0\n", (int)x->ncurve, (int)x->nsurf);
        char box[160], *b = box;
        const double *bb = x->bbox;
        b = fmt_dbl(b, bb[0]), *b++ = ' ', b = fmt_dbl(b, bb[1]), b += sprintf(b, " 0 ");
        b = fmt_dbl(b, bb[2]), *b++ = ' ', b = fmt_dbl(b, bb[3]), b += sprintf(b, " 0");
        for (int32_t i = 0; i < x->ncurve; i++)
            q += sprintf(q, "%d %s 1 %d 0\n", (int)i + 1, box, (int)i + 1);
        for (int32_t i = 0; i < x->nsurf; i++)
            q += sprintf(q, "%d %s 1 %d 0\n", (int)i + 1, box, (int)i + 1);
        q += sprintf(q, "$EndEntities\n$Nodes\n%lld %lld 1 %lld\n", (long long)x->nodeblocks_tot,
                     msh_nnodes(w), msh_nnodes(w));
    }
    int64_t n = x->nhead + x->nsel;
    if (n) q += sprintf(q, "2 1 0 %lld\n", (long long)n);
    return q;
}

static char *msh_vrec(void *c, int64_t i, char *q) { /* tags, then coordinates */
    const mesh_xview *x = ((wctx *)c)->x;
    int64_t n = x->nhead + x->nsel;
    if (i < n) {
        q = fmt_int(q, (long long)(x->vfirst + i) + 1);
        *q++ = '\n';
        return q;
    }
    int32_t mk;
    const double *at;
    return put_xy(x, q, wvert(x, i - n, &mk, &at), " 0\n");
}

static char *msh_mhead(void *c, char *q) {
    const mesh_xview *x = ((wctx *)c)->x;
    if (x->nwe) q += sprintf(q, "2 1 0 %lld\n", (long long)x->nwe);
    return q;
}

static char *msh_mrec(void *c, int64_t i, char *q) {
    const mesh_xview *x = ((wctx *)c)->x;
    if (i < x->nwe) {
        q = fmt_int(q, (long long)(x->nvtot + x->egid[x->we[i]]) + 1);
        *q++ = '\n';
        return q;
    }
    double m[2];
    int32_t a, b;
    wmid(x, i - x->nwe, m, &a, &b);
    return put_xy(x, q, m, " 0\n");
}

static char *msh_ehead(void *c, char *q) {
    wctx *w = c;
    const mesh_xview *x = w->x;
    if (w->rank == 0) {
        long long ne = (long long)(x->ltot + x->ttot);
        q += sprintf(q, "$EndNodes\n$Elements\n%lld %lld 1 %lld\n", (long long)x->blocks_tot, ne,
                     ne);
    }
    return q;
}

static char *msh_line(void *c, int64_t i, char *q) {
    wctx *w = c;
    const mesh_xview *x = w->x;
    int32_t g = w->lgrp[i];
    if (i == 0 || w->lgrp[i - 1] != g)
        q += sprintf(q, "1 %d %d %d\n", (int)g + 1, w->o2 ? 8 : 1, (int)w->lcnt[g]);
    int32_t e = x->wl[x->lperm[i]], h = x->ehe[e], a, b;
    he_ends(x, h, &a, &b);
    q = fmt_int(q, (long long)(x->lfirst + i) + 1);
    *q++ = ' ';
    q = fmt_int(q, vnum(x, a) + 1);
    *q++ = ' ';
    q = fmt_int(q, vnum(x, b) + 1);
    if (w->o2) {
        *q++ = ' ';
        q = fmt_int(q, (long long)(x->nvtot + x->egid[e]) + 1);
    }
    *q++ = '\n';
    return q;
}

static char *msh_tri(void *c, int64_t i, char *q) {
    wctx *w = c;
    const mesh_xview *x = w->x;
    int32_t g = w->tgrp[i], t = x->tperm[i];
    if (i == 0 || w->tgrp[i - 1] != g)
        q += sprintf(q, "2 %d %d %d\n", (int)g + 1, w->o2 ? 9 : 2, (int)w->tcnt[g]);
    q = fmt_int(q, (long long)(x->ltot + x->tfirst + t) + 1);
    for (int k = 0; k < 3; k++) {
        *q++ = ' ';
        q = fmt_int(q, vnum(x, x->f->tri[3 * (size_t)t + (size_t)k]) + 1);
    }
    for (int k = 0; k < 3 && w->o2; k++) {
        *q++ = ' ';
        q = fmt_int(q, mid_num(x, t, mid_order[k]) + 1);
    }
    *q++ = '\n';
    return q;
}

static char *msh_tail(void *c, char *q) {
    wctx *w = c;
    if (w->rank == w->size - 1) q += sprintf(q, "$EndElements\n");
    return q;
}

/* ---- writing ------------------------------------------------------------------------------ */

static int put(const mesh_text_out *out, struct meshio_set *set, const char *path,
               const mesh_text_sec *s, int ns, char *err, size_t errlen) {
    if (!out) return meshio_write_sections(set, path, s, ns, err, errlen);
    return out->put(out->ctx, set, path, s, ns, err, errlen);
}

/* Sorted positions' groups and per-group counts (for the Gmsh block headers). */
static void msh_groups(wctx *w) {
    const mesh_xview *x = w->x;
    const int32_t nt = x->f->ntris;
    w->lgrp = mesh_xmalloc((size_t)x->nwl + 1, sizeof(int32_t));
    w->lcnt = mesh_xcalloc((size_t)x->ncurve + 1, sizeof(int32_t));
    for (int32_t i = 0; i < x->nwl; i++) {
        int32_t m = x->emark[x->wl[x->lperm[i]]], lo = 0, hi = x->ncurve - 1;
        while (lo < hi) { /* curve_mark is sorted and holds m */
            int32_t mid = (lo + hi) / 2;
            if (x->curve_mark[mid] < m)
                lo = mid + 1;
            else
                hi = mid;
        }
        w->lgrp[i] = lo;
        w->lcnt[lo]++;
    }
    w->tgrp = mesh_xmalloc((size_t)nt + 1, sizeof(int32_t));
    w->tcnt = mesh_xcalloc((size_t)x->nsurf + 1, sizeof(int32_t));
    for (int32_t i = 0; i < nt; i++) {
        int32_t g = 0;
        if (x->surf_attr && x->f->tattr) {
            double a = x->f->tattr[x->tperm[i]];
            int32_t lo = 0, hi = x->nsurf - 1;
            while (lo < hi) {
                int32_t mid = (lo + hi) / 2;
                if (x->surf_attr[mid] < a)
                    lo = mid + 1;
                else
                    hi = mid;
            }
            g = lo;
        }
        w->tgrp[i] = g;
        w->tcnt[g]++;
    }
}

int mesh_xview_write(const mesh_xview *x, const mesh_text_out *out, const mesh_xreq *r, char *err,
                     size_t errlen) {
    wctx w = {x, 0, 1, r->order2, NULL, NULL, NULL, NULL};
    if (out) {
        w.rank = out->rank;
        w.size = out->size;
    }
    if (errlen) err[0] = '\0';
    const int64_t nv = x->nhead + x->nsel, nt = x->f->ntris;
    const size_t rm = 400 + 32 * (size_t)x->nattr; /* one record's room, block header included */
    char path[1100];
    int rc = 0;
    if (r->prefix && strlen(r->prefix) + 8 > sizeof path) {
        snprintf(err, errlen, "%s: path too long", r->prefix);
        return -1;
    }
    if (r->prefix && r->edges) {
        snprintf(path, sizeof path, "%s.edge", r->prefix);
        mesh_text_sec s = {x->nwe, edge_head, edge_rec, tail_pcdm, &w, 64, rm};
        rc = put(out, r->set, path, &s, 1, err, errlen);
    }
    if (rc == 0 && r->prefix && r->neighbors) {
        snprintf(path, sizeof path, "%s.neigh", r->prefix);
        mesh_text_sec s = {nt, neigh_head, neigh_rec, tail_pcdm, &w, 64, rm};
        rc = put(out, r->set, path, &s, 1, err, errlen);
    }
    if (rc == 0 && r->prefix && r->order2 && !(r->skip & MESHIO_SKIP_NODE)) {
        snprintf(path, sizeof path, "%s.node", r->prefix);
        mesh_text_sec s[2] = {{nv, node2_head, node2_vrec, NULL, &w, 64, rm},
                              {x->nwe, NULL, node2_mrec, tail_pcdm, &w, 64, rm}};
        rc = put(out, r->set, path, s, 2, err, errlen);
    }
    if (rc == 0 && r->prefix && r->order2 && !(r->skip & MESHIO_SKIP_ELE)) {
        snprintf(path, sizeof path, "%s.ele", r->prefix);
        mesh_text_sec e = {nt, ele2_head, ele2_rec, tail_pcdm, &w, 64, rm};
        rc = put(out, r->set, path, &e, 1, err, errlen);
    }
    if (rc == 0 && r->vtk && r->order2) {
        mesh_text_sec s[7] = {{nv, vtk_head, vtk_vrec, NULL, &w, 256, rm},
                              {x->nwe, NULL, vtk_mrec, NULL, &w, 64, rm},
                              {nt, vtk_cells_head, vtk_cell, NULL, &w, 64, rm},
                              {nt, vtk_types_head, vtk_type, NULL, &w, 64, rm},
                              {nt, vtk_cdata_head, vtk_crank, NULL, &w, 128, rm},
                              {nv, vtk_pdata_head, vtk_vmark, NULL, &w, 128, rm},
                              {x->nwe, NULL, vtk_mmark, NULL, &w, 64, rm}};
        rc = put(out, r->set, r->vtk, s, 7, err, errlen);
    }
    if (rc == 0 && r->msh) {
        msh_groups(&w);
        size_t hm = msh_headmax(x);
        mesh_text_sec s[4] = {
            {2 * nv, msh_head, msh_vrec, NULL, &w, hm, rm},
            {w.o2 ? 2 * (int64_t)x->nwe : 0, msh_mhead, msh_mrec, NULL, &w, 64, rm},
            {x->nwl, msh_ehead, msh_line, NULL, &w, 128, rm},
            {nt, NULL, msh_tri, msh_tail, &w, 64, rm}};
        if (!w.o2) s[1].head = NULL;
        rc = put(out, r->set, r->msh, s, 4, err, errlen);
    }
    free(w.lgrp);
    free(w.tgrp);
    free(w.lcnt);
    free(w.tcnt);
    return rc;
}

int meshio_write_extras(const mesh_flat *m, const mesh_xreq *r, char *err, size_t errlen) {
    mesh_xview x;
    mesh_xview_topo(&x, m, NULL);
    x.nvtot = x.nsel = m->nverts;
    x.ttot = m->ntris;
    x.nattr = m->vattr ? m->nattr : 0;
    x.ele_attr = m->tattr ? 1 : 0; /* Triangle's: the region's with -A, else none */
    mesh_xview_finish(&x);
    x.etot = x.nwe;
    x.ltot = x.nwl;
    int32_t *marks, nm, na;
    double *attrs;
    mesh_xview_local_groups(&x, &marks, &nm, &attrs, &na);
    mesh_xview_groups(&x, marks, nm, m->tattr ? attrs : NULL, na);
    free(marks);
    free(attrs);
    x.blocks_tot = x.nlblk + x.ntblk;
    x.nodeblocks_tot = (x.nsel > 0) + (r->order2 && x.nwe > 0);
    x.bbox[0] = x.bbox[1] = INFINITY;
    x.bbox[2] = x.bbox[3] = -INFINITY;
    for (int32_t v = 0; v < m->nverts; v++)
        for (int k = 0; k < 2; k++) {
            double c = ldexp(m->xy[2 * (size_t)v + (size_t)k], -m->scale_exp);
            x.bbox[k] = fmin(x.bbox[k], c);
            x.bbox[2 + k] = fmax(x.bbox[2 + k], c);
        }
    if (m->nverts == 0) x.bbox[0] = x.bbox[1] = x.bbox[2] = x.bbox[3] = 0;
    int rc = mesh_xview_write(&x, NULL, r, err, errlen);
    mesh_xview_free(&x);
    return rc;
}
