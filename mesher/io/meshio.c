/* meshio: writers (Triangle .node/.ele/.poly, legacy VTK, SVG) and the Triangle-format reader
 * for mesh_flat.
 *
 * Every writer opens "PATH.tmpXXXXXX" (mkstemp) in the destination directory, writes through a
 * 1 MiB stdio buffer, checks every error (including fclose) and only then renames the file
 * over PATH; on any failure the temporary file is removed, so a reader never sees half a
 * file.  Coordinates are printed with "%.17g" so that a written mesh reads back bit for bit;
 * integers are formatted by hand because the big meshes have tens of millions of them.  The
 * SVG groups triangles by owning rank (one fill per <g>, no per-element style) so a picture of
 * a million triangles stays a few tens of megabytes.  The .poly lists the input's segments (not
 * interface ones) and ends with the input's holes and regions (meshio_fmt_domain, which the
 * parallel writer shares), so it meshes the same domain again.  The reader takes .node (and .poly
 * segments) through pslg_read.c and parses .ele itself with the same full-token checks, the file
 * loaded and walked by base/textin.h as pslg_read's are (the same encodings taken, binary input
 * refused); a .ele must hold every triangle its count declares.
 */
#define _GNU_SOURCE /* sync_file_range, fopencookie */
#include "io/meshio.h"

#include "base/base.h"
#include "base/textin.h"

#include "geom/pslg.h"
#include "io/fmt.h"
#include "io/oset.h"
#include "io/wfile.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---------------------------------------------------------------- atomic output --------- */

int meshio_mktemp(const char *path, char *tmp, size_t tmplen, char *err, size_t errlen) {
    if (strlen(path) + 12 > tmplen) return mesh_fail(err, errlen, "%s: path too long", path);
    snprintf(tmp, tmplen, "%s.tmpXXXXXX", path);
    int fd = mkstemp(tmp);
    if (fd < 0)
        return mesh_fail(err, errlen, "%s: cannot create temporary file: %s", path,
                         strerror(errno));
    mode_t um = umask(0);
    umask(um);
    (void)fchmod(fd, 0666 & ~um); /* mkstemp makes 0600; the usual permissions, not fatal */
    return fd;
}

void meshio_writeback(int fd, long long off, long long n) {
#ifdef SYNC_FILE_RANGE_WRITE
    if (fd >= 0 && off >= 0 && n > 0) (void)sync_file_range(fd, off, n, SYNC_FILE_RANGE_WRITE);
#else
    (void)fd, (void)off, (void)n;
#endif
}

int meshio_writeback_open(const char *path) {
#ifdef SYNC_FILE_RANGE_WRITE
    return open(path, O_WRONLY | O_CLOEXEC);
#else
    (void)path;
    return -1;
#endif
}

#ifdef __GLIBC__
#define WB_STEP ((long long)8 << 20) /* bytes between two writeback hints */

/* The stream's write: all of n bytes to the descriptor (a short write is continued), then a
 * writeback hint every WB_STEP bytes.  Returns the bytes written, 0 on an error (errno set, as
 * the stream's caller then reads it). */
static ssize_t wf_write(void *cookie, const char *b, size_t n) {
    wfile *w = cookie;
    size_t done = 0;
    while (done < n) {
        ssize_t k = write(w->fd, b + done, n - done);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) {
            if (k == 0) errno = EIO;
            break;
        }
        done += (size_t)k;
    }
    w->at += (long long)done;
    if (w->at - w->hinted >= WB_STEP) {
        meshio_writeback(w->fd, w->hinted, w->at - w->hinted);
        w->hinted = w->at;
    }
    return (ssize_t)done;
}

static int wf_close(void *cookie) {
    return close(((wfile *)cookie)->fd);
}
#endif

