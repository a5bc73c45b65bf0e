/* pwrite.c: a distributed mesh written by every rank at once (pwrite.h), no gather.
 *
 * Triangle files, in bounded memory: a file's text is never held whole.  Pass 1, for each of
 * the three files: each rank formats its lines into one chunk buffer (rank 0 starts with the
 * header, whose counts come from an MPI_Allreduce; the last rank ends with the trailer) until it
 * is full -- for the .node file up to mesh_part.keep bytes more -- keeps that text, and only
 * counts the bytes of the rest (integers by their digit count, coordinates by fmt_dbl_len: the
 * shortest round-trip digits found but not written, about 70% of formatting's cost).  One
 * MPI_Exscan of the three byte counts gives each rank its offsets in the temporary files rank 0
 * created (mkstemp) and named to all.  Pass 2: rank r takes the files in the order r, r + 1,
 * ... (mod 3), writes the kept text, then formats the remaining lines chunk by chunk, each
 * written at its offset with an independent MPI_File_write_at (no collective call inside the
 * loop, so ranks with different chunk counts never wait for each other), and its disk write
 * started at once (meshio_writeback, wfile.h: the MPI_File_sync before the renames then has
 * little left to write; measured at 2 ranks, 810 MB: 0.3-0.5 s of waiting gone).  The rotation
 * matters on a local file system: buffered writes to one file hold its inode lock, so two ranks
 * writing one file at once mostly wait for each other (measured: 560 MB by two writers into one
 * ext4 file 1.6 s, into two files 0.4 s).  Chunks are 1 MiB: copied into the page cache while still
 * in the processor's cache, they cost half the kernel time of 8 MiB chunks (measured).  The .ele
 * lines name each vertex about six times: its number's digits are formatted once per local vertex
 * (8 bytes and a length), and record numbers come from a decimal counter.  After MPI_File_close the
 * ranks agree on success; rank 0 renames the temporary files over the targets (or removes them),
 * and its outcome is agreed again.  Global numbers are 1-based in the files (Triangle's default),
 * so the bytes equal meshio_write_triangle's for the same mesh.  With mesh_part.threads T > 1 the
 * formatting runs on T threads ("several threads" below: blocks of records formatted at once,
 * written in order by the calling thread, which alone calls MPI), the counting on T ranges at once,
 * and the last rank counts nothing: its bytes place no rank.
 *
 * VTU pieces are local files (binary appended raw data, or ASCII), each written through
 * meshio_wopen/meshio_wclose, array by array in blocks converted on the fly (VTK's XML file
 * format: "VTK File Formats", appended data = UInt64 byte count then raw values); rank 0
 * writes the .pvtu index once every piece is written.
 *
 * Invariants: every rank returns the same status; no file is left half-written under its
 * final name; every MPI call's return code is checked (the communicators return errors).
 */
#include "io/pwrite.h"

#include "base/base.h"
#include "base/base_mpi.h"
#include "io/fmt.h"
#include "io/oset.h"
#include "io/ptext.h"
#include "io/wfile.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define PATH_MAX_LEN 1024
#define ERR_LEN 512

/* ---- errors ------------------------------------------------------------------------- */

/* ---- the text of one Triangle file, record by record --------------------------------- */

#define CHUNK_DEFAULT ((size_t)1 << 20) /* formatted text still in cache when copied out */
static size_t chunk_bytes = 0;          /* meshio_pwrite_set_chunk; 0: CHUNK_DEFAULT */

void meshio_pwrite_set_chunk(size_t bytes) {
    chunk_bytes = bytes;
}

enum { F_NODE, F_ELE, F_POLY };
_Static_assert(MESHIO_SKIP_NODE == 1 << F_NODE && MESHIO_SKIP_ELE == 1 << F_ELE &&
                   MESHIO_SKIP_POLY == 1 << F_POLY,
               "mesh_part.skip has one bit per file kind");

/* What one rank writes into one file: its records (first = number base + 1), the header
 * (rank 0) and the trailer (last rank). */
typedef struct ftext {
    const mesh_part *p;
    const uint64_t *vdig; /* per local vertex: the digits of its number + 1 (ltri, nlocal) */
    const uint8_t *vlen;  /* their count (0: not cached, format it) */
    char ctr[24];         /* the decimal form of record ctr_i's number (a counter) */
    int ctrlen;
    int64_t ctr_i;
    int kind;
    long long tot, base; /* records in the file (all ranks); numbers before this rank's */
    int first, last;
    int64_t nrec;
    size_t recmax; /* room one record may need */
} ftext;

static char *fmt_head(const ftext *x, char *q) {
    const mesh_part *p = x->p;
    if (x->kind == F_NODE)
        q += sprintf(q, "%lld 2 %d 1\n", x->tot, p->nattr);
    else if (x->kind == F_ELE)
        q += sprintf(q, "%lld 3 %d\n", x->tot, p->tattr || p->trank ? 1 : 0);
    else
        q += sprintf(q, "0 2 0 1\n%lld 1\n", x->tot);
    return q;
}

