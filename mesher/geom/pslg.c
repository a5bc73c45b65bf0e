/* pslg: reading, checking and measuring planar straight-line graphs (Triangle's .poly/.node).
 *
 * The reader loads the whole file, walks it line by line (comments after '#' and blank lines
 * skipped), and parses every token in full (strtol/strtod must consume the token); any problem
 * becomes one "FILE:LINE: problem" message and every allocation is released.  pslg_check()
 * merges duplicate vertices (sort by (x, y)), drops repeated segments and rejects zero-length
 * and crossing segments: candidate pairs come from a uniform grid whose cells each segment
 * visits along its length, and every candidate is decided with the exact geom_orient2d.
 * pslg_domain_area() measures the domain from the PSLG alone by tracing the faces of the
 * segment arrangement (half-edges sorted around each vertex by exact angular order), so the
 * validator can compare a mesh against an independent figure; pslg_regions() maps the region
 * points onto the same faces (exact point-in-walk tests), so the validator finds each
 * triangle's region without the mesher's labels.  Invariant after pslg_check():
 * distinct vertex coordinates, distinct non-degenerate segments, no two segments meeting
 * except at shared endpoints, and no vertex inside a segment (a segment through a vertex is
 * split there, so every corner it makes with another segment is at an endpoint of both).
 */
#include "geom/pslg.h"

#include "base/base.h"

#include "geom/geom.h"
#include "geom/pslg_impl.h"

#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------- line reader ---------- */

typedef struct reader {
    const char *path;
    char *buf; /* whole file, NUL-terminated, tokenised in place */
    size_t len;
    char *next; /* start of the next unread line */
    char *cur;  /* cursor in the current line */
    long line;  /* number of the current line (1-based) */
    char *err;
    size_t errlen;
} reader;

__attribute__((format(printf, 2, 3))) static int rfail(reader *r, const char *fmt, ...) {
    char msg[384];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    snprintf(r->err, r->errlen, "%s:%ld: %s", r->path, r->line > 0 ? r->line : 1, msg);
    return -1;
}

/* Loads path into r.  Returns 0, or -1 with "PATH: cannot open: reason". */
static int reader_open(reader *r, const char *path, char *err, size_t errlen) {
    memset(r, 0, sizeof *r);
    r->path = path;
    r->err = err;
    r->errlen = errlen;
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    size_t cap = 1 << 16, n = 0;
    char *buf = mesh_xmalloc(cap, 1);
    for (;;) {
        if (!buf) {
            fclose(f);
            snprintf(err, errlen, "%s: out of memory reading the file", path);
            return -1;
        }
        n += fread(buf + n, 1, cap - n - 1, f);
        if (n < cap - 1) break;
        char *nb = cap > SIZE_MAX / 2 ? NULL : mesh_xrealloc(buf, cap * 2, 1);
        if (!nb) free(buf);
        buf = nb;
        cap *= 2;
    }
    int bad = ferror(f);
    fclose(f);
    if (bad) {
        free(buf);
        snprintf(err, errlen, "%s: cannot read: %s", path, strerror(errno));
        return -1;
    }
    buf[n] = '\0';
    r->buf = buf;
    r->len = n;
    r->next = buf;
    return 0;
}

static void reader_close(reader *r) {
    free(r->buf);
    r->buf = NULL;
}

/* Advances to the next line holding data (comments and blank lines skipped).  Returns 1, or 0
 * at the end of the file (r->line is then the last line of the file). */
static int next_line(reader *r) {
    while (r->next && r->next < r->buf + r->len) {
        char *s = r->next;
        char *e = memchr(s, '\n', (size_t)(r->buf + r->len - s));
        if (e) {
            *e = '\0';
            r->next = e + 1;
        } else {
            e = r->buf + r->len;
            r->next = NULL;
        }
        r->line++;
        char *h = strchr(s, '#');
        if (h) *h = '\0';
        s += strspn(s, " \t\r\v\f");
        if (*s) {
            r->cur = s;
            return 1;
        }
    }
    r->cur = NULL;
    return 0;
}

/* Next token of the current line, NUL-terminated in place, or NULL at its end. */
static char *next_tok(reader *r) {
    if (!r->cur) return NULL;
    char *s = r->cur + strspn(r->cur, " \t\r\v\f");
    if (!*s) {
        r->cur = s;
        return NULL;
    }
    char *e = s + strcspn(s, " \t\r\v\f");
    if (*e) {
        *e = '\0';
        r->cur = e + 1;
    } else {
        r->cur = e;
    }
    return s;
}

/* Bytes not yet consumed: an upper bound for how many records the rest of the file can hold. */
static size_t bytes_left(const reader *r) {
    return r->next ? (size_t)(r->buf + r->len - r->next) : 0;
}

/* Decimal integer with optional sign; *end is set past the digits.  Returns 0, or -1 when
 * there are no digits or the value leaves [-INT32_MAX, INT32_MAX]. */
static int scan_long(const char *t, char **end, long *out) {
    const char *p = t;
    int neg = 0;
    if (*p == '+' || *p == '-') neg = *p++ == '-';
    long v = 0;
    const char *d = p;
    while (*p >= '0' && *p <= '9') {
        if (v > INT32_MAX / 10 + 1)
            v = (long)INT32_MAX + 1; /* saturate: reported as out of range */
        else
            v = v * 10 + (*p - '0');
        p++;
    }
    *end = (char *)p;
    if (p == d) return -1;
    *out = neg ? -v : v;
    return v > INT32_MAX ? 1 : 0;
}

/* Messages name the field: "WHAT" or "WHAT of OWNER ID". */
static void field_name(char *buf, size_t n, const char *what, const char *owner, long id) {
    if (owner)
        snprintf(buf, n, "%s of %s %ld", what, owner, id);
    else
        snprintf(buf, n, "%s", what);
}

static int parse_long(reader *r, const char *what, const char *owner, long id, long *out) {
    char *t = next_tok(r), *end, name[96];
    if (t) {
        int rc = scan_long(t, &end, out);
        if (rc == 0 && !*end) return 0;
        field_name(name, sizeof name, what, owner, id);
        if (rc > 0 && !*end) return rfail(r, "%s '%s' is out of range", name, t);
        return rfail(r, "malformed %s '%s' (not an integer)", name, t);
    }
    field_name(name, sizeof name, what, owner, id);
    return rfail(r, "missing %s", name);
}

static int parse_double(reader *r, const char *what, const char *owner, long id, double *out) {
    char *t = next_tok(r), *end, name[96];
    if (t) {
        double v = strtod(t, &end);
        if (end != t && !*end && isfinite(v)) {
            *out = v;
            return 0;
        }
        field_name(name, sizeof name, what, owner, id);
        if (end == t || *end) return rfail(r, "malformed %s '%s' (not a number)", name, t);
        return rfail(r, "%s '%s' is not finite", name, t);
    }
    field_name(name, sizeof name, what, owner, id);
    return rfail(r, "missing %s", name);
}

/* The next token of the current line without consuming it (NULL at the line's end). */
static const char *peek_tok(const reader *r) {
    if (!r->cur) return NULL;
    const char *s = r->cur + strspn(r->cur, " \t\r\v\f");
    return *s ? s : NULL;
}

/* Optional integer: absent leaves *out unchanged. */
static int parse_long_opt(reader *r, const char *what, long *out) {
    return peek_tok(r) ? parse_long(r, what, NULL, 0, out) : 0;
}

static int line_end(reader *r) {
    char *t = next_tok(r);
    if (t)
        return rfail(r, "unexpected text '%s' at the end of the line (comments start with '#')", t);
    return 0;
}

/* Reads a count: a non-negative integer that the rest of the file can hold (each record takes
 * at least min_bytes characters) and that is allocatable. */
static int check_count(reader *r, const char *what, long n, size_t min_bytes) {
    if (n < 0) return rfail(r, "negative %s count %ld", what, n);
    if ((size_t)n > INT32_MAX / 8) return rfail(r, "%s count %ld is too large", what, n);
    if ((size_t)n * min_bytes > bytes_left(r) + 1)
        return rfail(r, "%s count %ld is more than the rest of the file can hold", what, n);
    return 0;
}

static int eof_fail(reader *r, const char *what, long got, long want) {
    return rfail(r, "unexpected end of file: expected %ld %s, found %ld", want, what, got);
}

/* ---------------------------------------------------------------- reading --------------- */

void pslg_free(pslg *g) {
    if (!g) return;
    free(g->xy);
    free(g->vmarker);
    free(g->vattr);
    free(g->vline);
    free(g->seg);
    free(g->smarker);
    free(g->sline);
    free(g->holes);
    free(g->regions);
    memset(g, 0, sizeof *g);
}

/* Reads the vertex section whose header line is current in r. */
static int read_vertices(reader *r, pslg *g) {
    long n, dim = 2, nattr = 0, nmark = 0;
    if (parse_long(r, "vertex count", NULL, 0, &n) || parse_long_opt(r, "dimension", &dim) ||
        parse_long_opt(r, "attribute count", &nattr) ||
        parse_long_opt(r, "boundary marker count", &nmark) || line_end(r))
        return -1;
    long hline = r->line;
    if (check_count(r, "vertex", n, 5)) return -1;
    if (dim != 2) return rfail(r, "dimension must be 2, not %ld", dim);
    if (nattr < 0 || nattr > 1000)
        return rfail(r, "attribute count %ld out of range [0, 1000]", nattr);
    if (nmark != 0 && nmark != 1)
        return rfail(r, "boundary marker count must be 0 or 1, not %ld", nmark);
    if (n > 0 && (size_t)n * (size_t)(nattr + 1) > bytes_left(r) + 1)
        return rfail(r, "vertex count %ld is more than the rest of the file can hold", n);
    g->nverts = (int32_t)n;
    g->nattr = (int)nattr;
    g->xy = mesh_xcalloc((size_t)n * 2, sizeof(double));
    g->vmarker = mesh_xcalloc((size_t)n, sizeof(int32_t));
    g->vline = mesh_xcalloc((size_t)n, sizeof(int32_t));
    g->vattr = nattr ? mesh_xcalloc((size_t)n * (size_t)nattr, sizeof(double)) : NULL;
    if (!g->xy || !g->vmarker || !g->vline || (nattr && !g->vattr))
        return rfail(r, "out of memory for %ld vertices", n);
    for (long i = 0; i < n; i++) {
        if (!next_line(r)) return eof_fail(r, "vertices", i, n);
        long id;
        if (parse_long(r, "vertex number", NULL, 0, &id)) return -1;
        if (i == 0) {
            if (id != 0 && id != 1)
                return rfail(r, "first vertex number must be 0 or 1, not %ld", id);
            g->first_index = (int)id;
        } else if (id != g->first_index + i) {
            return rfail(r,
                         "vertex number %ld out of sequence (expected %ld: line %ld declares %ld "
                         "vertices)",
                         id, g->first_index + i, hline, n);
        }
        if (parse_double(r, "x coordinate", "vertex", id, &g->xy[2 * i]) ||
            parse_double(r, "y coordinate", "vertex", id, &g->xy[2 * i + 1]))
            return -1;
        for (long k = 0; k < nattr; k++)
            if (parse_double(r, "an attribute", "vertex", id, &g->vattr[i * nattr + k])) return -1;
        if (nmark) {
            long mk;
            if (parse_long(r, "boundary marker", "vertex", id, &mk)) return -1;
            g->vmarker[i] = (int32_t)mk;
        }
        if (line_end(r)) return -1;
        g->vline[i] = (int32_t)r->line;
    }
    return 0;
}