int meshio_wopen(wfile *w, meshio_set *set, const char *path, char *err, size_t errlen) {
    memset(w, 0, sizeof *w);
    w->path = path;
    w->set = set;
    w->err = err;
    w->errlen = errlen;
    if (errlen) err[0] = '\0';
    int fd = meshio_mktemp(path, w->tmp, sizeof w->tmp, err, errlen);
    if (fd < 0) return -1;
    if (meshio_set_add(set, w->tmp, path, err, errlen) != 0) {
        close(fd);
        unlink(w->tmp);
        return -1;
    }
    w->fd = fd;
#ifdef __GLIBC__ /* a stream that hints the writeback as it goes */
    w->f = fopencookie(w, "w", (cookie_io_functions_t){NULL, wf_write, NULL, wf_close});
#else
    w->f = fdopen(fd, "w");
#endif
    if (!w->f) {
        int e = errno;
        close(fd);
        unlink(w->tmp);
        meshio_set_drop(set, w->tmp);
        return mesh_fail(err, errlen, "%s: cannot open temporary file: %s", path, strerror(e));
    }
    w->vbuf = mesh_xmalloc(1 << 20, 1);
    if (w->vbuf) setvbuf(w->f, w->vbuf, _IOFBF, 1 << 20);
    return 0;
}

int meshio_wclose(wfile *w, int failed) {
    int bad = failed, e = 0;
    /* the cause: a write that failed earlier fails again when the buffer is flushed, and errno
     * then names it (ENOSPC, EFBIG, EIO, ...) */
    if (!bad && (fflush(w->f) != 0 || ferror(w->f))) {
        bad = 1;
        e = errno;
    }
    if (!bad && fsync(w->fd) != 0 && errno != EINVAL && errno != EROFS) {
        bad = 1;
        e = errno;
    }
    if (fclose(w->f) != 0 && !bad) {
        bad = 1;
        e = errno;
    }
    free(w->vbuf);
    if (!bad && !w->set && rename(w->tmp, w->path) != 0) {
        bad = 1;
        e = errno;
    }
    if (bad) {
        unlink(w->tmp);
        meshio_set_drop(w->set, w->tmp);
        if (!failed || !w->err[0])
            mesh_fail(w->err, w->errlen, "%s: write failed: %s", w->path,
                      e ? strerror(e) : "an error of the C library's stream");
        return -1;
    }
    meshio_set_done(w->set, w->tmp);
    return 0;
}

/* ---------------------------------------------------------------- fast formatting ------- */

/* SVG coordinates: two decimals, by integer arithmetic (snprintf dominates otherwise). */
static char *put_fix(char *p, double v) {
    if (!(fabs(v) < 1e15)) return p + snprintf(p, 32, "%.2f", v);
    long long q = llround(v * 100);
    if (q < 0) {
        *p++ = '-';
        q = -q;
    }
    p = fmt_int(p, q / 100);
    int f = (int)(q % 100);
    if (f) {
        *p++ = '.';
        *p++ = (char)('0' + f / 10);
        if (f % 10) *p++ = (char)('0' + f % 10);
    }
    return p;
}

/* ---------------------------------------------------------------- Triangle files -------- */

static int write_node(const mesh_flat *m, meshio_set *set, const char *path, char *err,
                      size_t errlen) {
    wfile w;
    if (meshio_wopen(&w, set, path, err, errlen)) return -1;
    int nattr = m->vattr ? m->nattr : 0;
    fprintf(w.f, "%d 2 %d 1\n", (int)m->nverts, nattr);
    char *line = mesh_xmalloc(64 + 32 * (size_t)nattr, 1);
    for (int32_t i = 0; i < m->nverts; i++) {
        char *p = fmt_int(line, (long long)i + 1);
        *p++ = ' ';
        p = fmt_dbl(p, ldexp(m->xy[2 * i], -m->scale_exp));
        *p++ = ' ';
        p = fmt_dbl(p, ldexp(m->xy[2 * i + 1], -m->scale_exp));
        for (int k = 0; k < nattr; k++) {
            *p++ = ' ';
            p = fmt_dbl(p, m->vattr[(size_t)i * nattr + k]);
        }
        *p++ = ' ';
        p = fmt_int(p, m->vmarker ? m->vmarker[i] : 0);
        *p++ = '\n';
        fwrite(line, 1, (size_t)(p - line), w.f);
    }
    free(line);
    fprintf(w.f, "# written by pcdm\n");
    return meshio_wclose(&w, 0);
}