static char *fmt_tail(const ftext *x, char *q) {
    if (x->kind == F_NODE) return q + sprintf(q, "# written by pcdm\n");
    const mesh_part *p = x->p;
    if (x->kind == F_ELE)
        return q + sprintf(q, "# written by pcdm%s\n",
                           p->tattr   ? " (attribute: regional attribute)"
                           : p->trank ? " (attribute: owning rank)"
                                      : "");
    return meshio_fmt_domain(q, p->nholes, p->holes, p->nregions, p->regions, p->scale_exp);
}

static long long tri_vertex(const mesh_part *p, int64_t i, int k) {
    return p->tri ? (long long)p->tri[3 * i + k] : (long long)p->gid[p->ltri[3 * i + k]];
}

/* The decimal form of record i's number at q: a counter incremented digit by digit when the
 * records come in order (they do: each pass is sequential), else formatted afresh. */
static char *rec_number(ftext *x, int64_t i, char *q) {
    if (i != x->ctr_i) {
        x->ctrlen = (int)(fmt_int(x->ctr, x->base + i + 1) - x->ctr);
        x->ctr_i = i;
    }
    memcpy(q, x->ctr, (size_t)x->ctrlen);
    q += x->ctrlen;
    int d = x->ctrlen - 1; /* increment */
    while (d >= 0 && x->ctr[d] == '9')
        x->ctr[d--] = '0';
    if (d >= 0) {
        x->ctr[d]++;
    } else { /* 99..9 + 1: a new leading 1 */
        memmove(x->ctr + 1, x->ctr, (size_t)x->ctrlen);
        x->ctr[0] = '1';
        x->ctrlen++;
    }
    x->ctr_i++;
    return q;
}

/* Number + 1 of corner k of triangle i at q, from the digit cache when there. */
static char *tri_number(const ftext *x, int64_t i, int k, char *q) {
    const mesh_part *p = x->p;
    if (x->vdig) {
        int32_t v = p->ltri[3 * i + k];
        if (x->vlen[v]) {
            memcpy(q, &x->vdig[v], 8);
            return q + x->vlen[v];
        }
    }
    return fmt_int(q, tri_vertex(p, i, k) + 1);
}

/* Vertex record i's coordinates (*xy), attributes (*at, NULL: all 0) and marker (returned). */
static int32_t node_fields(const mesh_part *p, int64_t i, const double **xy, const double **at) {
    *at = NULL;
    if (i < p->nhead) {
        *xy = p->hxy + 2 * i;
        if (p->hvattr) *at = p->hvattr + (size_t)i * (size_t)p->nattr;
        return p->hvmarker ? p->hvmarker[i] : 0;
    }
    int64_t v = p->vsel ? p->vsel[i - p->nhead] : i - p->nhead;
    *xy = p->xy + 2 * v;
    if (p->vattr) *at = p->vattr + (size_t)v * (size_t)p->nattr;
    return p->vmarker ? p->vmarker[v] : 0;
}

/* Formats record i (0-based, this rank's) at q (which has room for 8 more bytes than the
 * record needs); returns the new end. */
static char *fmt_rec(ftext *x, int64_t i, char *q) {
    const mesh_part *p = x->p;
    q = rec_number(x, i, q);
    if (x->kind == F_NODE) {
        const double *xy, *at;
        int32_t mk = node_fields(p, i, &xy, &at);
        *q++ = ' ';
        q = fmt_dbl(q, p->scale_exp ? ldexp(xy[0], -p->scale_exp) : xy[0]);
        *q++ = ' ';
        q = fmt_dbl(q, p->scale_exp ? ldexp(xy[1], -p->scale_exp) : xy[1]);
        for (int k = 0; k < p->nattr; k++) {
            *q++ = ' ';
            q = fmt_dbl(q, at ? at[k] : 0.0);
        }
        *q++ = ' ';
        q = fmt_int(q, mk);
    } else if (x->kind == F_ELE) {
        for (int k = 0; k < 3; k++) {
            *q++ = ' ';
            q = tri_number(x, i, k, q);
        }
        if (p->tattr) {
            *q++ = ' ';
            q = fmt_dbl(q, p->tattr[i]);
        } else if (p->trank) {
            *q++ = ' ';
            q = fmt_int(q, p->trank[i]);
        }
    } else {
        for (int k = 0; k < 2; k++) {
            *q++ = ' ';
            q = fmt_int(q, (long long)p->seg[2 * i + k] + 1);
        }
        *q++ = ' ';
        q = fmt_int(q, p->smarker ? p->smarker[i] : 0);
    }
    *q++ = '\n';
    return q;
}