static void node_path_of(const char *poly, char *out, size_t outlen) {
    size_t n = strlen(poly);
    if (n >= 5 && strcmp(poly + n - 5, ".poly") == 0) n -= 5;
    snprintf(out, outlen, "%.*s.node", (int)n, poly);
}

static int ends_with(const char *s, const char *suffix) {
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && strcmp(s + n - k, suffix) == 0;
}

/* Reads a whole .node file into g. */
static int read_node_file(const char *path, pslg *g, char *err, size_t errlen) {
    reader r;
    if (reader_open(&r, path, err, errlen)) return -1;
    snprintf(g->path, sizeof g->path, "%s", path);
    int rc = -1;
    if (!next_line(&r)) {
        rfail(&r, "empty file: expected a vertex count");
        goto out;
    }
    if (read_vertices(&r, g)) goto out;
    if (next_line(&r)) {
        rfail(&r, "unexpected data after %d vertices", (int)g->nverts);
        goto out;
    }
    rc = 0;
out:
    reader_close(&r);
    return rc;
}

/* The .poly reader.  skip_node: do not read the .node file when the vertex count is 0; check
 * indices against (nv, first) instead. */
static int read_poly(const char *path, pslg *g, int skip_node, int32_t nv, int first, char *err,
                     size_t errlen) {
    reader r;
    if (reader_open(&r, path, err, errlen)) return -1;
    snprintf(g->path, sizeof g->path, "%s", path);
    snprintf(g->segpath, sizeof g->segpath, "%s", path);
    int rc = -1;
    if (!next_line(&r)) {
        rfail(&r, "empty file: expected a vertex count");
        goto out;
    }
    {
        const char *t = peek_tok(&r);
        size_t tl = strcspn(t, " \t\r\v\f");
        int zero = tl > 0 && strspn(t, "+-0") == tl; /* the count is 0 (else read normally) */
        if (zero) {
            pslg tmp = {0};
            if (read_vertices(&r, &tmp)) { /* validates the header line */
                pslg_free(&tmp);
                goto out;
            }
            pslg_free(&tmp);
            if (skip_node) {
                g->first_index = first;
            } else {
                char np[520];
                node_path_of(path, np, sizeof np);
                if (read_node_file(np, g, err, errlen)) goto out;
                nv = g->nverts;
                first = g->first_index;
            }
        } else {
            if (read_vertices(&r, g)) goto out;
            nv = g->nverts;
            first = g->first_index;
        }
    }
    /* segments */
    if (!next_line(&r)) {
        rfail(&r, "missing segments section (expected a segment count)");
        goto out;
    }
    long ns, nsm = 0;
    if (parse_long(&r, "segment count", NULL, 0, &ns) ||
        parse_long_opt(&r, "segment boundary marker count", &nsm) || line_end(&r))
        goto out;
    if (check_count(&r, "segment", ns, 5)) goto out;
    if (nsm != 0 && nsm != 1) {
        rfail(&r, "segment boundary marker count must be 0 or 1, not %ld", nsm);
        goto out;
    }
    g->nsegs = (int32_t)ns;
    g->seg = mesh_xcalloc((size_t)ns * 2, sizeof(int32_t));
    g->smarker = mesh_xcalloc((size_t)ns, sizeof(int32_t));
    g->sline = mesh_xcalloc((size_t)ns, sizeof(int32_t));
    if (!g->seg || !g->smarker || !g->sline) {
        rfail(&r, "out of memory for %ld segments", ns);
        goto out;
    }
    for (long i = 0; i < ns; i++) {
        if (!next_line(&r)) {
            eof_fail(&r, "segments", i, ns);
            goto out;
        }
        long id, e[2], mk = 0;
        if (parse_long(&r, "segment number", NULL, 0, &id)) goto out;
        for (int k = 0; k < 2; k++) {
            if (parse_long(&r, k ? "endpoint 2" : "endpoint 1", "segment", id, &e[k])) goto out;
            if (e[k] < first || e[k] >= (long)first + nv) {
                rfail(&r, "segment %ld: vertex %ld out of range [%d, %ld]", id, e[k], first,
                      (long)first + nv - 1);
                goto out;
            }
            g->seg[2 * i + k] = (int32_t)(e[k] - first);
        }
        if (nsm && parse_long(&r, "boundary marker", "segment", id, &mk)) goto out;
        if (line_end(&r)) goto out;
        g->smarker[i] = (int32_t)mk;
        g->sline[i] = (int32_t)r.line;
    }
    /* holes (a missing section means none) */
    if (!next_line(&r)) {
        rc = 0;
        goto out;
    }
    long nh;
    if (parse_long(&r, "hole count", NULL, 0, &nh) || line_end(&r) ||
        check_count(&r, "hole", nh, 5))
        goto out;
    g->nholes = (int32_t)nh;
    g->holes = mesh_xcalloc((size_t)nh * 2, sizeof(double));
    if (!g->holes) {
        rfail(&r, "out of memory for %ld holes", nh);
        goto out;
    }
    for (long i = 0; i < nh; i++) {
        long id;
        if (!next_line(&r)) {
            eof_fail(&r, "holes", i, nh);
            goto out;
        }
        if (parse_long(&r, "hole number", NULL, 0, &id) ||
            parse_double(&r, "x", "hole", id, &g->holes[2 * i]) ||
            parse_double(&r, "y", "hole", id, &g->holes[2 * i + 1]) || line_end(&r))
            goto out;
    }
    /* optional regional attributes */
    if (!next_line(&r)) {
        rc = 0;
        goto out;
    }
    long nr;
    if (parse_long(&r, "region count", NULL, 0, &nr) || line_end(&r) ||
        check_count(&r, "region", nr, 5))
        goto out;
    g->nregions = (int32_t)nr;
    g->regions = mesh_xcalloc((size_t)nr * 4, sizeof(double));
    if (!g->regions) {
        rfail(&r, "out of memory for %ld regions", nr);
        goto out;
    }
    for (long i = 0; i < nr; i++) {
        long id;
        double *q = g->regions + 4 * i;
        if (!next_line(&r)) {
            eof_fail(&r, "regions", i, nr);
            goto out;
        }
        q[2] = 0;
        q[3] = -1;
        if (parse_long(&r, "region number", NULL, 0, &id) ||
            parse_double(&r, "x", "region", id, &q[0]) ||
            parse_double(&r, "y", "region", id, &q[1]))
            goto out;
        if (peek_tok(&r)) {
            if (parse_double(&r, "attribute", "region", id, &q[2])) goto out;
            /* one value serves as both attribute and area bound (Triangle's .poly format) */
            q[3] = q[2];
        }
        if (peek_tok(&r) && parse_double(&r, "maximum area", "region", id, &q[3])) goto out;
        if (line_end(&r)) goto out;
    }
    if (next_line(&r)) {
        rfail(&r, "unexpected data after the regions section");
        goto out;
    }
    rc = 0;
out:
    reader_close(&r);
    return rc;
}

int pslg_read(const char *path, pslg *out, char *err, size_t errlen) {
    memset(out, 0, sizeof *out);
    if (errlen) err[0] = '\0';
    int rc;
    if (ends_with(path, ".node")) {
        rc = read_node_file(path, out, err, errlen);
        snprintf(out->segpath, sizeof out->segpath, "%s", path);
    } else {
        rc = read_poly(path, out, 0, 0, 0, err, errlen);
    }
    if (rc) pslg_free(out);
    return rc;
}

int pslg_read_segments(const char *path, int32_t nverts, int first_index, pslg *out, char *err,
                       size_t errlen) {
    memset(out, 0, sizeof *out);
    if (errlen) err[0] = '\0';
    int rc = read_poly(path, out, 1, nverts, first_index, err, errlen);
    if (rc) pslg_free(out);
    return rc;
}

/* ---------------------------------------------------------------- sorting helper -------- */

typedef int (*cmp_fn)(const void *ctx, int32_t a, int32_t b);

/* Stable merge sort of a[0..n) with a context comparator; tmp has room for n items. */
static void msort(int32_t *a, int32_t *tmp, int32_t n, cmp_fn cmp, const void *ctx) {
    if (n <= 16) {
        for (int32_t i = 1; i < n; i++) {
            int32_t v = a[i], j = i;
            while (j > 0 && cmp(ctx, a[j - 1], v) > 0) {
                a[j] = a[j - 1];
                j--;
            }
            a[j] = v;
        }
        return;
    }
    int32_t h = n / 2;
    msort(a, tmp, h, cmp, ctx);
    msort(a + h, tmp, n - h, cmp, ctx);
    int32_t i = 0, j = h, k = 0;
    while (i < h && j < n)
        tmp[k++] = cmp(ctx, a[j], a[i]) < 0 ? a[j++] : a[i++];
    while (i < h)
        tmp[k++] = a[i++];
    while (j < n)
        tmp[k++] = a[j++];
    memcpy(a, tmp, (size_t)n * sizeof *a);
}