static int write_ele(const mesh_flat *m, meshio_set *set, const char *path, char *err,
                     size_t errlen) {
    wfile w;
    if (meshio_wopen(&w, set, path, err, errlen)) return -1;
    fprintf(w.f, "%d 3 %d\n", (int)m->ntris, m->tattr || m->trank ? 1 : 0);
    char line[128];
    for (int32_t t = 0; t < m->ntris; t++) {
        char *p = fmt_int(line, (long long)t + 1);
        for (int k = 0; k < 3; k++) {
            *p++ = ' ';
            p = fmt_int(p, (long long)m->tri[3 * t + k] + 1);
        }
        if (m->tattr) { /* Triangle's -A: the regional attribute */
            *p++ = ' ';
            p = fmt_dbl(p, m->tattr[t]);
        } else if (m->trank) {
            *p++ = ' ';
            p = fmt_int(p, m->trank[t]);
        }
        *p++ = '\n';
        fwrite(line, 1, (size_t)(p - line), w.f);
    }
    fprintf(w.f, "# written by pcdm%s\n",
            m->tattr   ? " (attribute: regional attribute)"
            : m->trank ? " (attribute: owning rank)"
                       : "");
    return meshio_wclose(&w, 0);
}

static int write_poly(const mesh_flat *m, meshio_set *set, const char *path, char *err,
                      size_t errlen) {
    wfile w;
    if (meshio_wopen(&w, set, path, err, errlen)) return -1;
    int32_t ns = 0;
    for (int32_t s = 0; s < m->nsegs; s++)
        ns += !(m->sinterface && m->sinterface[s]);
    fprintf(w.f, "0 2 0 1\n%d 1\n", (int)ns);
    char line[128];
    for (int32_t s = 0, id = 0; s < m->nsegs; s++) {
        if (m->sinterface && m->sinterface[s]) continue; /* artificial: not the input's */
        char *p = fmt_int(line, (long long)++id);
        for (int k = 0; k < 2; k++) {
            *p++ = ' ';
            p = fmt_int(p, (long long)m->seg[2 * s + k] + 1);
        }
        *p++ = ' ';
        p = fmt_int(p, m->smarker ? m->smarker[s] : 0);
        *p++ = '\n';
        fwrite(line, 1, (size_t)(p - line), w.f);
    }
    char *dom = mesh_xmalloc(meshio_domain_maxlen(m->nholes, m->nregions), 1);
    char *q = meshio_fmt_domain(dom, m->nholes, m->holes, m->nregions, m->regions, m->scale_exp);
    fwrite(dom, 1, (size_t)(q - dom), w.f);
    free(dom);
    return meshio_wclose(&w, 0);
}

size_t meshio_domain_maxlen(int32_t nholes, int32_t nregions) {
    return 64 + 96 * (size_t)nholes + 160 * (size_t)nregions; /* 25 bytes per number at most */
}

char *meshio_fmt_domain(char *q, int32_t nholes, const double *holes, int32_t nregions,
                        const double *regions, int e) {
    q += sprintf(q, "%d\n", (int)nholes);
    for (int32_t i = 0; i < nholes; i++)
        q += sprintf(q, "%d %.17g %.17g\n", (int)i + 1, ldexp(holes[2 * i], -e),
                     ldexp(holes[2 * i + 1], -e));
    if (nregions) q += sprintf(q, "%d\n", (int)nregions);
    for (int32_t i = 0; i < nregions; i++) {
        const double *r = regions + 4 * i;
        q += sprintf(q, "%d %.17g %.17g %.17g %.17g\n", (int)i + 1, ldexp(r[0], -e),
                     ldexp(r[1], -e), r[2], r[3] > 0 ? ldexp(r[3], -2 * e) : r[3]);
    }
    return q;
}