/* The length of record i, counted without formatting it (fmt_int_len, fmt_dbl_len). */
static size_t rec_len(ftext *x, int64_t i) {
    const mesh_part *p = x->p;
    size_t n = (size_t)fmt_int_len(x->base + i + 1) + 1;
    if (x->kind == F_NODE) {
        const double *xy, *at;
        int32_t mk = node_fields(p, i, &xy, &at);
        n += 1 + (size_t)fmt_dbl_len(p->scale_exp ? ldexp(xy[0], -p->scale_exp) : xy[0]);
        n += 1 + (size_t)fmt_dbl_len(p->scale_exp ? ldexp(xy[1], -p->scale_exp) : xy[1]);
        for (int k = 0; k < p->nattr; k++)
            n += 1 + (size_t)fmt_dbl_len(at ? at[k] : 0.0);
        return n + 1 + (size_t)fmt_int_len(mk);
    }
    if (x->kind == F_ELE) {
        for (int k = 0; k < 3; k++) {
            int32_t v = x->vdig ? p->ltri[3 * i + k] : 0;
            n += 1 + (x->vdig && x->vlen[v] ? x->vlen[v]
                                            : (size_t)fmt_int_len(tri_vertex(p, i, k) + 1));
        }
        if (p->tattr)
            n += 1 + (size_t)fmt_dbl_len(p->tattr[i]);
        else if (p->trank)
            n += 1 + (size_t)fmt_int_len(p->trank[i]);
        return n;
    }
    for (int k = 0; k < 2; k++)
        n += 1 + (size_t)fmt_int_len((long long)p->seg[2 * i + k] + 1);
    return n + 1 + (size_t)fmt_int_len(p->smarker ? p->smarker[i] : 0);
}

/* Fills buf (room: chunk + recmax + 256) from record *i on while below chunk bytes; the
 * trailer is appended once the records are done (*tail_done).  Returns the bytes. */
static size_t fill_chunk(ftext *x, int64_t *i, int *tail_done, char *buf, size_t chunk) {
    char *q = buf;
    while (*i < x->nrec && (size_t)(q - buf) < chunk)
        q = fmt_rec(x, (*i)++, q);
    if (*i == x->nrec && x->last && !*tail_done && (size_t)(q - buf) < chunk) {
        q = fmt_tail(x, q);
        *tail_done = 1;
    }
    return (size_t)(q - buf);
}

/* ---- several threads formatting one rank's text ------------------------------------------
 * With mesh_part.threads = T > 1 the records a rank formats after its kept text are cut into
 * blocks of a fixed number of records; T threads take the blocks in order, each formatting one
 * into a free slot of a ring of 2T + 1 buffers (with its own copy of the file's ftext: the
 * record counter is per thread), while the calling thread alone writes the blocks at their
 * offsets in block order and frees their slots.  A block's text depends only on its records,
 * so the bytes are the same as one thread's.  The counting pass runs on T contiguous ranges
 * of records at once (rec_len only reads). */

#define PT_MAXTHR 64

/* The threaded pass 2 of one file: blocks [0, nblk) of records from i0 on. */
typedef struct pfmt {
    pthread_mutex_t mu;
    pthread_cond_t cv; /* a slot filled or freed, or stop */
    const ftext *x;
    int64_t i0, per; /* first record, records per block */
    int64_t nblk, claim;
    int tail; /* the last block ends with the trailer */
    int nslot, stop;
    char **buf;
    size_t *len;
    int64_t *blk; /* the block a slot holds (ready when len != SIZE_MAX), or -1: free */
} pfmt;

/* Formats block j of w into buf with x (a thread's own copy); returns the bytes. */
static size_t pfmt_block(const pfmt *w, ftext *x, int64_t j, char *buf) {
    int64_t a = w->i0 + j * w->per, b = a + w->per < x->nrec ? a + w->per : x->nrec;
    char *q = buf;
    for (int64_t i = a; i < b; i++)
        q = fmt_rec(x, i, q);
    if (j == w->nblk - 1 && w->tail) q = fmt_tail(x, q);
    return (size_t)(q - buf);
}

static void *pfmt_worker(void *arg) {
    pfmt *w = arg;
    ftext x = *w->x;
    x.ctr_i = -1;
    pthread_mutex_lock(&w->mu);
    for (;;) {
        while (!w->stop && w->claim < w->nblk && w->blk[w->claim % w->nslot] >= 0)
            pthread_cond_wait(&w->cv, &w->mu);
        if (w->stop || w->claim >= w->nblk) break;
        int64_t j = w->claim++;
        int s = (int)(j % w->nslot);
        w->blk[s] = j;
        w->len[s] = SIZE_MAX;
        pthread_mutex_unlock(&w->mu);
        size_t n = pfmt_block(w, &x, j, w->buf[s]);
        pthread_mutex_lock(&w->mu);
        w->len[s] = n;
        pthread_cond_broadcast(&w->cv);
    }
    pthread_mutex_unlock(&w->mu);
    return NULL;
}

/* Records [*i, nrec) of x (and its trailer when x->last and not *tail_done) formatted by T
 * threads and written at *at of fh in order by this thread; *i, *tail_done and *at advance.
 * 0, or -1 with the message in err. */