/* ---------------------------------------------------------------- uniform grid ---------- */

typedef struct grid {
    double x0, y0, cw, ch;
    int nx, ny;
    int32_t *start; /* nx*ny + 1 */
    int32_t *item;
} grid;

static void grid_setup(grid *gr, double x0, double y0, double x1, double y1, long n) {
    memset(gr, 0, sizeof *gr);
    double w = x1 - x0, h = y1 - y0;
    long nx = 1, ny = 1;
    if (n < 1) n = 1;
    if (w > 0 && h > 0) { /* clamped as doubles: a thin box's ratio may exceed a long */
        double fx = ceil(sqrt((double)n * w / h)), fy = ceil(sqrt((double)n * h / w));
        nx = fx >= 1 && fx <= 2048 ? (long)fx : fx > 2048 ? 2048 : 1;
        ny = fy >= 1 && fy <= 2048 ? (long)fy : fy > 2048 ? 2048 : 1;
    } else if (w > 0) {
        nx = n;
    } else if (h > 0) {
        ny = n;
    }
    nx = nx < 1 ? 1 : nx > 2048 ? 2048 : nx;
    ny = ny < 1 ? 1 : ny > 2048 ? 2048 : ny;
    gr->x0 = x0;
    gr->y0 = y0;
    gr->nx = (int)nx;
    gr->ny = (int)ny;
    gr->cw = w > 0 ? w / nx : 1;
    gr->ch = h > 0 ? h / ny : 1;
}

static int grid_cx(const grid *gr, double x) {
    double c = (x - gr->x0) / gr->cw;
    if (!(c > 0)) return 0;
    return c >= gr->nx - 1 ? gr->nx - 1 : (int)c;
}

static int grid_cy(const grid *gr, double y) {
    double c = (y - gr->y0) / gr->ch;
    if (!(c > 0)) return 0;
    return c >= gr->ny - 1 ? gr->ny - 1 : (int)c;
}

/* Calls visit(ctx, cell) for every cell the segment ab passes near (row by row, padded by one
 * cell in x so rounding cannot lose a cell). */
static void grid_segment(const grid *gr, const double *a, const double *b,
                         void (*visit)(void *, int32_t), void *ctx) {
    double ylo = fmin(a[1], b[1]), yhi = fmax(a[1], b[1]);
    int j0 = grid_cy(gr, ylo), j1 = grid_cy(gr, yhi);
    int bx0 = grid_cx(gr, fmin(a[0], b[0])), bx1 = grid_cx(gr, fmax(a[0], b[0]));
    for (int j = j0; j <= j1; j++) {
        int i0 = bx0, i1 = bx1;
        if (j0 != j1) {
            double s0 = fmax(ylo, gr->y0 + j * gr->ch), s1 = fmin(yhi, gr->y0 + (j + 1) * gr->ch);
            double k = (b[0] - a[0]) / (b[1] - a[1]);
            double xa = a[0] + (s0 - a[1]) * k, xb = a[0] + (s1 - a[1]) * k;
            int c0 = grid_cx(gr, fmin(xa, xb)) - 1, c1 = grid_cx(gr, fmax(xa, xb)) + 1;
            if (c0 > i0) i0 = c0;
            if (c1 < i1) i1 = c1;
        }
        for (int i = i0; i <= i1; i++)
            visit(ctx, (int32_t)j * gr->nx + i);
    }
}

typedef struct fill_ctx {
    grid *gr;
    int32_t id;
    int counting;
} fill_ctx;

static void grid_visit(void *vctx, int32_t cell) {
    fill_ctx *c = vctx;
    if (c->counting)
        c->gr->start[cell + 1]++;
    else
        c->gr->item[c->gr->start[cell]++] = c->id;
}

/* Buckets the segments listed in ids[0..n) (endpoint pairs in seg, coordinates in xy) into a
 * grid over the bounding box of their endpoints.  Returns 0 or -1 (out of memory). */
static int grid_build_segments(grid *gr, const double *xy, const int32_t *seg, const int32_t *ids,
                               int32_t n) {
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int32_t i = 0; i < n; i++)
        for (int k = 0; k < 2; k++) {
            const double *p = xy + 2 * seg[2 * ids[i] + k];
            x0 = fmin(x0, p[0]);
            x1 = fmax(x1, p[0]);
            y0 = fmin(y0, p[1]);
            y1 = fmax(y1, p[1]);
        }
    if (n == 0) x0 = y0 = x1 = y1 = 0;
    grid_setup(gr, x0, y0, x1, y1, n);
    size_t ncell = (size_t)gr->nx * gr->ny;
    gr->start = mesh_xcalloc(ncell + 1, sizeof(int32_t));
    if (!gr->start) return -1;
    fill_ctx c = {gr, 0, 1};
    for (int32_t i = 0; i < n; i++) {
        const int32_t *s = seg + 2 * ids[i];
        grid_segment(gr, xy + 2 * s[0], xy + 2 * s[1], grid_visit, &c);
        if (gr->start[ncell] > INT32_MAX / 2) /* cell count overflow guard (absurd inputs) */
            return -1;
    }
    for (size_t i = 0; i < ncell; i++)
        gr->start[i + 1] += gr->start[i];
    gr->item = mesh_xmalloc(((size_t)gr->start[ncell] + 1) * sizeof(int32_t), 1);
    if (!gr->item) return -1;
    c.counting = 0;
    for (int32_t i = 0; i < n; i++) {
        const int32_t *s = seg + 2 * ids[i];
        c.id = ids[i];
        grid_segment(gr, xy + 2 * s[0], xy + 2 * s[1], grid_visit, &c);
    }
    for (size_t i = ncell; i > 0; i--)
        gr->start[i] = gr->start[i - 1];
    gr->start[0] = 0;
    return 0;
}

static void grid_free(grid *gr) {
    free(gr->start);
    free(gr->item);
    gr->start = gr->item = NULL;
}

/* ---------------------------------------------------------------- exact tests ----------- */

static int sgn(double v) {
    return (v > 0) - (v < 0);
}

/* For collinear s, p, q with p, q != s: 1 if p and q lie on the same side of s. */
static int same_direction(const double *s, const double *p, const double *q) {
    if (p[0] != s[0]) return (p[0] > s[0]) == (q[0] > s[0]);
    return (p[1] > s[1]) == (q[1] > s[1]);
}

/* 1 if p (collinear with ab) lies strictly between a and b. */
static int strictly_between(const double *a, const double *b, const double *p) {
    int k = a[0] != b[0] ? 0 : 1;
    double lo = fmin(a[k], b[k]), hi = fmax(a[k], b[k]);
    return p[k] > lo && p[k] < hi;
}

/* 1 if segments ab and cd (vertex indices) cross in their interiors or overlap collinearly.
 * Touching at a shared endpoint or at a vertex inside the other segment is allowed. */
static int segs_conflict(const double *xy, int32_t a, int32_t b, int32_t c, int32_t d) {
    const double *A = xy + 2 * a, *B = xy + 2 * b, *C = xy + 2 * c, *D = xy + 2 * d;
    if (a == c || a == d || b == c || b == d) {
        const double *S, *P, *Q;
        if (a == c || a == d) {
            S = A;
            P = B;
            Q = a == c ? D : C;
        } else {
            S = B;
            P = A;
            Q = b == c ? D : C;
        }
        if (P == Q || (P[0] == Q[0] && P[1] == Q[1])) return 1;
        if (geom_orient2d(S, P, Q) != 0) return 0;
        return same_direction(S, P, Q);
    }
    int o1 = sgn(geom_orient2d(A, B, C)), o2 = sgn(geom_orient2d(A, B, D));
    if (o1 == 0 && o2 == 0) {
        int k = A[0] != B[0] ? 0 : 1;
        double lo1 = fmin(A[k], B[k]), hi1 = fmax(A[k], B[k]);
        double lo2 = fmin(C[k], D[k]), hi2 = fmax(C[k], D[k]);
        return fmax(lo1, lo2) < fmin(hi1, hi2);
    }
    if (o1 * o2 >= 0) return 0;
    int o3 = sgn(geom_orient2d(C, D, A)), o4 = sgn(geom_orient2d(C, D, B));
    return o3 * o4 < 0;
}

/* ---------------------------------------------------------------- pslg_check ------------ */

typedef struct vkey {
    double x, y;
    int32_t i;
} vkey;

static int cmp_vkey(const void *pa, const void *pb) {
    const vkey *a = pa, *b = pb;
    if (a->x != b->x) return a->x < b->x ? -1 : 1;
    if (a->y != b->y) return a->y < b->y ? -1 : 1;
    return (a->i > b->i) - (a->i < b->i);
}

typedef struct skey {
    int32_t lo, hi, i;
} skey;

static int cmp_skey(const void *pa, const void *pb) {
    const skey *a = pa, *b = pb;
    if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
    return (a->i > b->i) - (a->i < b->i);
}

__attribute__((format(printf, 3, 4))) static int gfail(char *err, size_t errlen, const char *fmt,
                                                       ...) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
    return -1;
}

/* ---------------------------------------------------------------- scaling --------------- */

/* 1 iff x * 2^e is a multiple of 2^PSLG_GRID_EXP (0 included); x * 2^e is at most 2^100. */
static int on_grid(double x, int e) {
    if (x == 0) return 1;
    double y = ldexp(x, e - PSLG_GRID_EXP);
    return y != 0 && y == floor(y);
}

static double scale_area(double a, int e) {
    if (!(a > 0)) return a;
    double s = ldexp(a, 2 * e);
    return s > 0 ? s : DBL_MIN; /* a bound that underflowed stays a bound */
}