int meshio_flat_domain(mesh_flat *m, const struct pslg *g) {
    m->holes = mesh_xmalloc(2 * (size_t)g->nholes, sizeof(double));
    m->regions = mesh_xmalloc(4 * (size_t)g->nregions, sizeof(double));
    m->nholes = g->nholes;
    m->nregions = g->nregions;
    if (g->nholes) memcpy(m->holes, g->holes, 2 * (size_t)g->nholes * sizeof(double));
    if (g->nregions) memcpy(m->regions, g->regions, 4 * (size_t)g->nregions * sizeof(double));
    return 0;
}

int meshio_write_triangle(const mesh_flat *m, const char *prefix, char *err, size_t errlen) {
    return meshio_write_triangle_some(m, NULL, prefix, 0, err, errlen);
}

int meshio_write_triangle_some(const mesh_flat *m, meshio_set *set, const char *prefix,
                               unsigned skip, char *err, size_t errlen) {
    char path[1024];
    if (strlen(prefix) + 6 > sizeof path)
        return mesh_fail(err, errlen, "%s: path too long", prefix);
    snprintf(path, sizeof path, "%s.node", prefix);
    if (!(skip & MESHIO_SKIP_NODE) && write_node(m, set, path, err, errlen)) return -1;
    snprintf(path, sizeof path, "%s.ele", prefix);
    if (!(skip & MESHIO_SKIP_ELE) && write_ele(m, set, path, err, errlen)) return -1;
    snprintf(path, sizeof path, "%s.poly", prefix);
    return skip & MESHIO_SKIP_POLY ? 0 : write_poly(m, set, path, err, errlen);
}

/* ---------------------------------------------------------------- reading back ---------- */

/* "PATH:LINE: problem" (line 0, before the first: 1) */
#define lfail(err, errlen, path, line, ...)                                                        \
    mesh_fail_at(err, errlen, path, (line) > 0 ? (line) : 1, __VA_ARGS__)

/* Parses one decimal integer token at *s (advancing *s); 0, or -1 if missing or malformed. */
static int ele_int(char **s, long *v, int *missing) {
    char *t = *s + strspn(*s, " \t\r\v\f"), *p = t;
    *missing = *t == '\0';
    if (*missing) return -1;
    int neg = 0;
    if (*p == '+' || *p == '-') neg = *p++ == '-';
    char *d = p;
    long x = 0;
    while (*p >= '0' && *p <= '9' && x <= INT32_MAX)
        x = x * 10 + (*p++ - '0');
    if (p == d || x > INT32_MAX || (*p && !strchr(" \t\r\v\f", *p))) return -1;
    *v = neg ? -x : x;
    *s = p;
    return 0;
}

static int ele_dbl(char **s, double *v, int *missing) {
    char *t = *s + strspn(*s, " \t\r\v\f");
    *missing = *t == '\0';
    if (*missing) return -1;
    char *end;
    *v = strtod(t, &end);
    if (end == t || (*end && !strchr(" \t\r\v\f", *end)) || !isfinite(*v)) return -1;
    *s = end;
    return 0;
}