static int pass2_threads(MPI_File fh, int wb, const char *path, ftext *x, int64_t *i,
                         int *tail_done, long long *at, size_t chunk, int T, char *err,
                         size_t errlen) {
    pfmt w;
    memset(&w, 0, sizeof w);
    w.x = x;
    w.i0 = *i;
    w.per = (int64_t)(chunk / 40) > 0 ? (int64_t)(chunk / 40) : 1;
    w.tail = x->last && !*tail_done;
    w.nblk = (x->nrec - *i + w.per - 1) / w.per;
    if (w.nblk == 0 && w.tail) w.nblk = 1;
    if (w.nblk == 0) return 0;
    if (T > PT_MAXTHR) T = PT_MAXTHR;
    if (T > w.nblk) T = (int)w.nblk;
    w.nslot = 2 * T + 1;
    w.buf = mesh_xmalloc((size_t)w.nslot, sizeof *w.buf);
    w.len = mesh_xmalloc((size_t)w.nslot, sizeof *w.len);
    w.blk = mesh_xmalloc((size_t)w.nslot, sizeof *w.blk);
    for (int s = 0; s < w.nslot; s++) {
        w.buf[s] = mesh_xmalloc((size_t)(w.per + 1) * x->recmax + 512, 1);
        w.blk[s] = -1;
    }
    pthread_mutex_init(&w.mu, NULL);
    pthread_cond_init(&w.cv, NULL);
    pthread_t th[PT_MAXTHR];
    int nth = 0;
    for (; nth < T; nth++)
        if (pthread_create(&th[nth], NULL, pfmt_worker, &w) != 0) break;
    ftext own = *x; /* no thread started: this one formats each block itself */
    own.ctr_i = -1;
    int ok = 1;
    for (int64_t j = 0; j < w.nblk && ok; j++) {
        int s = (int)(j % w.nslot);
        if (nth == 0) {
            w.blk[s] = j;
            w.len[s] = pfmt_block(&w, &own, j, w.buf[s]);
        }
        pthread_mutex_lock(&w.mu);
        while (w.blk[s] != j || w.len[s] == SIZE_MAX)
            pthread_cond_wait(&w.cv, &w.mu);
        size_t n = w.len[s];
        pthread_mutex_unlock(&w.mu);
        if (n && meshio_pwrite_at(fh, wb, *at, w.buf[s], n, path, err, errlen) != 0) ok = 0;
        *at += (long long)n;
        pthread_mutex_lock(&w.mu);
        w.blk[s] = -1;
        if (!ok) w.stop = 1;
        pthread_cond_broadcast(&w.cv);
        pthread_mutex_unlock(&w.mu);
    }
    for (int k = 0; k < nth; k++)
        pthread_join(th[k], NULL);
    pthread_cond_destroy(&w.cv);
    pthread_mutex_destroy(&w.mu);
    for (int s = 0; s < w.nslot; s++)
        free(w.buf[s]);
    free(w.buf);
    free(w.len);
    free(w.blk);
    *i = x->nrec;
    if (w.tail) *tail_done = 1;
    return ok ? 0 : -1;
}

/* A range [a, b) of records (or local vertices) one thread works on; n: its result. */
typedef struct prange {
    ftext *x;
    const mesh_part *p;
    uint64_t *vdig;
    uint8_t *vlen;
    int64_t a, b;
    long long n;
    void (*fn)(struct prange *r);
} prange;

static void *prange_run(void *arg) {
    prange *r = arg;
    r->fn(r);
    return NULL;
}

/* Runs r0.fn on T contiguous parts of [a, b) at once (T - 1 new threads and this one; one
 * part when the range is short); returns the sum of their n. */
static long long split_run(prange r0, int64_t a, int64_t b, int T) {
    if (T > PT_MAXTHR) T = PT_MAXTHR;
    if (T < 1 || b - a < 4096) T = 1;
    prange r[PT_MAXTHR];
    pthread_t th[PT_MAXTHR];
    int started[PT_MAXTHR] = {0};
    for (int k = 0; k < T; k++) {
        r[k] = r0;
        r[k].a = a + (b - a) * k / T;
        r[k].b = a + (b - a) * (k + 1) / T;
        r[k].n = 0;
    }
    for (int k = 1; k < T; k++)
        started[k] = pthread_create(&th[k], NULL, prange_run, &r[k]) == 0;
    r[0].fn(&r[0]);
    long long n = r[0].n;
    for (int k = 1; k < T; k++) {
        if (started[k])
            pthread_join(th[k], NULL);
        else
            r[k].fn(&r[k]);
        n += r[k].n;
    }
    return n;
}

/* The bytes of records [a, b) of r->x. */
static void count_range(prange *r) {
    long long n = 0;
    for (int64_t j = r->a; j < r->b; j++)
        n += (long long)rec_len(r->x, j);
    r->n = n;
}

/* The digit cache of local vertices [a, b): each number + 1 as up to 8 digits (padded with
 * blanks) and their count (0: more than 8 digits, formatted each time). */
static void digits_range(prange *r) {
    for (int64_t v = r->a; v < r->b; v++) {
        char d[24];
        long long g = (long long)r->p->gid[v] + 1;
        int n = g >= 1 && g <= 99999999 ? (int)(fmt_int(d, g) - d) : 0;
        memset(d + n, ' ', 8 - (size_t)n);
        memcpy(&r->vdig[v], d, 8);
        r->vlen[v] = (uint8_t)n;
    }
}