/* Scales g by an exact power of two into the predicates' working range (pslg.h). */
static int pslg_scale(pslg *g, char *err, size_t errlen) {
    const char *vf = g->path[0] ? g->path : "(input)";
    const char *sf = g->segpath[0] ? g->segpath : vf;
    double big = 0;
    for (int32_t i = 0; i < 2 * g->nverts; i++)
        big = fmax(big, fabs(g->xy[i]));
    for (int32_t i = 0; i < 2 * g->nholes; i++)
        if (isfinite(g->holes[i])) big = fmax(big, fabs(g->holes[i]));
    for (int32_t i = 0; i < g->nregions; i++)
        for (int k = 0; k < 2; k++)
            if (isfinite(g->regions[4 * i + k])) big = fmax(big, fabs(g->regions[4 * i + k]));
    if (big == 0) return 0;
    int e = 0, k;
    if (big > 0x1p100) {
        e = 1; /* below */
    } else {
        for (int32_t i = 0; i < 2 * g->nverts && !e; i++)
            if (!on_grid(g->xy[i], 0)) e = 1;
        for (int32_t i = 0; i < 2 * g->nholes && !e; i++)
            if (isfinite(g->holes[i]) && !on_grid(g->holes[i], 0)) e = 1;
        for (int32_t i = 0; i < g->nregions && !e; i++)
            for (int j = 0; j < 2; j++)
                if (isfinite(g->regions[4 * i + j]) && !on_grid(g->regions[4 * i + j], 0)) e = 1;
    }
    if (!e) return 0; /* already in range: nothing moves, not even by a bit */
    frexp(big, &k);   /* big < 2^k */
    e = PSLG_TOP_EXP - k;
    if (e > PSLG_MAX_SCALE)
        return gfail(err, errlen,
                     "%s: the largest coordinate magnitude %.17g is below the supported range "
                     "(at least 2^%d, about 1.8e-218)",
                     vf, big, PSLG_TOP_EXP - 1 - PSLG_MAX_SCALE);
    for (int32_t i = 0; i < 2 * g->nverts; i++)
        if (!on_grid(g->xy[i], e))
            return gfail(err, errlen,
                         "%s:%d: vertex %d: coordinate %.17g is too small next to the largest "
                         "coordinate magnitude %.17g (supported: nonzero magnitudes down to "
                         "2^-247, about 4.4e-75, times the largest)",
                         vf, g->vline ? g->vline[i / 2] : 0, i / 2 + g->first_index, g->xy[i], big);
    for (int32_t i = 0; i < 2 * g->nholes; i++)
        if (isfinite(g->holes[i]) && !on_grid(g->holes[i], e))
            return gfail(err, errlen,
                         "%s: hole %d: coordinate %.17g is too small next to the largest "
                         "coordinate magnitude %.17g",
                         sf, i / 2 + g->first_index, g->holes[i], big);
    for (int32_t i = 0; i < g->nregions; i++)
        for (int j = 0; j < 2; j++)
            if (isfinite(g->regions[4 * i + j]) && !on_grid(g->regions[4 * i + j], e))
                return gfail(err, errlen,
                             "%s: region %d: coordinate %.17g is too small next to the largest "
                             "coordinate magnitude %.17g",
                             sf, i + g->first_index, g->regions[4 * i + j], big);
    for (int32_t i = 0; i < 2 * g->nverts; i++)
        g->xy[i] = ldexp(g->xy[i], e);
    for (int32_t i = 0; i < 2 * g->nholes; i++)
        g->holes[i] = ldexp(g->holes[i], e);
    for (int32_t i = 0; i < g->nregions; i++) {
        g->regions[4 * i] = ldexp(g->regions[4 * i], e);
        g->regions[4 * i + 1] = ldexp(g->regions[4 * i + 1], e);
        g->regions[4 * i + 3] = scale_area(g->regions[4 * i + 3], e);
    }
    g->scale_exp += e;
    return 0;
}

/* One normalisation pass of pslg_check_ex: merges duplicate vertices, rejects zero-length
 * segments, drops repeated ones and looks for conflicting pairs (crossing or overlapping).
 * quiet: no warnings (after a split the pieces are not the file's segments).  Without split the
 * conflict whose later segment comes first in the file is the error; with split every
 * conflicting pair goes into *pairs (s < t, two entries each, *npairs of them). */
static int normalise(pslg *g, int split, int quiet, int32_t **pairs, int64_t *npairs, char *err,
                     size_t errlen) {
    const char *vf = g->path[0] ? g->path : "(input)";
    const char *sf = g->segpath[0] ? g->segpath : vf;
    int32_t n = g->nverts;
    *pairs = NULL;
    *npairs = 0;
    /* 1. merge duplicate vertices */
    vkey *vk = mesh_xmalloc((size_t)(n ? n : 1) * sizeof *vk, 1);
    int32_t *map = mesh_xmalloc((size_t)(n ? n : 1) * sizeof *map, 1);
    if (!vk || !map) {
        free(vk);
        free(map);
        return gfail(err, errlen, "%s: out of memory checking %d vertices", vf, n);
    }
    for (int32_t i = 0; i < n; i++)
        vk[i] = (vkey){g->xy[2 * i], g->xy[2 * i + 1], i};
    qsort(vk, (size_t)n, sizeof *vk, cmp_vkey);
    int32_t ndup = 0;
    for (int32_t i = 0, rep = 0; i < n; i++) {
        if (i > 0 && vk[i].x == vk[i - 1].x && vk[i].y == vk[i - 1].y) {
            int32_t a = vk[i].i, b = vk[rep].i;
            map[a] = b;
            ndup++;
            if (!quiet && !g->quiet)
                fprintf(stderr,
                        "%s:%d: warning: vertex %d duplicates vertex %d (line %d); merged\n", vf,
                        g->vline ? g->vline[a] : 0, a + g->first_index, b + g->first_index,
                        g->vline ? g->vline[b] : 0);
            if (g->vmarker && g->vmarker[b] == 0) g->vmarker[b] = g->vmarker[a];
        } else {
            rep = i;
            map[vk[i].i] = vk[i].i;
        }
    }
    free(vk);
    if (ndup) {
        int32_t m = 0;
        int32_t *newidx = mesh_xmalloc((size_t)n * sizeof *newidx, 1);
        if (!newidx) {
            free(map);
            return gfail(err, errlen, "%s: out of memory", vf);
        }
        for (int32_t i = 0; i < n; i++) {
            if (map[i] != i) continue;
            newidx[i] = m;
            g->xy[2 * m] = g->xy[2 * i];
            g->xy[2 * m + 1] = g->xy[2 * i + 1];
            if (g->vmarker) g->vmarker[m] = g->vmarker[i];
            if (g->vline) g->vline[m] = g->vline[i];
            if (g->vattr)
                memmove(g->vattr + (size_t)m * g->nattr, g->vattr + (size_t)i * g->nattr,
                        (size_t)g->nattr * sizeof(double));
            m++;
        }
        for (int32_t i = 0; i < n; i++)
            map[i] = newidx[map[i]];
        free(newidx);
        for (int32_t s = 0; s < 2 * g->nsegs; s++)
            g->seg[s] = map[g->seg[s]];
        g->nverts = n = m;
    }
    free(map);
    /* 2. zero-length and repeated segments */
    int32_t ns = g->nsegs;
    for (int32_t s = 0; s < ns && !quiet; s++) /* pieces of a split: dropped below */
        if (g->seg[2 * s] == g->seg[2 * s + 1])
            return gfail(err, errlen, "%s:%d: segment %d has zero length (both endpoints are %s)",
                         sf, g->sline ? g->sline[s] : 0, s + g->first_index,
                         ndup ? "the same point" : "the same vertex");
    skey *sk = mesh_xmalloc((size_t)(ns ? ns : 1) * sizeof *sk, 1);
    int32_t *ids = mesh_xmalloc((size_t)(ns ? ns : 1) * sizeof *ids, 1);
    char *keep = mesh_xmalloc((size_t)(ns ? ns : 1), 1);
    if (!sk || !ids || !keep) {
        free(sk);
        free(ids);
        free(keep);
        return gfail(err, errlen, "%s: out of memory checking %d segments", sf, ns);
    }
    for (int32_t s = 0; s < ns; s++) {
        int32_t a = g->seg[2 * s], b = g->seg[2 * s + 1];
        sk[s] = (skey){a < b ? a : b, a < b ? b : a, s};
        keep[s] = 1;
    }
    qsort(sk, (size_t)ns, sizeof *sk, cmp_skey);
    for (int32_t i = 0; i < ns; i++) /* a piece whose ends merged (quiet passes only) */
        if (sk[i].lo == sk[i].hi) keep[sk[i].i] = 0;
    for (int32_t i = 1, run = 0; i < ns; i++) {
        if (sk[i].lo != sk[run].lo || sk[i].hi != sk[run].hi) {
            run = i;
        } else {
            int32_t s = sk[i].i, t = sk[run].i; /* the first of a run is kept */
            keep[s] = 0;
            if (!quiet && !g->quiet)
                fprintf(stderr,
                        "%s:%d: warning: segment %d repeats segment %d (line %d); dropped\n", sf,
                        g->sline ? g->sline[s] : 0, s + g->first_index, t + g->first_index,
                        g->sline ? g->sline[t] : 0);
        }
    }
    free(sk);
    int32_t nk = 0;
    for (int32_t s = 0; s < ns; s++)
        if (keep[s]) ids[nk++] = s;
    free(keep);
    /* 3. crossings and overlaps: grid candidates, exact decision */
    grid gr;
    int rc = 0;
    int32_t *pr = NULL;
    int64_t np = 0, pcap = 0;
    if (grid_build_segments(&gr, g->xy, g->seg, ids, nk)) {
        rc = gfail(err, errlen, "%s: out of memory checking segment crossings", sf);
    } else {
        int32_t bs = -1, bt = -1;
        size_t ncell = (size_t)gr.nx * gr.ny;
        for (size_t c = 0; c < ncell && rc == 0; c++) {
            for (int32_t i = gr.start[c]; i < gr.start[c + 1]; i++)
                for (int32_t j = i + 1; j < gr.start[c + 1]; j++) {
                    int32_t s = gr.item[i], t = gr.item[j];
                    if (s > t) {
                        int32_t x = s;
                        s = t;
                        t = x;
                    }
                    /* report the pair whose later segment comes first in the file */
                    if (!split && bt >= 0 && (t > bt || (t == bt && s >= bs))) continue;
                    if (!segs_conflict(g->xy, g->seg[2 * s], g->seg[2 * s + 1], g->seg[2 * t],
                                       g->seg[2 * t + 1]))
                        continue;
                    bs = s;
                    bt = t;
                    if (!split) continue;
                    if (np == pcap) {
                        pcap = pcap ? 2 * pcap : 64;
                        pr = mesh_xrealloc(pr, (size_t)pcap, 2 * sizeof *pr);
                    }
                    pr[2 * np] = s;
                    pr[2 * np + 1] = t;
                    np++;
                }
        }
        if (!split && bt >= 0)
            rc = gfail(err, errlen, "%s:%d: segment %d crosses segment %d (line %d)", sf,
                       g->sline ? g->sline[bt] : 0, bt + g->first_index, bs + g->first_index,
                       g->sline ? g->sline[bs] : 0);
    }
    grid_free(&gr);
    if (rc == 0 && nk < ns) { /* compact; pairs follow the segments' new numbers */
        int32_t *pos = mesh_xmalloc((size_t)ns, sizeof *pos);
        for (int32_t i = 0; i < nk; i++) {
            int32_t s = ids[i];
            pos[s] = i;
            g->seg[2 * i] = g->seg[2 * s];
            g->seg[2 * i + 1] = g->seg[2 * s + 1];
            if (g->smarker) g->smarker[i] = g->smarker[s];
            if (g->sline) g->sline[i] = g->sline[s];
        }
        for (int64_t k = 0; k < 2 * np; k++)
            pr[k] = pos[pr[k]];
        free(pos);
        g->nsegs = nk;
    }
    free(ids);
    if (rc == 0) {
        *pairs = pr;
        *npairs = np;
    } else {
        free(pr);
    }
    return rc;
}