static int read_ele(const char *path, mesh_flat *m, int first, char *err, size_t errlen) {
    mesh_textin in;
    if (mesh_textin_load(&in, path, err, errlen)) return -1;
    char *s;
    long nt, npt = 3, nattr = 0, v;
    int miss, rc = -1;
    if (!(s = mesh_textin_line(&in))) {
        lfail(err, errlen, path, in.line, "empty file: expected a triangle count");
        goto out;
    }
    if (ele_int(&s, &nt, &miss) || nt < 0) {
        lfail(err, errlen, path, in.line, "malformed triangle count");
        goto out;
    }
    if (ele_int(&s, &npt, &miss) && !miss) {
        lfail(err, errlen, path, in.line, "malformed nodes-per-triangle count");
        goto out;
    }
    if (ele_int(&s, &nattr, &miss) && !miss) {
        lfail(err, errlen, path, in.line, "malformed attribute count");
        goto out;
    }
    if ((npt != 3 && npt != 6) || nattr < 0 || nattr > 1000) {
        lfail(err, errlen, path, in.line,
              "expected 3 nodes per triangle (6: second order, -o2) and 0..1000 attributes");
        goto out;
    }
    if ((size_t)nt > mesh_textin_left(&in) / 7 + 1) {
        lfail(err, errlen, path, in.line, "triangle count %ld is more than the file can hold", nt);
        goto out;
    }
    m->ntris = (int32_t)nt;
    m->tri = mesh_xmalloc((size_t)nt * 3 + 1, sizeof(int32_t));
    m->trank = nattr ? mesh_xmalloc((size_t)nt + 1, sizeof(int32_t)) : NULL;
    m->tattr = nattr ? mesh_xmalloc((size_t)nt + 1, sizeof(double)) : NULL;
    int rank_ok = nattr > 0;
    for (long t = 0; t < nt; t++) {
        if (!(s = mesh_textin_line(&in))) {
            lfail(err, errlen, path, in.line,
                  "unexpected end of file: expected %ld triangles, found %ld", nt, t);
            goto out;
        }
        if (ele_int(&s, &v, &miss)) {
            lfail(err, errlen, path, in.line, "malformed triangle number");
            goto out;
        }
        for (int k = 0; k < npt; k++) { /* three corners, then -o2's midside nodes */
            const char *what = k < 3 ? "vertex" : "node";
            if (ele_int(&s, &v, &miss)) {
                lfail(err, errlen, path, in.line, "%s %s %d of triangle %ld",
                      miss ? "missing" : "malformed", what, k + 1, t + first);
                goto out;
            }
            if (v < first || v >= (long)first + m->nverts) {
                lfail(err, errlen, path, in.line, "triangle %ld: %s %ld out of range [%d, %ld]",
                      t + first, what, v, first, (long)first + m->nverts - 1);
                goto out;
            }
            if (k < 3) {
                m->tri[3 * t + k] = (int32_t)(v - first);
                continue;
            }
            /* a midside node must be the midpoint of the edge opposite corner k - 3, (a + b) / 2
             * as the writer computes it (exact under its power-of-two scaling); checked, not
             * kept */
            const double *a = m->xy + 2 * (size_t)m->tri[3 * t + (k - 2) % 3],
                         *b = m->xy + 2 * (size_t)m->tri[3 * t + (k - 1) % 3],
                         *c = m->xy + 2 * (size_t)(v - first);
            if (c[0] != (a[0] + b[0]) / 2 || c[1] != (a[1] + b[1]) / 2) {
                lfail(err, errlen, path, in.line,
                      "triangle %ld: node %ld is not the midpoint of the edge opposite corner %d",
                      t + first, v, k - 2);
                goto out;
            }
        }
        for (long k = 0; k < nattr; k++) {
            double a;
            if (ele_dbl(&s, &a, &miss)) {
                lfail(err, errlen, path, in.line, "%s attribute %ld of triangle %ld",
                      miss ? "missing" : "malformed", k + 1, t + first);
                goto out;
            }
            if (k == 0) {
                m->tattr[t] = a;
                if (a >= 0 && a <= INT32_MAX && a == floor(a))
                    m->trank[t] = (int32_t)a;
                else
                    rank_ok = 0;
            }
        }
        s += strspn(s, " \t\r\v\f");
        if (*s) {
            int n = (int)strcspn(s, " \t\r\v\f"); /* the token, not a CRLF file's CR */
            lfail(err, errlen, path, in.line, "unexpected text '%.*s' at the end of the line",
                  n < 40 ? n : 40, s);
            goto out;
        }
    }
    if (!rank_ok) { /* attributes that are not ranks (e.g. Triangle's regional attributes) */
        free(m->trank);
        m->trank = NULL;
    }
    rc = 0;
out:
    mesh_textin_free(&in);
    return rc;
}