/* ---- one shared file ------------------------------------------------------------------- */

#define NFILES 3

/* Collective.  Writes every rank's texts x[0 .. nf) into path[0 .. nf), each file atomically,
 * chunk by chunk.  Pass 1 runs over every file, then one MPI_Exscan gives all the offsets, and
 * in pass 2 rank r writes the files starting with file r mod nf: on ext4 (and most local file
 * systems) buffered writes to one file hold its inode lock, so two ranks writing one file at
 * once mostly wait for each other, while two files fill in parallel. */
static int write_files(MPI_Comm comm, meshio_set *set, const char (*path)[PATH_MAX_LEN + 8],
                       ftext *x, int nf, char *err, size_t errlen) {
    int rank;
    MESH_MPI(MPI_Comm_rank(comm, &rank));
    char tmp[NFILES][PATH_MAX_LEN + 16];
    memset(tmp, 0, sizeof tmp);
    int ok = 1;
    for (int f = 0; f < nf && rank == 0 && ok; f++) {
        int fd = meshio_mktemp(path[f], tmp[f], sizeof tmp[f], err, errlen);
        if (fd >= 0) {
            close(fd);
            if (meshio_set_add(set, tmp[f], path[f], err, errlen) != 0) {
                unlink(tmp[f]);
                fd = -1;
            }
        }
        if (fd < 0) {
            ok = 0;
            for (int g = 0; g < f; g++) {
                unlink(tmp[g]);
                meshio_set_drop(set, tmp[g]);
            }
        }
    }
    if (meshio_pagree(comm, ok, err, errlen)) return -1;
    MESH_MPI(MPI_Bcast(tmp, (int)sizeof tmp, MPI_CHAR, 0, comm));

    /* pass 1: each file's first chunk (for the .node text keep bytes more) formatted and kept,
     * the rest counted; a buffer's untouched pages cost nothing when the text is shorter */
    size_t chunk = chunk_bytes ? chunk_bytes : CHUNK_DEFAULT, kept[NFILES];
    size_t rmax = 0;
    for (int f = 0; f < nf; f++)
        rmax = x[f].recmax > rmax ? x[f].recmax : rmax;
    char *buf[NFILES], *scratch = mesh_xmalloc(rmax + 256, 1);
    int64_t i[NFILES];
    int tail_done[NFILES], counted[NFILES];
    long long mine[NFILES], off[NFILES] = {0};
    /* with threads, pass 2 formats in parallel what pass 1 would keep, and the last rank, whose
     * bytes place no other rank, counts nothing */
    int T = nf > 0 && x[0].p->threads > 1 ? x[0].p->threads : 1;
    for (int f = 0; f < nf; f++) {
        size_t ahead =
            T > 1 ? (x[f].last ? 0 : chunk) : chunk + (x[f].kind == F_NODE ? x[f].p->keep : 0);
        buf[f] = mesh_xmalloc(ahead + x[f].recmax + 512, 1);
        char *q = x[f].first ? fmt_head(&x[f], buf[f]) : buf[f];
        i[f] = 0;
        tail_done[f] = 0;
        kept[f] = (size_t)(q - buf[f]) + fill_chunk(&x[f], &i[f], &tail_done[f], q, ahead);
        mine[f] = (long long)kept[f];
        counted[f] = T == 1 || !x[f].last;
        if (T > 1 && counted[f])
            mine[f] += split_run((prange){.x = &x[f], .fn = count_range}, i[f], x[f].nrec, T);
        else if (T == 1)
            for (int64_t j = i[f]; j < x[f].nrec; j++)
                mine[f] += (long long)rec_len(&x[f], j);
        if (x[f].last && !tail_done[f]) mine[f] += (long long)(fmt_tail(&x[f], scratch) - scratch);
    }
    mesh_mpi_settle(comm); /* the ranks that formatted fewer bytes wait asleep */
    MESH_MPI(MPI_Exscan(mine, off, nf, MPI_LONG_LONG, MPI_SUM, comm));
    if (rank == 0) /* MPI_Exscan leaves rank 0's result undefined */
        for (int f = 0; f < nf; f++)
            off[f] = 0;

    /* the files, opened one by one (collective), then pass 2 in this rank's order */
    MPI_File fh[NFILES];
    int nopen = 0;
    for (; nopen < nf; nopen++) {
        int rc = MPI_File_open(comm, tmp[nopen], MPI_MODE_WRONLY, MPI_INFO_NULL, &fh[nopen]);
        if (rc != MPI_SUCCESS) {
            ok = 0;
            char why[MPI_MAX_ERROR_STRING];
            mesh_fail(err, errlen, "%s: cannot open for parallel writing: %s", path[nopen],
                      meshio_mpi_strerror(rc, why));
        }
        if (meshio_pagree(comm, ok, err, errlen)) break;
        MESH_MPI(MPI_File_set_errhandler(fh[nopen], MPI_ERRORS_RETURN));
    }
    int wb[NFILES]; /* this rank's descriptors for the writeback hints */
    for (int f = 0; f < nf; f++)
        wb[f] = nopen == nf ? meshio_writeback_open(tmp[f]) : -1;
    for (int k = 0; k < nf && nopen == nf && ok; k++) {
        int f = (k + rank) % nf;
        long long at = off[f];
        size_t n = kept[f];
        while (ok) {
            if (n && meshio_pwrite_at(fh[f], wb[f], at, buf[f], n, path[f], err, errlen) != 0)
                ok = 0;
            at += (long long)n;
            if (i[f] == x[f].nrec && (tail_done[f] || !x[f].last)) break;
            if (T > 1) {
                if (pass2_threads(fh[f], wb[f], path[f], &x[f], &i[f], &tail_done[f], &at, chunk, T,
                                  err, errlen) != 0)
                    ok = 0;
                n = 0;
                continue;
            }
            n = fill_chunk(&x[f], &i[f], &tail_done[f], buf[f], chunk);
        }
        if (ok && counted[f] &&
            at != off[f] + mine[f]) { /* pass 2 must have made exactly pass 1's bytes */
            ok = 0;
            mesh_fail(err, errlen, "%s: internal error: %lld bytes counted, %lld written", path[f],
                      mine[f], at - off[f]);
        }
    }
    for (int f = 0; f < nf; f++)
        free(buf[f]);
    free(scratch);
    for (int f = 0; f < nopen; f++)
        if (meshio_pclose(comm, &fh[f], ok, path[f], err, errlen) != 0) ok = 0;
    for (int f = 0; f < nf; f++)
        if (wb[f] >= 0) close(wb[f]);
    int all = nopen == nf && meshio_pagree(comm, ok, err, errlen) == 0;
    ok = 1;
    for (int f = 0; f < nf && rank == 0; f++) {
        if (!all || !ok) {
            unlink(tmp[f]);
            meshio_set_drop(set, tmp[f]);
        } else if (set) {
            meshio_set_done(set, tmp[f]);
        } else if (rename(tmp[f], path[f]) != 0) {
            ok = 0;
            mesh_fail(err, errlen, "%s: cannot rename the written file: %s", path[f],
                      strerror(errno));
            unlink(tmp[f]);
        }
    }
    if (!all) return -1;
    return meshio_pagree(comm, ok, err, errlen);
}