static void split_at_vertices(pslg *g); /* below, with the arrangement */

int pslg_check_ex(pslg *g, unsigned flags, char *err, size_t errlen) {
    geom_init();
    if (errlen) err[0] = '\0';
    const char *vf = g->path[0] ? g->path : "(input)";
    const char *sf = g->segpath[0] ? g->segpath : vf;
    int32_t n = g->nverts;
    for (int32_t i = 0; i < n; i++)
        if (!isfinite(g->xy[2 * i]) || !isfinite(g->xy[2 * i + 1]))
            return gfail(err, errlen, "%s:%d: vertex %d has a non-finite coordinate", vf,
                         g->vline ? g->vline[i] : 0, i + g->first_index);
    for (int32_t s = 0; s < g->nsegs; s++)
        for (int k = 0; k < 2; k++)
            if (g->seg[2 * s + k] < 0 || g->seg[2 * s + k] >= n)
                return gfail(err, errlen, "%s:%d: segment %d: vertex %d out of range", sf,
                             g->sline ? g->sline[s] : 0, s + g->first_index,
                             g->seg[2 * s + k] + g->first_index);
    if (pslg_scale(g, err, errlen) != 0) return -1;
    int split = (flags & PSLG_SPLIT) != 0;
    for (int round = 0;; round++) {
        int32_t *pairs;
        int64_t np;
        if (normalise(g, split, round > 0, &pairs, &np, err, errlen) != 0) return -1;
        if (np == 0) {
            int32_t ns = g->nsegs;
            split_at_vertices(g);
            if (g->nsegs != ns) { /* drop pieces that repeat a segment; no new conflicts */
                if (normalise(g, split, 1, &pairs, &np, err, errlen) != 0) return -1;
                free(pairs);
            }
            if (flags & PSLG_HULL) pslg_enclose_hull(g); /* pslg_hull.c */
            return 0;
        }
        int rc = 0;
        if (round == PSLG_SPLIT_ROUNDS) {
            int32_t s = pairs[0], t = pairs[1];
            rc = gfail(err, errlen,
                       "%s:%d: the segment on this line crosses the segment on line %d, and "
                       "splitting them at their intersection keeps making new crossings "
                       "(intersection points rounded to doubles; the segments are too close to "
                       "resolve): move them apart, or use --strict to see the first crossing",
                       sf, g->sline ? g->sline[t] : 0, g->sline ? g->sline[s] : 0);
        } else {
            rc = pslg_split_pairs(g, pairs, np, err, errlen);
        }
        free(pairs);
        if (rc != 0) return -1;
    }
}

int pslg_check(pslg *g, char *err, size_t errlen) {
    return pslg_check_ex(g, 0, err, errlen);
}

/* ---------------------------------------------------------------- arrangement ----------- */

/* Half-edge structure of the segment arrangement: edges split at vertices lying on them,
 * outgoing half-edges of each vertex sorted counter-clockwise. */
typedef struct arr {
    const double *xy;
    int32_t nv, ne;  /* vertices, undirected edges */
    int32_t *org;    /* 2*ne: origin of half-edge h; h^1 is its twin */
    int32_t *vstart; /* nv+1: outgoing half-edges of v are out[vstart[v] .. vstart[v+1]) */
    int32_t *out;    /* 2*ne */
    int32_t *pos;    /* 2*ne: position of h in out */
} arr;

static int quadrant(double dx, double dy) {
    if (dx > 0 && dy >= 0) return 0;
    if (dx <= 0 && dy > 0) return 1;
    if (dx < 0 && dy <= 0) return 2;
    return 3;
}

/* Angular order of half-edges leaving the same vertex (exact). */
static int cmp_angle(const void *ctx, int32_t h1, int32_t h2) {
    const arr *A = ctx;
    const double *o = A->xy + 2 * A->org[h1];
    const double *p = A->xy + 2 * A->org[h1 ^ 1], *q = A->xy + 2 * A->org[h2 ^ 1];
    int q1 = quadrant(p[0] - o[0], p[1] - o[1]), q2 = quadrant(q[0] - o[0], q[1] - o[1]);
    if (q1 != q2) return q1 < q2 ? -1 : 1;
    double d = geom_orient2d(o, p, q);
    return d > 0 ? -1 : d < 0 ? 1 : 0;
}

typedef struct split_ctx {
    const pslg *g;
    const grid *vg;
    int32_t s;
    int32_t *hits; /* growable list of (segment, vertex) pairs */
    size_t nhits, cap;
    int oom;
} split_ctx;

static void split_visit(void *vctx, int32_t cell) {
    split_ctx *c = vctx;
    const double *xy = c->g->xy;
    int32_t a = c->g->seg[2 * c->s], b = c->g->seg[2 * c->s + 1];
    for (int32_t i = c->vg->start[cell]; i < c->vg->start[cell + 1]; i++) {
        int32_t v = c->vg->item[i];
        if (v == a || v == b) continue;
        const double *A = xy + 2 * a, *B = xy + 2 * b, *P = xy + 2 * v;
        if (P[0] < fmin(A[0], B[0]) || P[0] > fmax(A[0], B[0]) || P[1] < fmin(A[1], B[1]) ||
            P[1] > fmax(A[1], B[1]))
            continue;
        if (geom_orient2d(A, B, P) != 0 || !strictly_between(A, B, P)) continue;
        /* each vertex lives in one cell and a segment visits a cell once: no repeats */
        if (c->nhits == c->cap) {
            size_t nc = c->cap ? 2 * c->cap : 64;
            int32_t *nh = mesh_xrealloc(c->hits, nc * 2 * sizeof(int32_t), 1);
            if (!nh) {
                c->oom = 1;
                return;
            }
            c->hits = nh;
            c->cap = nc;
        }
        c->hits[2 * c->nhits] = c->s;
        c->hits[2 * c->nhits + 1] = v;
        c->nhits++;
    }
}

/* Position of vertex v along segment s (for sorting split points). */
typedef struct along_ctx {
    const double *xy;
    const int32_t *hits;
    const double *a, *b;
} along_ctx;

static int cmp_along(const void *vctx, int32_t i, int32_t j) {
    const along_ctx *c = vctx;
    int k = c->a[0] != c->b[0] ? 0 : 1;
    double pi = c->xy[2 * c->hits[2 * i + 1] + k], pj = c->xy[2 * c->hits[2 * j + 1] + k];
    double dir = c->b[k] > c->a[k] ? 1 : -1;
    return pi == pj ? 0 : (pi - pj) * dir < 0 ? -1 : 1;
}

static void arr_free(arr *A) {
    free(A->org);
    free(A->vstart);
    free(A->out);
    free(A->pos);
}

/* The vertices of g lying strictly inside its segments (exact orient2d and bounds): sc->hits
 * gets (segment, vertex) pairs grouped by segment in segment order.  vg is filled with a grid
 * of the vertices (caller frees).  Returns 0 or -1 (out of memory). */
static int vertex_hits(const pslg *g, grid *vg, split_ctx *sc) {
    int32_t n = g->nverts, ns = g->nsegs;
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int32_t i = 0; i < n; i++) {
        x0 = fmin(x0, g->xy[2 * i]);
        x1 = fmax(x1, g->xy[2 * i]);
        y0 = fmin(y0, g->xy[2 * i + 1]);
        y1 = fmax(y1, g->xy[2 * i + 1]);
    }
    if (n == 0) x0 = x1 = y0 = y1 = 0;
    grid_setup(vg, x0, y0, x1, y1, n);
    size_t ncell = (size_t)vg->nx * vg->ny;
    vg->start = mesh_xcalloc(ncell + 1, sizeof(int32_t));
    vg->item = mesh_xmalloc((size_t)(n ? n : 1) * sizeof(int32_t), 1);
    for (int32_t i = 0; i < n; i++)
        vg->start[grid_cy(vg, g->xy[2 * i + 1]) * vg->nx + grid_cx(vg, g->xy[2 * i]) + 1]++;
    for (size_t c = 0; c < ncell; c++)
        vg->start[c + 1] += vg->start[c];
    for (int32_t i = 0; i < n; i++)
        vg->item[vg->start[grid_cy(vg, g->xy[2 * i + 1]) * vg->nx + grid_cx(vg, g->xy[2 * i])]++] =
            i;
    for (size_t c = ncell; c > 0; c--)
        vg->start[c] = vg->start[c - 1];
    vg->start[0] = 0;
    sc->g = g;
    sc->vg = vg;
    for (int32_t s = 0; s < ns; s++) {
        sc->s = s;
        grid_segment(vg, g->xy + 2 * g->seg[2 * s], g->xy + 2 * g->seg[2 * s + 1], split_visit, sc);
        if (sc->oom) return -1;
    }
    return 0;
}