void mesh_flat_free(mesh_flat *m) {
    if (!m) return;
    free(m->xy);
    free(m->vin);
    free(m->vmarker);
    free(m->vattr);
    free(m->tri);
    free(m->trank);
    free(m->tattr);
    free(m->seg);
    free(m->smarker);
    free(m->sinterface);
    free(m->holes);
    free(m->regions);
    memset(m, 0, sizeof *m);
}

int meshio_read_triangle(const char *prefix, mesh_flat *m, char *err, size_t errlen) {
    memset(m, 0, sizeof *m);
    if (errlen) err[0] = '\0';
    char path[1024];
    if (strlen(prefix) + 6 > sizeof path)
        return mesh_fail(err, errlen, "%s: path too long", prefix);
    pslg g;
    snprintf(path, sizeof path, "%s.node", prefix);
    if (pslg_read(path, &g, err, errlen)) return -1;
    m->nverts = g.nverts;
    m->xy = g.xy;
    m->vmarker = g.vmarker;
    m->nattr = g.nattr;
    m->vattr = g.vattr;
    g.xy = g.vattr = NULL;
    g.vmarker = NULL;
    int first = g.first_index;
    pslg_free(&g);
    snprintf(path, sizeof path, "%s.ele", prefix);
    if (read_ele(path, m, first, err, errlen)) goto fail;
    snprintf(path, sizeof path, "%s.poly", prefix);
    if (access(path, F_OK) == 0) {
        if (pslg_read_segments(path, m->nverts, first, &g, err, errlen)) goto fail;
        if (g.nverts != 0) {
            pslg_free(&g);
            mesh_fail(err, errlen, "%s: lists its own vertices; expected 0 (vertices in %s.node)",
                      path, prefix);
            goto fail;
        }
        m->nsegs = g.nsegs;
        m->seg = g.seg;
        m->smarker = g.smarker;
        m->nholes = g.nholes; /* kept, so that writing m again keeps them (Triangle's -r) */
        m->holes = g.holes;
        m->nregions = g.nregions;
        m->regions = g.regions;
        g.seg = g.smarker = NULL;
        g.holes = g.regions = NULL;
        pslg_free(&g);
    }
    return 0;
fail:
    mesh_flat_free(m);
    return -1;
}

/* ---------------------------------------------------------------- VTK ------------------- */

/* Legacy VTK's BINARY encoding: big-endian numbers, buffered; a block ends with a newline. */
typedef struct bebuf {
    FILE *f;
    size_t k;
    unsigned char b[4096];
} bebuf;

static void be_put(bebuf *w, uint64_t v, int bytes) {
    if (w->k + (size_t)bytes > sizeof w->b) {
        fwrite(w->b, 1, w->k, w->f);
        w->k = 0;
    }
    for (int i = bytes - 1; i >= 0; i--)
        w->b[w->k++] = (unsigned char)(v >> (8 * i));
}

static void be_f64(bebuf *w, double d) {
    uint64_t v;
    memcpy(&v, &d, sizeof v);
    be_put(w, v, 8);
}

static void be_end(bebuf *w) {
    fwrite(w->b, 1, w->k, w->f);
    w->k = 0;
    fputc('\n', w->f);
}

/* One block of n int32 values (v[i], or all `dflt` when v is NULL), binary or one per line. */
static void vtk_ints(bebuf *w, const int32_t *v, int32_t n, int32_t dflt, int binary) {
    char line[32];
    for (int32_t i = 0; i < n; i++) {
        int32_t x = v ? v[i] : dflt;
        if (binary) {
            be_put(w, (uint32_t)x, 4);
        } else {
            char *p = fmt_int(line, x);
            *p++ = '\n';
            fwrite(line, 1, (size_t)(p - line), w->f);
        }
    }
    if (binary) be_end(w);
}