/* ---- Triangle files ------------------------------------------------------------------- */

static void counts(MPI_Comm comm, const mesh_part *p, long long tot[3], long long base[3]) {
    long long mine[3] = {(long long)p->nverts, (long long)p->ntris, (long long)p->nsegs};
    int rank;
    MESH_MPI(MPI_Comm_rank(comm, &rank));
    MESH_MPI(MPI_Allreduce(mine, tot, 3, MPI_LONG_LONG, MPI_SUM, comm));
    MESH_MPI(MPI_Exscan(mine, base, 3, MPI_LONG_LONG, MPI_SUM, comm));
    if (rank == 0) base[0] = base[1] = base[2] = 0;
}

int meshio_pwrite_triangle(MPI_Comm comm, meshio_set *set, const mesh_part *p, const char *prefix,
                           char *err, size_t errlen) {
    int rank, size;
    MESH_MPI(MPI_Comm_rank(comm, &rank));
    MESH_MPI(MPI_Comm_size(comm, &size));
    if (errlen) err[0] = '\0';
    if ((p->skip & MESHIO_SKIP_ALL) == MESHIO_SKIP_ALL) return 0; /* -NEP: every rank alike */
    long long tot[3], base[3];
    counts(comm, p, tot, base);
    static const char *const ext[3] = {"node", "ele", "poly"};
    const int64_t nrec[3] = {p->nverts, p->ntris, p->nsegs};
    /* the .ele file names each vertex about six times: its digits formatted once (8 bytes and
     * a count per local vertex; numbers of more than 8 digits are formatted each time) */
    uint64_t *vdig = NULL;
    uint8_t *vlen = NULL;
    if (!p->tri && p->ltri && p->nlocal > 0 && p->ntris > 0 && !(p->skip & MESHIO_SKIP_ELE)) {
        vdig = mesh_xmalloc((size_t)p->nlocal, sizeof *vdig);
        vlen = mesh_xmalloc((size_t)p->nlocal, 1);
        split_run((prange){.p = p, .vdig = vdig, .vlen = vlen, .fn = digits_range}, 0, p->nlocal,
                  p->threads > 1 ? p->threads : 1);
    }
    char path[NFILES][PATH_MAX_LEN + 8];
    ftext x[NFILES];
    int nf = 0; /* the files written, in kind order (-N, -E, -P leave some out) */
    for (int k = 0; k < NFILES; k++) {
        if (p->skip & (1u << k)) continue;
        int f = nf++;
        snprintf(path[f], sizeof path[f], "%s.%s", prefix, ext[k]);
        memset(&x[f], 0, sizeof x[f]);
        x[f].p = p;
        x[f].kind = k;
        x[f].tot = tot[k];
        x[f].base = base[k];
        x[f].first = rank == 0;
        x[f].last = rank == size - 1;
        x[f].nrec = nrec[k];
        x[f].recmax = 128 + 32 * (size_t)(p->nattr > 0 ? p->nattr : 0);
        if (f == F_POLY) /* the trailer (holes, regions) must fit where a record does */
            x[f].recmax += meshio_domain_maxlen(p->nholes, p->nregions);
        x[f].ctr_i = -1;
        if (k == F_ELE) {
            x[f].vdig = vdig;
            x[f].vlen = vlen;
        }
    }
    int rc = write_files(comm, set, (const char(*)[PATH_MAX_LEN + 8]) path, x, nf, err, errlen);
    free(vdig);
    free(vlen);
    return rc;
}

