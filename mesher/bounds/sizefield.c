/* sizefield: the size rules of -r's .area and --size (the mesh to refine itself is read by
 * io/meshin.c, meshio_read_mesh_pslg).
 *
 * The size rule: the old triangles (with their .area bounds) and the background mesh (with
 * its lengths) are each indexed by a tloc; a query locates the centroid of the new triangle
 * (rounded: it only picks which bound applies).  Everything is scaled by 2^scale_exp when
 * loaded, exactly (a power of two), so the rule compares internal coordinates with internal
 * coordinates.  The .area file is loaded and walked as the .node and .ele are (base/textin.h)
 * and must list every triangle.
 */
#include "bounds/sizefield.h"

#include "base/base.h"
#include "base/textin.h"
#include "geom/geom.h"
#include "io/meshio.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------- .area ------------------ */

/* A whole decimal integer token at *s, with an optional sign (advancing *s past it): 0, or -1
 * when there is none, it leaves [-INT32_MAX, INT32_MAX], or more follows it than a blank.  By
 * hand: strtol took a seventh of the time to read a .area of 1.7M triangles. */
static int area_int(char **s, long *v) {
    const char *p = *s + strspn(*s, " \t\r\v\f");
    int neg = *p == '-';
    p += *p == '+' || *p == '-';
    const char *d = p;
    long x = 0;
    while (*p >= '0' && *p <= '9' && x <= INT32_MAX)
        x = x * 10 + (*p++ - '0');
    if (p == d || x > INT32_MAX || (*p && !strchr(" \t\r\v\f", *p))) return -1;
    *v = neg ? -x : x;
    *s = (char *)p;
    return 0;
}

/* Reads PATH (.area) for nt triangles numbered from first into area[]: loaded and walked by
 * base/textin.h (as the .node and .ele), every triangle's line present. */
static int read_area(const char *path, int32_t nt, int first, double *area, char *err,
                     size_t errlen) {
    mesh_textin in;
    if (mesh_textin_load(&in, path, err, errlen)) return -1;
    char *s, *end;
    long n, rc = -1;
    if (!(s = mesh_textin_line(&in))) {
        mesh_fail(err, errlen, "%s:%ld: empty file: expected a triangle count", path, in.line);
        goto out;
    }
    if (area_int(&s, &n)) {
        mesh_fail(err, errlen, "%s:%ld: malformed triangle count", path, in.line);
        goto out;
    }
    if (n != nt) {
        mesh_fail(err, errlen, "%s:%ld: triangle count %ld does not match the mesh's %d triangles",
                  path, in.line, n, (int)nt);
        goto out;
    }
    for (int32_t t = 0; t < nt; t++) {
        if (!(s = mesh_textin_line(&in))) {
            mesh_fail(err, errlen,
                      "%s:%ld: unexpected end of file: expected %d triangles, found %d", path,
                      in.line, (int)nt, (int)t);
            goto out;
        }
        long id;
        if (area_int(&s, &id)) {
            mesh_fail(err, errlen, "%s:%ld: malformed triangle number", path, in.line);
            goto out;
        }
        if (id != (long)first + t) {
            mesh_fail(err, errlen, "%s:%ld: triangle number out of sequence (expected %ld)", path,
                      in.line, (long)first + t);
            goto out;
        }
        double a = strtod(s, &end);
        if (end == s || !isfinite(a)) {
            mesh_fail(err, errlen, "%s:%ld: malformed maximum area of triangle %ld", path, in.line,
                      id);
            goto out;
        }
        end += strspn(end, " \t\r\v\f");
        if (*end) {
            int k = (int)strcspn(end, " \t\r\v\f"); /* the token, not a CRLF file's CR */
            mesh_fail(err, errlen, "%s:%ld: unexpected text '%.*s'", path, in.line, k < 40 ? k : 40,
                      end);
            goto out;
        }
        area[t] = a;
    }
    rc = 0;
out:
    mesh_textin_free(&in);
    return (int)rc;
}

/* ---------------------------------------------------------------- loading ---------------- */

static double scale_len(double x, int e) {
    return e ? ldexp(x, e) : x;
}