int meshio_write_vtk(const mesh_flat *m, meshio_set *set, int binary, const char *path, char *err,
                     size_t errlen) {
    wfile wf;
    if (meshio_wopen(&wf, set, path, err, errlen)) return -1;
    bebuf w = {wf.f, 0, {0}};
    fprintf(wf.f, "# vtk DataFile Version 3.0\npcdm mesh\n%s\nDATASET UNSTRUCTURED_GRID\n",
            binary ? "BINARY" : "ASCII");
    fprintf(wf.f, "POINTS %d double\n", (int)m->nverts);
    char line[160];
    for (int32_t i = 0; i < m->nverts; i++) {
        double x = ldexp(m->xy[2 * i], -m->scale_exp), y = ldexp(m->xy[2 * i + 1], -m->scale_exp);
        if (binary) {
            be_f64(&w, x);
            be_f64(&w, y);
            be_f64(&w, 0.0);
        } else {
            char *p = fmt_dbl(line, x);
            *p++ = ' ';
            p = fmt_dbl(p, y);
            memcpy(p, " 0\n", 3);
            fwrite(line, 1, (size_t)(p + 3 - line), wf.f);
        }
    }
    if (binary) be_end(&w);
    fprintf(wf.f, "CELLS %d %lld\n", (int)m->ntris, 4LL * m->ntris);
    for (int32_t t = 0; t < m->ntris; t++) {
        if (binary) {
            be_put(&w, 3, 4);
            for (int j = 0; j < 3; j++)
                be_put(&w, (uint32_t)m->tri[3 * t + j], 4);
            continue;
        }
        char *p = line;
        *p++ = '3';
        for (int j = 0; j < 3; j++) {
            *p++ = ' ';
            p = fmt_int(p, m->tri[3 * t + j]);
        }
        *p++ = '\n';
        fwrite(line, 1, (size_t)(p - line), wf.f);
    }
    if (binary) be_end(&w);
    fprintf(wf.f, "CELL_TYPES %d\n", (int)m->ntris);
    vtk_ints(&w, NULL, m->ntris, 5, binary);
    fprintf(wf.f, "CELL_DATA %d\nSCALARS rank int 1\nLOOKUP_TABLE default\n", (int)m->ntris);
    vtk_ints(&w, m->trank, m->ntris, 0, binary);
    if (m->tattr) {
        fprintf(wf.f, "SCALARS region_attr double 1\nLOOKUP_TABLE default\n");
        for (int32_t t = 0; t < m->ntris; t++) {
            if (binary) {
                be_f64(&w, m->tattr[t]);
            } else {
                char *p = fmt_dbl(line, m->tattr[t]);
                *p++ = '\n';
                fwrite(line, 1, (size_t)(p - line), wf.f);
            }
        }
        if (binary) be_end(&w);
    }
    fprintf(wf.f, "POINT_DATA %d\nSCALARS marker int 1\nLOOKUP_TABLE default\n", (int)m->nverts);
    vtk_ints(&w, m->vmarker, m->nverts, 0, binary);
    return meshio_wclose(&wf, 0);
}

/* ---------------------------------------------------------------- SVG ------------------- */

static const char *const palette[12] = {"#4e79a7", "#f28e2b", "#76b7b2", "#59a14f",
                                        "#edc948", "#b07aa1", "#ff9da7", "#9c755f",
                                        "#bab0ac", "#8cd17d", "#a0cbe8", "#ffbe7d"};

typedef struct svgmap {
    double x0, y1, s, pad;
} svgmap;

static char *put_pt(char *p, const svgmap *sm, const double *q) {
    p = put_fix(p, (q[0] - sm->x0) * sm->s + sm->pad);
    *p++ = ' ';
    return put_fix(p, (sm->y1 - q[1]) * sm->s + sm->pad);
}