/* Sorts the hits of one segment (order[0..m), indices into sc->hits) from a to b. */
static void hits_along(const pslg *g, const split_ctx *sc, int32_t s, int32_t *order, int32_t *tmp,
                       int32_t m) {
    along_ctx ac = {g->xy, sc->hits, g->xy + 2 * g->seg[2 * s], g->xy + 2 * g->seg[2 * s + 1]};
    msort(order, tmp, m, cmp_along, &ac);
}

/* Splits every segment at the vertices lying strictly inside it, so that afterwards a segment
 * meets other vertices only at its endpoints: the refinement rules then see every corner a
 * segment makes with the others at a vertex (incidences, small input angles), and the pieces
 * keep the segment's marker and line.  Exact; adds no vertex, so no crossing.  Repeated pieces
 * (a piece that is also an input segment) are left to the next normalisation. */
static void split_at_vertices(pslg *g) {
    grid vg = {0};
    split_ctx sc = {0};
    vertex_hits(g, &vg, &sc); /* the funnel never fails: no out-of-memory return to handle */
    grid_free(&vg);
    if (sc.nhits == 0) {
        free(sc.hits);
        return;
    }
    int32_t ns = g->nsegs;
    size_t cap = (size_t)ns + sc.nhits;
    int32_t *seg = mesh_xmalloc(cap, 2 * sizeof(int32_t));
    int32_t *smk = g->smarker ? mesh_xmalloc(cap, sizeof(int32_t)) : NULL;
    int32_t *sln = g->sline ? mesh_xmalloc(cap, sizeof(int32_t)) : NULL;
    int32_t *order = mesh_xmalloc(sc.nhits, sizeof *order);
    int32_t *tmp = mesh_xmalloc(sc.nhits, sizeof *tmp);
    size_t n = 0, h = 0;
    for (int32_t s = 0; s < ns; s++) {
        size_t h0 = h;
        while (h < sc.nhits && sc.hits[2 * h] == s)
            h++;
        int32_t m = (int32_t)(h - h0);
        for (int32_t i = 0; i < m; i++)
            order[i] = (int32_t)(h0 + (size_t)i);
        hits_along(g, &sc, s, order, tmp, m);
        int32_t prev = g->seg[2 * s];
        for (int32_t i = 0; i <= m; i++) {
            int32_t v = i < m ? sc.hits[2 * order[i] + 1] : g->seg[2 * s + 1];
            seg[2 * n] = prev;
            seg[2 * n + 1] = v;
            if (smk) smk[n] = g->smarker[s];
            if (sln) sln[n] = g->sline[s];
            n++;
            prev = v;
        }
    }
    free(order);
    free(tmp);
    free(sc.hits);
    pslg_set_segments(g, seg, smk, sln, (int32_t)n);
}

/* Builds the arrangement of g's segments.  Returns 0 or -1 (out of memory). */
static int arr_build(const pslg *g, arr *A) {
    memset(A, 0, sizeof *A);
    A->xy = g->xy;
    A->nv = g->nverts;
    int32_t n = g->nverts, ns = g->nsegs;
    int rc = -1;
    split_ctx sc = {0};
    grid vg = {0};
    skey *ek = NULL;
    int32_t *order = NULL, *tmp = NULL;
    /* vertices lying inside segments */
    if (vertex_hits(g, &vg, &sc)) goto out;
    /* sub-edges: hits are grouped by segment already (segments visited in order) */
    size_t nsub = (size_t)(ns > 0 ? ns : 0) + sc.nhits;
    ek = mesh_xmalloc((nsub ? nsub : 1) * sizeof *ek, 1);
    order = mesh_xmalloc((sc.nhits ? sc.nhits : 1) * sizeof *order, 1);
    tmp = mesh_xmalloc((sc.nhits ? sc.nhits : 1) * sizeof *tmp, 1);
    if (!ek || !order || !tmp) goto out;
    size_t ne = 0, h = 0;
    for (int32_t s = 0; s < ns; s++) {
        int32_t a = g->seg[2 * s], b = g->seg[2 * s + 1];
        size_t h0 = h;
        while (h < sc.nhits && sc.hits[2 * h] == s)
            h++;
        int32_t m = (int32_t)(h - h0);
        for (int32_t i = 0; i < m; i++)
            order[i] = (int32_t)(h0 + (size_t)i);
        hits_along(g, &sc, s, order, tmp, m);
        int32_t prev = a;
        for (int32_t i = 0; i <= m; i++) {
            int32_t v = i < m ? sc.hits[2 * order[i] + 1] : b;
            if (v != prev) ek[ne++] = (skey){prev < v ? prev : v, prev < v ? v : prev, 0};
            prev = v;
        }
    }
    qsort(ek, ne, sizeof *ek, cmp_skey);
    size_t m = 0;
    for (size_t i = 0; i < ne; i++)
        if (m == 0 || ek[i].lo != ek[m - 1].lo || ek[i].hi != ek[m - 1].hi) ek[m++] = ek[i];
    ne = m;
    A->ne = (int32_t)ne;
    A->org = mesh_xmalloc((2 * ne + 1) * sizeof(int32_t), 1);
    A->out = mesh_xmalloc((2 * ne + 1) * sizeof(int32_t), 1);
    A->pos = mesh_xmalloc((2 * ne + 1) * sizeof(int32_t), 1);
    A->vstart = mesh_xcalloc((size_t)n + 2, sizeof(int32_t));
    free(tmp);
    tmp = mesh_xmalloc((2 * ne + 1) * sizeof(int32_t), 1);
    if (!A->org || !A->out || !A->pos || !A->vstart || !tmp) goto out;
    for (size_t e = 0; e < ne; e++) {
        A->org[2 * e] = ek[e].lo;
        A->org[2 * e + 1] = ek[e].hi;
        A->vstart[ek[e].lo + 1]++;
        A->vstart[ek[e].hi + 1]++;
    }
    for (int32_t v = 0; v < n; v++)
        A->vstart[v + 1] += A->vstart[v];
    for (int32_t hh = 0; hh < (int32_t)(2 * ne); hh++)
        A->out[A->vstart[A->org[hh]]++] = hh;
    for (int32_t v = n; v > 0; v--)
        A->vstart[v] = A->vstart[v - 1];
    A->vstart[0] = 0;
    for (int32_t v = 0; v < n; v++) {
        int32_t *o = A->out + A->vstart[v];
        int32_t d = A->vstart[v + 1] - A->vstart[v];
        msort(o, tmp, d, cmp_angle, A);
        for (int32_t i = 0; i < d; i++)
            A->pos[o[i]] = A->vstart[v] + i;
    }
    rc = 0;
out:
    if (rc) arr_free(A);
    free(sc.hits);
    grid_free(&vg);
    free(ek);
    free(order);
    free(tmp);
    return rc;
}

/* The half-edge after h on the face to the left of h. */
static int32_t arr_next(const arr *A, int32_t h) {
    int32_t t = h ^ 1, v = A->org[t];
    int32_t p = A->pos[t] - 1;
    if (p < A->vstart[v]) p = A->vstart[v + 1] - 1;
    return A->out[p];
}

double pslg_input_angles(const pslg *g, double bound_deg,
                         void (*fn)(void *ctx, int32_t v, int32_t s1, int32_t s2, double deg),
                         void *ctx) {
    geom_init();
    int32_t n = g->nverts, ns = g->nsegs;
    double best = 360;
    /* A vertex lying inside a segment s (a T-junction, decided exactly by pslg_segment_pieces)
     * is a corner too: there s leaves in both directions, so it gets two half-edges of s, each
     * paired with a slot for the far end of s (which does not list it: at s's endpoints the
     * segment is counted once). */
    pslg_pieces P;
    int have = ns > 0 && pslg_segment_pieces(g, &P) == 0;
    int32_t ne = ns;
    for (int32_t s = 0; have && s < ns; s++)
        if (P.start[s + 1] - P.start[s] > 2) ne += 2 * (P.start[s + 1] - P.start[s] - 2);
    arr A = {0};
    A.xy = g->xy;
    A.org = mesh_xmalloc((2 * (size_t)ne + 1) * sizeof(int32_t), 1);
    A.out = mesh_xmalloc((2 * (size_t)ne + 1) * sizeof(int32_t), 1);
    A.vstart = mesh_xcalloc((size_t)n + 2, sizeof(int32_t));
    int32_t *tmp = mesh_xmalloc((2 * (size_t)ne + 1) * sizeof(int32_t), 1);
    int32_t *sid = mesh_xmalloc(((size_t)ne + 1) * sizeof(int32_t), 1);
    uint8_t *listed = mesh_xmalloc(2 * (size_t)ne + 1, 1); /* h is in v's list */
    if (!A.org || !A.out || !A.vstart || !tmp || !sid || !listed) goto out;
    int32_t e = 0;
    for (int32_t s = 0; s < ns; s++, e++) {
        A.org[2 * e] = g->seg[2 * s];
        A.org[2 * e + 1] = g->seg[2 * s + 1];
        sid[e] = s;
        listed[2 * e] = listed[2 * e + 1] = 1;
    }
    for (int32_t s = 0; have && s < ns; s++)
        for (int32_t k = P.start[s] + 1; k + 1 < P.start[s + 1]; k++)
            for (int end = 0; end < 2; end++, e++) {
                A.org[2 * e] = P.vert[k];
                A.org[2 * e + 1] = g->seg[2 * s + end];
                sid[e] = s;
                listed[2 * e] = 1;
                listed[2 * e + 1] = 0;
            }
    for (int32_t h = 0; h < 2 * ne; h++)
        if (listed[h]) A.vstart[A.org[h] + 1]++;
    for (int32_t v = 0; v < n; v++)
        A.vstart[v + 1] += A.vstart[v];
    for (int32_t h = 0; h < 2 * ne; h++)
        if (listed[h]) A.out[A.vstart[A.org[h]]++] = h;
    for (int32_t v = n; v > 0; v--)
        A.vstart[v] = A.vstart[v - 1];
    A.vstart[0] = 0;
    for (int32_t v = 0; v < n; v++) {
        int32_t *o = A.out + A.vstart[v];
        int32_t d = A.vstart[v + 1] - A.vstart[v];
        if (d < 2) continue;
        msort(o, tmp, d, cmp_angle, &A);
        const double *c = g->xy + 2 * v;
        for (int32_t i = 0; i < d; i++) {
            int32_t h1 = o[i], h2 = o[(i + 1) % d];
            const double *p = g->xy + 2 * A.org[h1 ^ 1], *q = g->xy + 2 * A.org[h2 ^ 1];
            /* the counter-clockwise angle from p to q around c, in (0, 360]: the difference of
             * two atan2 values loses a sliver's angle entirely, so the size comes from
             * geom_angle_deg (exact cross product) and the side from orient2d */
            double deg = geom_angle_deg(p, c, q), side = geom_orient2d(c, p, q);
            if (side < 0) deg = 360 - deg;
            if (deg <= 0) deg += 360; /* coincident directions (overlapping segments) */
            if (deg < best) best = deg;
            if (deg < bound_deg && fn) fn(ctx, v, sid[h1 >> 1], sid[h2 >> 1], deg);
        }
    }
out:
    if (have) pslg_pieces_free(&P);
    free(A.org);
    free(A.out);
    free(A.vstart);
    free(tmp);
    free(sid);
    free(listed);
    return best;
}

