/* textin: an input text file loaded whole and walked line by line (textin.h).
 *
 * A regular file's buffer is allocated once at its size (a pipe's doubles); the first 64 KiB
 * are read alone and looked at before anything else is (the byte-order mark, NUL bytes, the
 * first token), then the rest in 1 MiB pieces, each scanned for a NUL byte (memchr) while it is
 * still in cache.  Walking an LF or CRLF file is one memchr per line, as it was before CR files
 * were taken.
 */
#include "base/textin.h"

#include "base/base.h"

#include <errno.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define FIRST_CHUNK ((size_t)64 * 1024) /* read and looked at before the rest */
#define CHUNK ((size_t)1 << 20)         /* the rest, one NUL scan per piece */
#define FIRST_LINE_MAX ((size_t)64 * 1024)
#define PRELUDE_MAX ((size_t)1 << 20) /* comments and blanks before the first count */

/* Whether the text at s uses CR line ends: its first line end is a lone CR.  -1: not known yet
 * (no line end before e, or a CR last before e while more may follow). */
static int cr_file(const char *s, const char *e, int eof) {
    const char *p = s + strcspn(s, "\r\n"); /* *e is NUL */
    if (p >= e) return eof ? 0 : -1;
    if (*p == '\n') return 0;
    if (p + 1 >= e) return eof ? 1 : -1;
    return p[1] != '\n';
}

/* Whether c ends a line in a file whose mode is cr. */
static int is_eol(char c, int cr) {
    return c == '\n' || (cr && c == '\r');
}

/* The number of the line holding p in the text starting at s. */
static long line_at(const char *s, const char *p, int cr) {
    long n = 1;
    for (const char *q = s; q < p; q++)
        n += *q == '\n' ? !(cr && q > s && q[-1] == '\r') : cr && *q == '\r';
    return n;
}

enum { J_NEED, J_COUNT, J_STOP, J_FAIL };

/* Looks for the first token of the first data line in [s, e) (*e is NUL; eof: that is the whole
 * file).  J_COUNT: it is a count (an optional sign and digits), or the file has no data line;
 * J_STOP: it cannot be one (the reader's parse refuses it: loading can stop); J_NEED: more bytes
 * are needed; J_FAIL: the first line is too long or the first MiB holds no data (*line, *why). */
static int judge(const char *s, const char *e, int eof, long *line, const char **why) {
    int cr = cr_file(s, e, eof);
    const char *p = s, *bol = s;
    long n = 1;
    for (;;) {
        while (p < e && *p && strchr(" \t\v\f\r\n", *p)) {
            if (cr >= 0 && is_eol(*p, cr) && !(cr && *p == '\n' && p > s && p[-1] == '\r')) n++;
            if (cr >= 0 && is_eol(*p, cr)) bol = p + 1;
            p++;
        }
        if (p < e && *p == '#') { /* a comment: to the line's end */
            while (p < e && !(cr >= 0 && is_eol(*p, cr)))
                p++;
            if (p < e) continue;
        }
        if (p >= e && eof) return J_COUNT; /* no data line: the reader says so */
        if (p < e) {                       /* the first token */
            const char *t = p + (*p == '+' || *p == '-');
            const char *d = t;
            while (t < e && *t >= '0' && *t <= '9')
                t++;
            int ended = t < e ? strchr(" \t\v\f\r\n#", *t) != NULL : eof;
            if (t < e && !ended) return J_STOP; /* a character no count has */
            if (ended) return t > d ? J_COUNT : J_STOP;
        }
        /* the bytes end inside the comment or the token */
        *line = n;
        if ((size_t)(e - bol) > FIRST_LINE_MAX) {
            *why = "a line of more than 64 KiB before the first count: not a text file";
            return J_FAIL;
        }
        if ((size_t)(e - s) > PRELUDE_MAX) {
            *why = "no count in the first MiB (only comments and blanks): not a text file";
            return J_FAIL;
        }
        return J_NEED;
    }
}

int mesh_textin_load(mesh_textin *t, const char *path, char *err, size_t errlen) {
    memset(t, 0, sizeof *t);
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    size_t cap = FIRST_CHUNK + 1, len = 0, skip = 0;
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0 &&
        (uintmax_t)st.st_size < SIZE_MAX / 2)
        cap = (size_t)st.st_size + 1; /* exact: no copy while loading */
    char *buf = mesh_xmalloc(cap, 1);
    int verdict = J_NEED, rc = -1;
    for (;;) {
        size_t len0 = len;
        int eof;
        if (len + 1 == cap) { /* full: one more byte tells the end of a file read whole */
            int c = getc(f);
            if (c == EOF) break;
            cap *= 2;
            buf = mesh_xrealloc(buf, cap, 1);
            buf[len++] = (char)c;
            eof = 0;
        } else {
            size_t want = cap - 1 - len, most = verdict == J_NEED ? FIRST_CHUNK : CHUNK;
            if (want > most) want = most;
            size_t got = fread(buf + len, 1, want, f);
            len += got;
            eof = got < want;
        }
        buf[len] = '\0';
        if (len0 == 0) {
            const unsigned char *u = (const unsigned char *)buf;
            if (len >= 2 && ((u[0] == 0xff && u[1] == 0xfe) || (u[0] == 0xfe && u[1] == 0xff))) {
                mesh_fail_at(err, errlen, path, 1, "UTF-16 text (save the file as UTF-8 or ASCII)");
                goto out;
            }
            if (len >= 3 && u[0] == 0xef && u[1] == 0xbb && u[2] == 0xbf) skip = 3;
        }
        const char *z = memchr(buf + len0, '\0', len - len0);
        if (z) {
            const char *s = buf + skip;
            mesh_fail_at(err, errlen, path, line_at(s, z, cr_file(s, z, 1) > 0),
                         "a NUL byte: not a text file");
            goto out;
        }
        if (verdict == J_NEED) {
            long line = 1;
            const char *why = "";
            verdict = judge(buf + skip, buf + len, eof, &line, &why);
            if (verdict == J_FAIL) {
                mesh_fail_at(err, errlen, path, line, "%s", why);
                goto out;
            }
            if (verdict == J_STOP) break; /* the rest is never read: the reader refuses the line */
        }
        if (eof) break;
    }
    if (ferror(f)) {
        snprintf(err, errlen, "%s: cannot read: %s", path, strerror(errno));
        goto out;
    }
    t->buf = buf;
    t->end = buf + len;
    t->next = buf + skip;
    t->cr = cr_file(buf + skip, buf + len, 1) > 0;
    buf = NULL;
    rc = 0;
out:
    free(buf);
    fclose(f);
    return rc;
}

char *mesh_textin_line(mesh_textin *t) {
    while (t->next && t->next < t->end) {
        char *s = t->next, *e;
        if (!t->cr) {
            e = memchr(s, '\n', (size_t)(t->end - s));
        } else {
            e = s + strcspn(s, "\r\n"); /* no NUL before t->end */
            if (e >= t->end) e = NULL;
        }
        if (e) {
            t->next = e + 1 + (*e == '\r' && e[1] == '\n');
            *e = '\0';
        } else {
            t->next = NULL;
        }
        t->line++;
        char *h = strchr(s, '#');
        if (h) *h = '\0';
        s += strspn(s, " \t\r\v\f");
        if (*s) return s;
    }
    return NULL;
}

size_t mesh_textin_left(const mesh_textin *t) {
    return t->next ? (size_t)(t->end - t->next) : 0;
}

void mesh_textin_free(mesh_textin *t) {
    free(t->buf);
    memset(t, 0, sizeof *t);
}