/* ---- VTK XML pieces ------------------------------------------------------------------- */

static int little_endian(void) {
    const uint16_t one = 1;
    unsigned char c;
    memcpy(&c, &one, 1);
    return c == 1;
}

/* The arrays of a piece, in file order: name, VTK type, bytes per value, components. */
enum { A_MARKER, A_RANK, A_SUB, A_ATTR, A_POINTS, A_CONN, A_OFFS, A_TYPES, A_N };
static const struct vtu_arr {
    const char *name, *type;
    int size, ncomp;
} vtu_arrs[A_N] = {{"marker", "Int32", 4, 1},    {"rank", "Int32", 4, 1},
                   {"subdomain", "Int32", 4, 1}, {"region_attr", "Float64", 8, 1},
                   {"Points", "Float64", 8, 3},  {"connectivity", "Int64", 8, 1},
                   {"offsets", "Int64", 8, 1},   {"types", "UInt8", 1, 1}};

/* Number of values of array a in m. */
static size_t vtu_count(const mesh_flat *m, int a) {
    size_t nv = (size_t)m->nverts, nt = (size_t)m->ntris;
    return a == A_MARKER ? nv : a == A_POINTS ? 3 * nv : a == A_CONN ? 3 * nt : nt;
}

/* Values [k0, k0 + n) of array a into out (its VTK type). */
static void vtu_fill(const mesh_flat *m, int rank, const int32_t *tsub, int a, size_t k0, size_t n,
                     void *out) {
    int32_t *i32 = out;
    int64_t *i64 = out;
    double *f64 = out;
    uint8_t *u8 = out;
    for (size_t j = 0; j < n; j++) {
        size_t k = k0 + j;
        switch (a) {
        case A_MARKER:
            i32[j] = m->vmarker ? m->vmarker[k] : 0;
            break;
        case A_RANK:
            i32[j] = m->trank ? m->trank[k] : rank;
            break;
        case A_SUB:
            i32[j] = tsub[k];
            break;
        case A_ATTR:
            f64[j] = m->tattr[k];
            break;
        case A_POINTS:
            f64[j] = k % 3 == 2 ? 0.0 : ldexp(m->xy[k / 3 * 2 + k % 3], -m->scale_exp);
            break;
        case A_CONN:
            i64[j] = m->tri[k];
            break;
        case A_OFFS:
            i64[j] = 3 * (int64_t)(k + 1);
            break;
        default:
            u8[j] = 5; /* VTK_TRIANGLE */
        }
    }
}

#define VTU_BLOCK 8192 /* values converted at a time */