/* 1 if p lies strictly inside the closed walk starting at half-edge h0 (crossing count with
 * exact side tests; edges walked in both directions cancel). */
static int in_cycle(const arr *A, int32_t h0, const double *p) {
    int in = 0;
    int32_t h = h0;
    do {
        const double *a = A->xy + 2 * A->org[h], *b = A->xy + 2 * A->org[h ^ 1];
        if ((a[1] <= p[1]) != (b[1] <= p[1])) {
            double o = geom_orient2d(a, b, p);
            if (b[1] > a[1] ? o > 0 : o < 0) in ^= 1;
        }
        h = arr_next(A, h);
    } while (h != h0);
    return in;
}

typedef struct cycle {
    int32_t h0, comp;
    int sign;          /* the exact sign of the walk's area (walk_sign): what topology uses */
    double area, face; /* signed area of the walk (rounded, its sign forced to `sign`); face
                          area (outer minus inner) */
    double x0, y0, x1, y1;
    int removed;
    int32_t encl; /* negative walks: the enclosing bounded face, or -1 */
} cycle;

static int32_t uf_find(int32_t *p, int32_t x) {
    while (p[x] != x) {
        p[x] = p[p[x]];
        x = p[x];
    }
    return x;
}

/* The exact sign of the area of closed walk number id starting at h0 (cid[] already holds id
 * on the whole walk).  Half-edges whose twin lies on the same walk (dangling segments, trees,
 * bridges to islands) add nothing to the area; if every half-edge is such, the area is exactly
 * 0.  The others bound the walk's region; at their lexicographically smallest vertex v every
 * one of them points into the half-plane right of v, and the most clockwise of them borders
 * the outside of the region: the face (left of each half-edge) lies inside iff that one leaves
 * v (a counter-clockwise outer boundary, positive) and outside iff it enters v (the clockwise
 * outer boundary of a component, negative).  Directions are compared by orient2d, exactly. */
static int lex_less(const double *p, const double *q) {
    return p[0] < q[0] || (p[0] == q[0] && p[1] < q[1]);
}

static int walk_sign(const arr *A, const int32_t *cid, int32_t h0, int32_t id) {
    int32_t h = h0, v = -1;
    do {
        if (cid[h ^ 1] != id)
            for (int k = 0; k < 2; k++) {
                int32_t x = A->org[h ^ k];
                if (v < 0 || lex_less(A->xy + 2 * x, A->xy + 2 * v)) v = x;
            }
        h = arr_next(A, h);
    } while (h != h0);
    if (v < 0) return 0;
    const double *pv = A->xy + 2 * v, *best = NULL;
    int out = 0;
    h = h0;
    do {
        if (cid[h ^ 1] != id && (A->org[h] == v || A->org[h ^ 1] == v)) {
            int leaves = A->org[h] == v;
            const double *q = A->xy + 2 * A->org[leaves ? h ^ 1 : h];
            if (!best || geom_orient2d(pv, q, best) > 0) { /* q clockwise of best */
                best = q;
                out = leaves;
            }
        }
        h = arr_next(A, h);
    } while (h != h0);
    return out ? 1 : -1;
}

/* The innermost positive cycle (other than component skip) strictly containing p, or -1; p
 * lies on no candidate (a hole point on no edge, or a vertex of another component).  Decided
 * exactly, without areas: a positive walk of one connected component winds once around its
 * face and the holes inside it and nowhere else, so two walks that both contain p belong to
 * different components, which share no point, and are nested; the inner one is the one whose
 * first vertex the other contains (in_cycle, orient2d). */
static int32_t enclosing(const arr *A, const cycle *cy, int32_t nc, const double *p, int32_t skip) {
    int32_t best = -1;
    for (int32_t i = 0; i < nc; i++) {
        const cycle *c = cy + i;
        if (c->sign <= 0 || c->comp == skip) continue;
        if (p[0] < c->x0 || p[0] > c->x1 || p[1] < c->y0 || p[1] > c->y1) continue;
        if (best >= 0) { /* c can only be inner if its box lies in best's */
            const cycle *b = cy + best;
            if (c->x0 < b->x0 || c->x1 > b->x1 || c->y0 < b->y0 || c->y1 > b->y1) continue;
        }
        if (!in_cycle(A, c->h0, p)) continue;
        if (best < 0 || in_cycle(A, cy[best].h0, A->xy + 2 * A->org[c->h0])) best = i;
    }
    return best;
}

/* The faces of the arrangement and which of them the domain keeps: cy[i] for each closed walk
 * (positive: a bounded face's outer boundary; negative or zero: the outer boundary of a
 * component, or a tree of dangling segments, whose face is cy[i].encl, -1 for the unbounded
 * face), cid[h] the walk of half-edge h (the
 * face to its left).  Hole points remove the face strictly containing them; one exactly on an
 * arrangement vertex or edge removes every face whose closure contains it (as the mesher's
 * carving does, cdt.c). */
typedef struct faces {
    arr A;
    cycle *cy;
    int32_t *cid, nc;
} faces;

static void faces_free(faces *F) {
    arr_free(&F->A);
    free(F->cy);
    free(F->cid);
}

/* The bounded face to the left of half-edge h, or -1 (unbounded). */
static int32_t face_left(const faces *F, int32_t h) {
    const cycle *c = F->cy + F->cid[h];
    return c->sign > 0 ? F->cid[h] : c->encl;
}

static void remove_face(faces *F, int32_t f) {
    if (f >= 0) F->cy[f].removed = 1;
}

/* Applies hole point p (see faces). */
static void faces_hole(faces *F, const pslg *g, const double *p) {
    const arr *A = &F->A;
    int on = 0;
    for (int32_t h = 0; h < 2 * A->ne; h += 2) {
        const double *a = g->xy + 2 * A->org[h], *b = g->xy + 2 * A->org[h + 1];
        int at_a = a[0] == p[0] && a[1] == p[1], at_b = b[0] == p[0] && b[1] == p[1];
        if (at_a || at_b || (geom_orient2d(a, b, p) == 0 && strictly_between(a, b, p))) {
            remove_face(F, face_left(F, h));
            remove_face(F, face_left(F, h + 1));
            on = 1;
        }
    }
    if (!on) remove_face(F, enclosing(A, F->cy, F->nc, p, -1));
}

static int faces_build(const pslg *g, faces *F) {
    memset(F, 0, sizeof *F);
    if (g->nsegs == 0 || arr_build(g, &F->A)) return -1;
    arr *A = &F->A;
    int32_t nh = 2 * A->ne, n = g->nverts;
    F->cid = mesh_xmalloc((size_t)nh * sizeof(int32_t) + 1, 1);
    int32_t *uf = mesh_xmalloc((size_t)(n ? n : 1) * sizeof(int32_t), 1);
    F->cy = mesh_xmalloc((size_t)nh * sizeof(cycle) + 1, 1);
    if (!F->cid || !uf || !F->cy) {
        free(uf);
        faces_free(F);
        return -1;
    }
    int32_t *cid = F->cid;
    cycle *cy = F->cy;
    for (int32_t v = 0; v < n; v++)
        uf[v] = v;
    for (int32_t e = 0; e < A->ne; e++) {
        int32_t a = uf_find(uf, A->org[2 * e]), b = uf_find(uf, A->org[2 * e + 1]);
        if (a != b) uf[a] = b;
    }
    for (int32_t h = 0; h < nh; h++)
        cid[h] = -1;
    int32_t nc = 0;
    for (int32_t h0 = 0; h0 < nh; h0++) {
        if (cid[h0] >= 0) continue;
        cycle *c = cy + nc;
        const double *o = g->xy + 2 * A->org[h0];
        double sum = 0, comp = 0; /* Neumaier summation of the shoelace terms */
        c->x0 = c->x1 = o[0];
        c->y0 = c->y1 = o[1];
        int32_t h = h0;
        do {
            cid[h] = nc;
            const double *a = g->xy + 2 * A->org[h], *b = g->xy + 2 * A->org[h ^ 1];
            double t = geom_area2_accurate(o, a, b);
            double s = sum + t;
            comp += fabs(sum) >= fabs(t) ? (sum - s) + t : (t - s) + sum;
            sum = s;
            c->x0 = fmin(c->x0, a[0]);
            c->x1 = fmax(c->x1, a[0]);
            c->y0 = fmin(c->y0, a[1]);
            c->y1 = fmax(c->y1, a[1]);
            h = arr_next(A, h);
        } while (h != h0);
        c->h0 = h0;
        c->sign = walk_sign(A, cid, h0, nc);
        c->area = 0.5 * (sum + comp);
        if (c->sign == 0 || (c->sign > 0) != (c->area > 0)) /* rounding: the sign is exact */
            c->area = c->sign * DBL_MIN;
        c->face = c->area;
        c->comp = uf_find(uf, A->org[h0]);
        c->removed = 0;
        c->encl = -1;
        nc++;
    }
    free(uf);
    F->nc = nc;
    /* outer boundaries of components (negative walks) go to their enclosing face */
    for (int32_t i = 0; i < nc; i++) {
        if (cy[i].sign > 0) continue; /* zero: a tree of dangling segments */
        int32_t f = enclosing(A, cy, nc, g->xy + 2 * A->org[cy[i].h0], cy[i].comp);
        cy[i].encl = f;
        if (f >= 0) cy[f].face += cy[i].area;
    }
    for (int32_t k = 0; k < g->nholes; k++)
        faces_hole(F, g, g->holes + 2 * k);
    return 0;
}