int meshio_write_svg(const mesh_flat *m, meshio_set *set, const char *path, char *err,
                     size_t errlen) {
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int32_t i = 0; i < m->nverts; i++) {
        x0 = fmin(x0, m->xy[2 * i]);
        x1 = fmax(x1, m->xy[2 * i]);
        y0 = fmin(y0, m->xy[2 * i + 1]);
        y1 = fmax(y1, m->xy[2 * i + 1]);
    }
    if (m->nverts == 0) x0 = y0 = x1 = y1 = 0;
    double w = x1 - x0, h = y1 - y0, big = fmax(w, h);
    svgmap sm = {x0, y1, big > 0 ? 1000 / big : 1, 10};
    double W = w * sm.s + 2 * sm.pad, H = h * sm.s + 2 * sm.pad;
    /* triangles grouped by rank (counting sort) */
    int32_t maxr = 0;
    for (int32_t t = 0; m->trank && t < m->ntris; t++)
        if (m->trank[t] > maxr) maxr = m->trank[t];
    int32_t *start = mesh_xcalloc((size_t)maxr + 2, sizeof(int32_t));
    int32_t *order = mesh_xmalloc((size_t)m->ntris + 1, sizeof(int32_t));
    for (int32_t t = 0; t < m->ntris; t++)
        start[(m->trank && m->trank[t] > 0 ? m->trank[t] : 0) + 1]++;
    for (int32_t r = 0; r <= maxr; r++)
        start[r + 1] += start[r];
    for (int32_t t = 0; t < m->ntris; t++)
        order[start[m->trank && m->trank[t] > 0 ? m->trank[t] : 0]++] = t;
    for (int32_t r = maxr + 1; r > 0; r--)
        start[r] = start[r - 1];
    start[0] = 0;
    wfile wf;
    if (meshio_wopen(&wf, set, path, err, errlen)) {
        free(start);
        free(order);
        return -1;
    }
    /* edge width: a quarter of a typical triangle's size in pixels, at most one pixel */
    double ew = m->ntris ? fmin(1.0, 0.25 * sqrt(w * h * sm.s * sm.s / m->ntris)) : 1;
    fprintf(wf.f,
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
            "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 %.2f %.2f\" "
            "width=\"%.0f\" height=\"%.0f\">\n"
            "<!-- pcdm mesh: %d triangles, %d vertices, %d segments; fill = owning rank -->\n"
            "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n",
            W, H, W, H, (int)m->ntris, (int)m->nverts, (int)m->nsegs);
    char line[256];
    for (int32_t r = 0; r <= maxr; r++) {
        if (start[r] == start[r + 1]) continue;
        fprintf(wf.f,
                "<g fill=\"%s\" stroke=\"#808080\" stroke-width=\"%.3f\" "
                "stroke-linejoin=\"round\">\n",
                palette[r % 12], ew);
        for (int32_t i = start[r]; i < start[r + 1]; i++) {
            if ((i - start[r]) % 4096 == 0)
                fputs(i == start[r] ? "<path d=\"" : "\"/>\n<path d=\"", wf.f);
            const int32_t *t = m->tri + 3 * order[i];
            char *p = line;
            for (int k = 0; k < 3; k++) {
                *p++ = k ? 'L' : 'M';
                p = put_pt(p, &sm, m->xy + 2 * t[k]);
            }
            *p++ = 'Z';
            fwrite(line, 1, (size_t)(p - line), wf.f);
        }
        fputs("\"/>\n</g>\n", wf.f);
    }
    for (int pass = 0; pass < 2; pass++) { /* constraints black, then interfaces red */
        int any = 0;
        for (int32_t s = 0; s < m->nsegs; s++) {
            int iface = m->sinterface && m->sinterface[s];
            if (iface != pass) continue;
            if (any % 4096 == 0)
                fprintf(wf.f,
                        "%s<path fill=\"none\" stroke=\"%s\" stroke-width=\"%.2f\" "
                        "stroke-linecap=\"round\" d=\"",
                        any ? "\"/>\n" : "", pass ? "#e00000" : "black", pass ? 1.5 : 2.0);
            any++;
            char *p = line;
            *p++ = 'M';
            p = put_pt(p, &sm, m->xy + 2 * m->seg[2 * s]);
            *p++ = 'L';
            p = put_pt(p, &sm, m->xy + 2 * m->seg[2 * s + 1]);
            fwrite(line, 1, (size_t)(p - line), wf.f);
        }
        if (any) fputs("\"/>\n", wf.f);
    }
    fputs("</svg>\n", wf.f);
    free(start);
    free(order);
    return meshio_wclose(&wf, 0);
}