int meshio_write_vtu(const mesh_flat *m, meshio_set *set, int rank, const int32_t *tsub, int binary,
                     const char *path, char *err, size_t errlen) {
    wfile w;
    if (meshio_wopen(&w, set, path, err, errlen)) return -1;
    FILE *f = w.f;
    int use[A_N];
    uint64_t off[A_N], o = 0;
    for (int a = 0; a < A_N; a++) {
        use[a] = (a != A_SUB || tsub) && (a != A_ATTR || m->tattr);
        off[a] = o;
        if (use[a]) o += 8 + (uint64_t)vtu_count(m, a) * (uint64_t)vtu_arrs[a].size;
    }
    fprintf(f,
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
            "byte_order=\"%s\" header_type=\"UInt64\">\n<UnstructuredGrid>\n"
            "<Piece NumberOfPoints=\"%lld\" NumberOfCells=\"%lld\">\n",
            little_endian() ? "LittleEndian" : "BigEndian", (long long)m->nverts,
            (long long)m->ntris);
    unsigned char *blk = mesh_xmalloc(VTU_BLOCK, 8);
    for (int a = 0; a < A_N; a++) {
        if (!use[a]) continue;
        if (a == A_MARKER) fputs("<PointData Scalars=\"marker\">\n", f);
        if (a == A_RANK) fputs("<CellData Scalars=\"rank\">\n", f);
        if (a == A_POINTS) fputs("<Points>\n", f);
        if (a == A_CONN) fputs("<Cells>\n", f);
        const struct vtu_arr *d = &vtu_arrs[a];
        fprintf(f, "<DataArray type=\"%s\"", d->type);
        if (a != A_POINTS) fprintf(f, " Name=\"%s\"", d->name);
        if (d->ncomp > 1) fprintf(f, " NumberOfComponents=\"%d\"", d->ncomp);
        if (binary) {
            fprintf(f, " format=\"appended\" offset=\"%llu\"/>\n", (unsigned long long)off[a]);
        } else {
            fprintf(f, " format=\"ascii\">\n");
            size_t n = vtu_count(m, a);
            char line[48];
            for (size_t k0 = 0; k0 < n; k0 += VTU_BLOCK) {
                size_t nb = n - k0 < VTU_BLOCK ? n - k0 : VTU_BLOCK;
                vtu_fill(m, rank, tsub, a, k0, nb, blk);
                for (size_t j = 0; j < nb; j++) {
                    char *q = line;
                    if (d->size == 4) q = fmt_int(q, ((const int32_t *)(void *)blk)[j]);
                    if (a == A_POINTS || a == A_ATTR)
                        q = fmt_dbl(q, ((const double *)(void *)blk)[j]);
                    if (a == A_CONN || a == A_OFFS)
                        q = fmt_int(q, ((const int64_t *)(void *)blk)[j]);
                    if (a == A_TYPES) q = fmt_int(q, blk[j]);
                    *q++ = (k0 + j + 1) % 12 == 0 || k0 + j + 1 == n ? '\n' : ' ';
                    fwrite(line, 1, (size_t)(q - line), f);
                }
            }
            fputs("</DataArray>\n", f);
        }
        if (a == A_MARKER) fputs("</PointData>\n", f);
        if (a == (m->tattr ? A_ATTR : tsub ? A_SUB : A_RANK)) fputs("</CellData>\n", f);
        if (a == A_POINTS) fputs("</Points>\n", f);
        if (a == A_TYPES) fputs("</Cells>\n", f);
    }
    fputs("</Piece>\n</UnstructuredGrid>\n", f);
    if (binary) {
        fputs("<AppendedData encoding=\"raw\">\n_", f);
        for (int a = 0; a < A_N; a++) {
            if (!use[a]) continue;
            size_t n = vtu_count(m, a);
            uint64_t bytes = (uint64_t)n * (uint64_t)vtu_arrs[a].size;
            fwrite(&bytes, sizeof bytes, 1, f);
            for (size_t k0 = 0; k0 < n; k0 += VTU_BLOCK) {
                size_t nb = n - k0 < VTU_BLOCK ? n - k0 : VTU_BLOCK;
                vtu_fill(m, rank, tsub, a, k0, nb, blk);
                fwrite(blk, (size_t)vtu_arrs[a].size, nb, f);
            }
        }
        fputs("\n</AppendedData>\n", f);
    }
    fputs("</VTKFile>\n", f);
    free(blk);
    return meshio_wclose(&w, 0);
}

int meshio_pwrite_pvtu(MPI_Comm comm, meshio_set *set, const mesh_flat *local, const int32_t *tsub,
                       int binary, const char *prefix, char *err, size_t errlen) {
    int rank, size;
    MESH_MPI(MPI_Comm_rank(comm, &rank));
    MESH_MPI(MPI_Comm_size(comm, &size));
    if (errlen) err[0] = '\0';
    char path[PATH_MAX_LEN + 32];
    int ok = strlen(prefix) < PATH_MAX_LEN;
    if (!ok) mesh_fail(err, errlen, "%s: path too long", prefix);
    if (ok) {
        snprintf(path, sizeof path, "%s_%d.vtu", prefix, rank);
        ok = meshio_write_vtu(local, set, rank, tsub, binary, path, err, errlen) == 0;
    }
    if (meshio_pagree(comm, ok, err, errlen)) return -1;
    if (rank == 0) {
        const char *slash = strrchr(prefix, '/');
        const char *base = slash ? slash + 1 : prefix;
        snprintf(path, sizeof path, "%s.pvtu", prefix);
        wfile w;
        ok = meshio_wopen(&w, set, path, err, errlen) == 0;
        if (ok) {
            fprintf(w.f,
                    "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" "
                    "byte_order=\"%s\" header_type=\"UInt64\">\n"
                    "<PUnstructuredGrid GhostLevel=\"0\">\n"
                    "<PPointData Scalars=\"marker\"><PDataArray type=\"Int32\" "
                    "Name=\"marker\"/></PPointData>\n"
                    "<PCellData Scalars=\"rank\"><PDataArray type=\"Int32\" "
                    "Name=\"rank\"/>%s%s</PCellData>\n"
                    "<PPoints><PDataArray type=\"Float64\" NumberOfComponents=\"3\"/></PPoints>\n",
                    little_endian() ? "LittleEndian" : "BigEndian",
                    tsub ? "<PDataArray type=\"Int32\" Name=\"subdomain\"/>" : "",
                    local->tattr ? "<PDataArray type=\"Float64\" Name=\"region_attr\"/>" : "");
            for (int r = 0; r < size; r++)
                fprintf(w.f, "<Piece Source=\"%s_%d.vtu\"/>\n", base, r);
            fputs("</PUnstructuredGrid>\n</VTKFile>\n", w.f);
            ok = meshio_wclose(&w, 0) == 0;
        }
    }
    return meshio_pagree(comm, ok, err, errlen);
}