double pslg_domain_area(const pslg *g) {
    geom_init();
    faces F;
    if (faces_build(g, &F)) return 0;
    double total = 0, comp = 0;
    for (int32_t i = 0; i < F.nc; i++)
        if (F.cy[i].sign > 0 && !F.cy[i].removed) {
            double t = F.cy[i].face, s = total + t;
            comp += fabs(total) >= fabs(t) ? (total - s) + t : (t - s) + total;
            total = s;
        }
    total += comp;
    faces_free(&F);
    return total;
}

struct pslg_regions {
    faces F;
    int32_t *freg; /* per walk: the region of its face (positive walks), or -1 */
};

/* 1 iff p lies on a segment of the arrangement (endpoints included). */
static int on_arrangement(const faces *F, const pslg *g, const double *p) {
    const arr *A = &F->A;
    for (int32_t h = 0; h < 2 * A->ne; h += 2) {
        const double *a = g->xy + 2 * A->org[h], *b = g->xy + 2 * A->org[h + 1];
        if ((a[0] == p[0] && a[1] == p[1]) || (b[0] == p[0] && b[1] == p[1]) ||
            (geom_orient2d(a, b, p) == 0 && strictly_between(a, b, p)))
            return 1;
    }
    return 0;
}

pslg_regions *pslg_regions_build(const pslg *g) {
    geom_init();
    pslg_regions *R = mesh_xcalloc(1, sizeof *R);
    if (!R) return NULL;
    if (g->nsegs == 0 || faces_build(g, &R->F)) {
        free(R);
        return NULL;
    }
    R->freg = mesh_xmalloc((size_t)R->F.nc * sizeof(int32_t) + 1, 1);
    if (!R->freg) {
        faces_free(&R->F);
        free(R);
        return NULL;
    }
    for (int32_t i = 0; i < R->F.nc; i++)
        R->freg[i] = -1;
    for (int32_t i = 0; i < g->nregions; i++) { /* in file order: the later one wins */
        const double *p = g->regions + 4 * i;
        if (on_arrangement(&R->F, g, p)) continue;
        int32_t f = enclosing(&R->F.A, R->F.cy, R->F.nc, p, -1);
        if (f >= 0 && !R->F.cy[f].removed) R->freg[f] = i;
    }
    return R;
}

int32_t pslg_region_at(const pslg_regions *R, const double p[2]) {
    if (!R) return -1;
    int32_t f = enclosing(&R->F.A, R->F.cy, R->F.nc, p, -1);
    return f >= 0 ? R->freg[f] : -1;
}

void pslg_regions_free(pslg_regions *R) {
    if (!R) return;
    faces_free(&R->F);
    free(R->freg);
    free(R);
}

/* 1 iff the half-edge h borders a kept face on one side or the other. */
static int borders_domain(const faces *F, int32_t h) {
    int32_t f1 = face_left(F, h), f2 = face_left(F, h ^ 1);
    return (f1 >= 0 && !F->cy[f1].removed) || (f2 >= 0 && !F->cy[f2].removed);
}

void pslg_pieces_free(pslg_pieces *P) {
    free(P->start);
    free(P->vert);
    free(P->border);
    memset(P, 0, sizeof *P);
}

/* Appends vertex v (and, after the first, the border flag of the piece ending there). */
static int piece_push(pslg_pieces *P, int32_t *cap, int32_t v, uint8_t border, int first) {
    if (P->nvert == *cap) {
        int32_t nc = *cap ? 2 * *cap : 64;
        int32_t *nv = mesh_xrealloc(P->vert, (size_t)nc * sizeof *nv, 1);
        if (!nv) return -1;
        P->vert = nv;
        uint8_t *nb = mesh_xrealloc(P->border, (size_t)nc, 1);
        if (!nb) return -1;
        P->border = nb;
        *cap = nc;
    }
    if (!first) P->border[P->nvert - 1] = border;
    P->border[P->nvert] = 0;
    P->vert[P->nvert++] = v;
    return 0;
}

int pslg_segment_pieces(const pslg *g, pslg_pieces *P) {
    geom_init();
    memset(P, 0, sizeof *P);
    int32_t cap = 0;
    P->start = mesh_xmalloc(((size_t)g->nsegs + 1) * sizeof *P->start, 1);
    if (!P->start) return -1;
    P->start[0] = 0;
    faces F;
    int have = g->nsegs > 0 && faces_build(g, &F) == 0;
    for (int32_t s = 0; s < g->nsegs; s++) {
        int32_t a = g->seg[2 * s], b = g->seg[2 * s + 1], cur = a;
        const double *pb = g->xy + 2 * b;
        int32_t first = P->nvert;
        if (piece_push(P, &cap, a, 0, 1)) goto oom;
        /* walk the pieces of s from a to b: at each vertex the outgoing half-edge pointing at
         * b (collinear, same direction) */
        for (int32_t steps = 0; have && cur != b && steps <= F.A.ne; steps++) {
            int32_t next = -1;
            for (int32_t i = F.A.vstart[cur]; i < F.A.vstart[cur + 1]; i++) {
                int32_t h = F.A.out[i], w = F.A.org[h ^ 1];
                const double *pc = g->xy + 2 * cur, *pw = g->xy + 2 * w;
                if (w != b && !(geom_orient2d(pc, pb, pw) == 0 && strictly_between(pc, pb, pw)))
                    continue;
                if (piece_push(P, &cap, w, (uint8_t)borders_domain(&F, h), 0)) goto oom;
                next = w;
                break;
            }
            if (next < 0) break;
            cur = next;
        }
        if (cur != b) { /* no arrangement (should not happen): the whole segment, required */
            P->nvert = first;
            if (piece_push(P, &cap, a, 0, 1) || piece_push(P, &cap, b, 1, 0)) goto oom;
        }
        P->start[s + 1] = P->nvert;
    }
    if (have) faces_free(&F);
    return 0;
oom:
    if (have) faces_free(&F);
    pslg_pieces_free(P);
    return -1;
}

/* ---------------------------------------------------------------- markers --------------- */

/* 1 iff exactly one side of half-edge h is a kept face: the piece is on the domain's boundary. */
static int on_boundary(const faces *F, int32_t h) {
    int32_t f1 = face_left(F, h), f2 = face_left(F, h ^ 1);
    return ((f1 >= 0 && !F->cy[f1].removed) != 0) + ((f2 >= 0 && !F->cy[f2].removed) != 0) == 1;
}

int pslg_boundary_markers(pslg *g) {
    geom_init();
    if (g->nsegs == 0 && g->vmarker && g->nverts >= 3) { /* a point set: its hull's vertices */
        int32_t *cyc = mesh_xmalloc(2 * (size_t)g->nverts + 2, sizeof *cyc);
        int32_t h = pslg_hull(g, cyc);
        for (int32_t i = 0; i < h; i++)
            if (g->vmarker[cyc[i]] == 0) g->vmarker[cyc[i]] = 1;
        free(cyc);
    }
    if (g->nsegs == 0 || !g->smarker) return 0;
    faces F;
    if (faces_build(g, &F)) return -1;
    uint8_t *onb = mesh_xcalloc((size_t)g->nsegs + 1, 1);
    /* the vertices along each segment, in order (as pslg_segment_pieces walks them) */
    int32_t *start = mesh_xmalloc((size_t)g->nsegs + 1, sizeof(int32_t)), nv = 0, cap = 64;
    int32_t *vert = mesh_xmalloc((size_t)cap, sizeof(int32_t));
    for (int32_t s = 0; s < g->nsegs; s++) {
        int32_t a = g->seg[2 * s], b = g->seg[2 * s + 1], cur = a;
        const double *pb = g->xy + 2 * b;
        start[s] = nv;
        for (int32_t steps = 0; cur != b && steps <= F.A.ne; steps++) {
            int32_t next = -1;
            for (int32_t i = F.A.vstart[cur]; i < F.A.vstart[cur + 1]; i++) {
                int32_t h = F.A.out[i], w = F.A.org[h ^ 1];
                const double *pc = g->xy + 2 * cur, *pw = g->xy + 2 * w;
                if (w != b && !(geom_orient2d(pc, pb, pw) == 0 && strictly_between(pc, pb, pw)))
                    continue;
                if (on_boundary(&F, h)) onb[s] = 1;
                if (w != b) {
                    if (nv == cap) vert = mesh_xrealloc(vert, (size_t)(cap *= 2), sizeof(int32_t));
                    vert[nv++] = w;
                }
                next = w;
                break;
            }
            if (next < 0) break;
            cur = next;
        }
    }
    faces_free(&F);
    if (g->vmarker) /* pass 1: the input's nonzero segment markers; pass 2: boundary ones */
        for (int pass = 0; pass < 2; pass++) {
            for (int32_t s = 0; s < g->nsegs; s++) {
                int32_t mk = g->smarker[s] ? g->smarker[s] : pass && onb[s] ? 1 : 0;
                if (!mk) continue;
                int32_t end = s + 1 < g->nsegs ? start[s + 1] : nv;
                for (int32_t i = start[s] - 2; i < end; i++) {
                    int32_t v = i < start[s] ? g->seg[2 * s + (i - start[s] + 2)] : vert[i];
                    if (g->vmarker[v] == 0) g->vmarker[v] = mk;
                }
            }
        }
    for (int32_t s = 0; s < g->nsegs; s++)
        if (g->smarker[s] == 0 && onb[s]) g->smarker[s] = 1;
    free(onb);
    free(start);
    free(vert);
    return 0;
}