static int load_old(size_field *S, const char *name, int e, char *err, size_t errlen) {
    char prefix[400], path[512];
    if (meshio_mesh_prefix(name, prefix, sizeof prefix, err, errlen)) return -1;
    mesh_flat m;
    if (meshio_read_triangle(prefix, &m, err, errlen)) return -1;
    meshio_flat_orient_ccw(&m);
    snprintf(path, sizeof path, "%s.area", prefix);
    S->ont = m.ntris;
    S->oarea = mesh_xmalloc((size_t)m.ntris + 1, sizeof(double));
    /* the first vertex number of the .node names the triangles' numbering too */
    pslg nodes;
    char p2[512];
    snprintf(p2, sizeof p2, "%s.node", prefix);
    int first = 1;
    if (pslg_read(p2, &nodes, err, errlen) == 0) {
        first = nodes.first_index;
        pslg_free(&nodes);
    }
    if (read_area(path, m.ntris, first, S->oarea, err, errlen)) {
        mesh_flat_free(&m);
        return -1;
    }
    S->oxy = mesh_xmalloc(6 * (size_t)m.ntris + 1, sizeof(double));
    S->otri = mesh_xmalloc(3 * (size_t)m.ntris + 1, sizeof(int32_t));
    for (int32_t t = 0; t < m.ntris; t++) {
        for (int k = 0; k < 3; k++) {
            const double *p = m.xy + 2 * (size_t)m.tri[3 * (size_t)t + k];
            S->oxy[6 * (size_t)t + 2 * k] = scale_len(p[0], e);
            S->oxy[6 * (size_t)t + 2 * k + 1] = scale_len(p[1], e);
            S->otri[3 * (size_t)t + k] = 3 * t + k;
        }
        double a = S->oarea[t];
        S->oarea[t] = a > 0 ? fmax(ldexp(a, 2 * e), DBL_MIN) : 0;
    }
    mesh_flat_free(&m);
    if (tloc_build(&S->old, S->oxy, S->otri, S->ont))
        return mesh_fail(err, errlen, "%s.ele: too many triangles to index", prefix);
    return 0;
}

static int load_background(size_field *S, const char *name, int e, char *err, size_t errlen) {
    char prefix[1024];
    if (meshio_mesh_prefix(name, prefix, sizeof prefix, err, errlen)) return -1;
    mesh_flat m;
    if (meshio_read_triangle(prefix, &m, err, errlen)) return -1;
    if (m.nattr < 1 || !m.vattr) {
        mesh_flat_free(&m);
        return mesh_fail(err, errlen,
                         "%s.node: a background mesh needs one attribute per vertex (the target "
                         "edge length there)",
                         prefix);
    }
    S->bnv = m.nverts;
    S->bnt = m.ntris;
    S->bxy = m.xy;
    S->btri = m.tri;
    S->blen = mesh_xmalloc((size_t)m.nverts + 1, sizeof(double));
    for (int32_t v = 0; v < m.nverts; v++) {
        S->bxy[2 * (size_t)v] = scale_len(S->bxy[2 * (size_t)v], e);
        S->bxy[2 * (size_t)v + 1] = scale_len(S->bxy[2 * (size_t)v + 1], e);
        S->blen[v] = scale_len(m.vattr[(size_t)v * m.nattr], e);
    }
    m.xy = NULL;
    m.tri = NULL;
    mesh_flat_free(&m);
    if (tloc_build(&S->bg, S->bxy, S->btri, S->bnt))
        return mesh_fail(err, errlen, "%s.ele: too many triangles to index", prefix);
    return 0;
}

int size_field_load(size_field *S, const char *refine_area, const char *background, int scale_exp,
                    char *err, size_t errlen) {
    memset(S, 0, sizeof *S);
    geom_init();
    int rc = 0;
    if (refine_area) rc = load_old(S, refine_area, scale_exp, err, errlen);
    if (rc == 0 && background) rc = load_background(S, background, scale_exp, err, errlen);
    if (rc) {
        size_field_free(S);
        return -1;
    }
    S->active = refine_area || background;
    return 0;
}

int size_field_unsuitable(void *ctx, const double *const p[3], double area) {
    const size_field *S = ctx;
    double c[2] = {(p[0][0] + p[1][0] + p[2][0]) / 3, (p[0][1] + p[1][1] + p[2][1]) / 3};
    if (S->oarea) {
        int32_t t = tloc_find(&S->old, c);
        if (t >= 0 && S->oarea[t] > 0 && area > S->oarea[t]) return 1;
    }
    if (S->blen) {
        int32_t t = tloc_find(&S->bg, c);
        if (t >= 0) {
            double w[3], h = 0;
            tloc_weights(&S->bg, t, c, w);
            for (int k = 0; k < 3; k++)
                h += w[k] * S->blen[S->btri[3 * (size_t)t + k]];
            if (h > 0 && area > 0.4330127018922193 * h * h) return 1;
        }
    }
    return 0;
}

void size_field_free(size_field *S) {
    tloc_free(&S->old);
    tloc_free(&S->bg);
    free(S->oxy);
    free(S->otri);
    free(S->oarea);
    free(S->bxy);
    free(S->btri);
    free(S->blen);
    memset(S, 0, sizeof *S);
}
