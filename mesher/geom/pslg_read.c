/* pslg_read: Triangle's .poly and .node files read into a pslg.
 *
 * The file is loaded and walked line by line by base/textin.h (comments after '#' and blank
 * lines skipped; a UTF-8 byte-order mark, CRLF and CR-only line ends taken; NUL bytes refused,
 * so binary input stops at its first chunk), and every token is parsed in full (strtol/strtod
 * must consume the token); a count is checked against the bytes left before anything is
 * allocated for it.  Every section Triangle's reader needs must be there: a .poly's vertices
 * (or a count of 0 and NAME.node beside it), its segments and its hole count, each with all its
 * records; only the regional attributes may be left out, as in Triangle's format (a file cut
 * after its segments is refused, not read as a domain without holes).  Any problem becomes one
 * "FILE:LINE: problem" message and every allocation is released, so a failed read leaves
 * nothing behind.  The reader decides nothing about geometry: duplicate vertices, crossing and
 * zero-length segments are pslg_check's (pslg_check.c).  Invariant on a successful return:
 * counts as declared, every number finite or reported, every segment endpoint an index into
 * the vertices read, ids 0-based (first_index records the file's base), and each vertex and
 * segment remembers its line for later messages.
 */
#include "geom/pslg.h"

#include "base/base.h"
#include "base/textin.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------- line reader ---------- */

typedef struct reader {
    const char *path;
    mesh_textin in; /* the file, tokenised in place */
    char *cur;      /* cursor in the current line */
    long line;      /* number of the current line (1-based) */
    char *err;
    size_t errlen;
} reader;

/* "PATH:LINE: problem" at r's current line (0, before the first: 1) */
#define rfail(r, ...)                                                                              \
    mesh_fail_at((r)->err, (r)->errlen, (r)->path, (r)->line > 0 ? (r)->line : 1, __VA_ARGS__)

/* Loads path into r.  Returns 0, or -1 with textin's message (cannot open, not a text file). */
static int reader_open(reader *r, const char *path, char *err, size_t errlen) {
    memset(r, 0, sizeof *r);
    r->path = path;
    r->err = err;
    r->errlen = errlen;
    return mesh_textin_load(&r->in, path, err, errlen);
}

static void reader_close(reader *r) {
    mesh_textin_free(&r->in);
}

/* Advances to the next line holding data (comments and blank lines skipped).  Returns 1, or 0
 * at the end of the file (r->line is then the last line of the file). */
static int next_line(reader *r) {
    r->cur = mesh_textin_line(&r->in);
    r->line = r->in.line;
    return r->cur != NULL;
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
    return mesh_textin_left(&r->in);
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
static int read_poly(const char *path, pslg *g, int skip_node, int32_t nv, int first,
                     void (*on_vertices)(void *, const pslg *), void *ctx, char *err,
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
        if (on_vertices && !skip_node) on_vertices(ctx, g);
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
    /* holes: the count must be there (a file cut after its segments is not a domain without
     * holes), as in Triangle */
    if (!next_line(&r)) {
        rfail(&r, "the file ends before the hole count (a .poly lists its holes after its "
                  "segments; write 0 for none)");
        goto out;
    }
    long nh;
    if (parse_long(&r, "hole count", NULL, 0, &nh) || line_end(&r) ||
        check_count(&r, "hole", nh, 5))
        goto out;
    g->nholes = (int32_t)nh;
    g->holes = mesh_xcalloc((size_t)nh * 2, sizeof(double));
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
    return pslg_read_ex(path, out, NULL, NULL, err, errlen);
}

int pslg_read_ex(const char *path, pslg *out, void (*on_vertices)(void *ctx, const pslg *g),
                 void *ctx, char *err, size_t errlen) {
    memset(out, 0, sizeof *out);
    if (errlen) err[0] = '\0';
    int rc;
    if (ends_with(path, ".node")) {
        rc = read_node_file(path, out, err, errlen);
        snprintf(out->segpath, sizeof out->segpath, "%s", path);
        if (rc == 0 && on_vertices) on_vertices(ctx, out);
    } else {
        rc = read_poly(path, out, 0, 0, 0, on_vertices, ctx, err, errlen);
    }
    if (rc) pslg_free(out);
    return rc;
}

int pslg_read_segments(const char *path, int32_t nverts, int first_index, pslg *out, char *err,
                       size_t errlen) {
    memset(out, 0, sizeof *out);
    if (errlen) err[0] = '\0';
    int rc = read_poly(path, out, 1, nverts, first_index, NULL, NULL, err, errlen);
    if (rc) pslg_free(out);
    return rc;
}
