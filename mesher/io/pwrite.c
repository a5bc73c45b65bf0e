/* pwrite.c: a distributed mesh written by every rank at once (pwrite.h), no gather.
 *
 * Triangle files: every rank formats its lines into one memory buffer (rank 0 prefixes the
 * header, whose counts come from an MPI_Allreduce; the last rank appends the trailer), an
 * MPI_Exscan of the buffer lengths gives each rank its byte offset, and the ranks write their
 * bytes with MPI-IO into one temporary file that rank 0 created (mkstemp) and named to all.
 * After MPI_File_close the ranks agree on success; rank 0 then renames the temporary file over
 * the target (or removes it), and its outcome is agreed again.  Global numbers are 1-based in
 * the files (Triangle's default), so the bytes equal meshio_write_triangle's for the same mesh.
 *
 * VTU pieces are local files (binary appended raw data, or ASCII), each written through
 * meshio_wopen/meshio_wclose; rank 0 writes the .pvtu index once every piece is written.
 *
 * Invariants: every rank returns the same status; no file is left half-written under its
 * final name; every MPI call's return code is checked (the communicators return errors).
 */
#include "io/pwrite.h"

#include "base/base.h"
#include "io/fmt.h"
#include "io/wfile.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define PATH_MAX_LEN 1024
#define ERR_LEN 512

/* ---- collective agreement ------------------------------------------------------------ */

/* Collective.  0 when ok on every rank; otherwise -1 everywhere, with the message of the
 * lowest failing rank copied into err on every rank. */
static int agree(MPI_Comm comm, int ok, char *err, size_t errlen) {
    int rank, size;
    MESH_MPI(MPI_Comm_rank(comm, &rank));
    MESH_MPI(MPI_Comm_size(comm, &size));
    int mine = ok ? size : rank, first;
    MESH_MPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm));
    if (first == size) return 0;
    char msg[ERR_LEN] = "";
    if (rank == first) snprintf(msg, sizeof msg, "%s", errlen ? err : "");
    MESH_MPI(MPI_Bcast(msg, (int)sizeof msg, MPI_CHAR, first, comm));
    if (errlen) snprintf(err, errlen, "%s", msg);
    return -1;
}

MESH_PRINTF(3, 4) static void efmt(char *err, size_t errlen, const char *fmt, ...) {
    if (!errlen) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

/* ---- a growing text buffer ------------------------------------------------------------- */

typedef struct tbuf {
    char *b;
    size_t n, cap;
} tbuf;

/* Room for at least `more` bytes; returns where to write. */
static char *tb_room(tbuf *t, size_t more) {
    if (t->n + more > t->cap) {
        size_t c = t->cap ? t->cap : 1 << 16;
        while (c < t->n + more)
            c *= 2;
        t->b = mesh_xrealloc(t->b, c, 1);
        t->cap = c;
    }
    return t->b + t->n;
}

static void tb_end(tbuf *t, const char *p) {
    t->n = (size_t)(p - t->b);
}

MESH_PRINTF(2, 3) static void tb_printf(tbuf *t, const char *fmt, ...) {
    char *p = tb_room(t, 256);
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(p, 256, fmt, ap);
    va_end(ap);
    if (n > 0) t->n += (size_t)(n < 256 ? n : 255);
}

/* ---- one shared file ------------------------------------------------------------------- */

/* Collective.  Writes every rank's t at its offset into path, atomically. */
static int write_shared(MPI_Comm comm, const char *path, const tbuf *t, char *err, size_t errlen) {
    int rank;
    MESH_MPI(MPI_Comm_rank(comm, &rank));
    char tmp[PATH_MAX_LEN + 16] = "";
    int ok = 1;
    if (rank == 0) {
        int fd = meshio_mktemp(path, tmp, sizeof tmp, err, errlen);
        if (fd < 0)
            ok = 0;
        else
            close(fd);
    }
    if (agree(comm, ok, err, errlen)) return -1;
    MESH_MPI(MPI_Bcast(tmp, (int)sizeof tmp, MPI_CHAR, 0, comm));

    long long mine = (long long)t->n, off = 0;
    MESH_MPI(MPI_Exscan(&mine, &off, 1, MPI_LONG_LONG, MPI_SUM, comm));
    if (rank == 0) off = 0; /* MPI_Exscan leaves rank 0's result undefined */
    MPI_File fh;
    int rc = MPI_File_open(comm, tmp, MPI_MODE_WRONLY, MPI_INFO_NULL, &fh);
    if (rc != MPI_SUCCESS) {
        ok = 0;
        efmt(err, errlen, "%s: cannot open for parallel writing (MPI-IO error %d)", path, rc);
    }
    if (agree(comm, ok, err, errlen)) {
        if (rank == 0) unlink(tmp);
        return -1;
    }
    MESH_MPI(MPI_File_set_errhandler(fh, MPI_ERRORS_RETURN));
    size_t done = 0;
    while (ok && done < t->n) { /* counts are int: write in pieces of at most 1 GiB */
        size_t chunk = t->n - done < ((size_t)1 << 30) ? t->n - done : (size_t)1 << 30;
        MPI_Status st;
        rc = MPI_File_write_at(fh, (MPI_Offset)(off + (long long)done), t->b + done, (int)chunk,
                               MPI_BYTE, &st);
        int got = 0;
        if (rc == MPI_SUCCESS) MPI_Get_count(&st, MPI_BYTE, &got);
        if (rc != MPI_SUCCESS || got != (int)chunk) {
            ok = 0;
            efmt(err, errlen, "%s: write failed at byte %lld (MPI-IO error %d)", path,
                 off + (long long)done, rc);
        }
        done += chunk;
    }
    if (MPI_File_close(&fh) != MPI_SUCCESS && ok) {
        ok = 0;
        efmt(err, errlen, "%s: closing failed", path);
    }
    int all = agree(comm, ok, err, errlen) == 0;
    ok = 1;
    if (rank == 0) {
        if (!all) {
            unlink(tmp);
        } else if (rename(tmp, path) != 0) {
            ok = 0;
            efmt(err, errlen, "%s: cannot rename the written file: %s", path, strerror(errno));
            unlink(tmp);
        }
    }
    if (!all) return -1;
    return agree(comm, ok, err, errlen);
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

static void fmt_node(const mesh_part *p, long long tot, long long base, int first, int last,
                     tbuf *t) {
    int nattr = p->vattr ? p->nattr : 0;
    if (first) tb_printf(t, "%lld 2 %d 1\n", tot, nattr);
    for (int64_t i = 0; i < p->nverts; i++) {
        char *q = tb_room(t, 64 + 32 * (size_t)nattr);
        q = fmt_int(q, base + i + 1);
        *q++ = ' ';
        q = fmt_dbl(q, ldexp(p->xy[2 * i], -p->scale_exp));
        *q++ = ' ';
        q = fmt_dbl(q, ldexp(p->xy[2 * i + 1], -p->scale_exp));
        for (int k = 0; k < nattr; k++) {
            *q++ = ' ';
            q = fmt_dbl(q, p->vattr[(size_t)i * (size_t)nattr + (size_t)k]);
        }
        *q++ = ' ';
        q = fmt_int(q, p->vmarker ? p->vmarker[i] : 0);
        *q++ = '\n';
        tb_end(t, q);
    }
    if (last) tb_printf(t, "# written by pcdm\n");
}

static void fmt_ele(const mesh_part *p, long long tot, long long base, int first, int last,
                    tbuf *t) {
    if (first) tb_printf(t, "%lld 3 %d\n", tot, p->trank ? 1 : 0);
    for (int64_t i = 0; i < p->ntris; i++) {
        char *q = tb_room(t, 128);
        q = fmt_int(q, base + i + 1);
        for (int k = 0; k < 3; k++) {
            *q++ = ' ';
            q = fmt_int(q, (long long)p->tri[3 * i + k] + 1);
        }
        if (p->trank) {
            *q++ = ' ';
            q = fmt_int(q, p->trank[i]);
        }
        *q++ = '\n';
        tb_end(t, q);
    }
    if (last) tb_printf(t, "# written by pcdm%s\n", p->trank ? " (attribute: owning rank)" : "");
}

static void fmt_poly(const mesh_part *p, long long tot, long long base, int first, int last,
                     tbuf *t) {
    if (first) tb_printf(t, "0 2 0 1\n%lld 1\n", tot);
    for (int64_t i = 0; i < p->nsegs; i++) {
        char *q = tb_room(t, 128);
        q = fmt_int(q, base + i + 1);
        for (int k = 0; k < 2; k++) {
            *q++ = ' ';
            q = fmt_int(q, (long long)p->seg[2 * i + k] + 1);
        }
        *q++ = ' ';
        q = fmt_int(q, p->smarker ? p->smarker[i] : 0);
        *q++ = '\n';
        tb_end(t, q);
    }
    if (last) tb_printf(t, "0\n");
}

int meshio_pwrite_triangle(MPI_Comm comm, const mesh_part *p, const char *prefix, char *err,
                           size_t errlen) {
    int rank, size;
    MESH_MPI(MPI_Comm_rank(comm, &rank));
    MESH_MPI(MPI_Comm_size(comm, &size));
    if (errlen) err[0] = '\0';
    long long tot[3], base[3];
    counts(comm, p, tot, base);
    static const char *const ext[3] = {"node", "ele", "poly"};
    int rc = 0;
    for (int f = 0; f < 3 && rc == 0; f++) {
        char path[PATH_MAX_LEN + 8];
        snprintf(path, sizeof path, "%s.%s", prefix, ext[f]);
        tbuf t = {0};
        int first = rank == 0, last = rank == size - 1;
        if (f == 0) fmt_node(p, tot[0], base[0], first, last, &t);
        if (f == 1) fmt_ele(p, tot[1], base[1], first, last, &t);
        if (f == 2) fmt_poly(p, tot[2], base[2], first, last, &t);
        rc = write_shared(comm, path, &t, err, errlen);
        free(t.b);
    }
    return rc;
}

/* ---- VTK XML pieces ------------------------------------------------------------------- */

static int little_endian(void) {
    const uint16_t one = 1;
    unsigned char c;
    memcpy(&c, &one, 1);
    return c == 1;
}

/* Writes one appended block: a UInt64 byte count, then the bytes. */
static void put_block(FILE *f, const void *data, uint64_t bytes) {
    fwrite(&bytes, sizeof bytes, 1, f);
    if (bytes) fwrite(data, 1, (size_t)bytes, f);
}

int meshio_write_vtu(const mesh_flat *m, int rank, int binary, const char *path, char *err,
                     size_t errlen) {
    wfile w;
    if (meshio_wopen(&w, path, err, errlen)) return -1;
    size_t nv = (size_t)m->nverts, nt = (size_t)m->ntris;
    double *pts = mesh_xmalloc(3 * nv + 1, sizeof *pts);
    int32_t *mark = mesh_xmalloc(nv + 1, sizeof *mark);
    int64_t *conn = mesh_xmalloc(3 * nt + 1, sizeof *conn);
    int64_t *offs = mesh_xmalloc(nt + 1, sizeof *offs);
    uint8_t *type = mesh_xmalloc(nt + 1, 1);
    int32_t *crank = mesh_xmalloc(nt + 1, sizeof *crank);
    for (size_t v = 0; v < nv; v++) {
        pts[3 * v] = ldexp(m->xy[2 * v], -m->scale_exp);
        pts[3 * v + 1] = ldexp(m->xy[2 * v + 1], -m->scale_exp);
        pts[3 * v + 2] = 0;
        mark[v] = m->vmarker ? m->vmarker[v] : 0;
    }
    for (size_t t = 0; t < nt; t++) {
        for (int k = 0; k < 3; k++)
            conn[3 * t + (size_t)k] = m->tri[3 * t + (size_t)k];
        offs[t] = 3 * (int64_t)(t + 1);
        type[t] = 5; /* VTK_TRIANGLE */
        crank[t] = m->trank ? m->trank[t] : rank;
    }
    /* name, VTK type, data, bytes, components */
    struct arr {
        const char *name, *type;
        const void *data;
        uint64_t bytes;
        int ncomp;
    } a[6] = {{"marker", "Int32", mark, 4 * nv, 1},   {"rank", "Int32", crank, 4 * nt, 1},
              {"Points", "Float64", pts, 24 * nv, 3}, {"connectivity", "Int64", conn, 24 * nt, 1},
              {"offsets", "Int64", offs, 8 * nt, 1},  {"types", "UInt8", type, nt, 1}};
    uint64_t off[6], o = 0;
    for (int i = 0; i < 6; i++) {
        off[i] = o;
        o += 8 + a[i].bytes;
    }
    FILE *f = w.f;
    fprintf(f,
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
            "byte_order=\"%s\" header_type=\"UInt64\">\n<UnstructuredGrid>\n"
            "<Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n",
            little_endian() ? "LittleEndian" : "BigEndian", nv, nt);
    static const char *const open_tag[6] = {"<PointData Scalars=\"marker\">\n",
                                            "<CellData Scalars=\"rank\">\n",
                                            "<Points>\n",
                                            "<Cells>\n",
                                            "",
                                            ""};
    static const char *const close_tag[6] = {
        "</PointData>\n", "</CellData>\n", "</Points>\n", "", "", "</Cells>\n"};
    for (int i = 0; i < 6; i++) {
        fputs(open_tag[i], f);
        fprintf(f, "<DataArray type=\"%s\"", a[i].type);
        if (i != 2) fprintf(f, " Name=\"%s\"", a[i].name);
        if (a[i].ncomp > 1) fprintf(f, " NumberOfComponents=\"%d\"", a[i].ncomp);
        if (binary) {
            fprintf(f, " format=\"appended\" offset=\"%llu\"/>\n", (unsigned long long)off[i]);
        } else {
            fprintf(f, " format=\"ascii\">\n");
            size_t n = (size_t)(a[i].bytes / (i == 5 ? 1 : (i == 0 || i == 1) ? 4 : 8));
            char line[48];
            for (size_t k = 0; k < n; k++) {
                char *q = line;
                if (i == 0 || i == 1) q = fmt_int(q, ((const int32_t *)a[i].data)[k]);
                if (i == 2) q = fmt_dbl(q, ((const double *)a[i].data)[k]);
                if (i == 3 || i == 4) q = fmt_int(q, ((const int64_t *)a[i].data)[k]);
                if (i == 5) q = fmt_int(q, ((const uint8_t *)a[i].data)[k]);
                *q++ = (k + 1) % 12 == 0 || k + 1 == n ? '\n' : ' ';
                fwrite(line, 1, (size_t)(q - line), f);
            }
            fputs("</DataArray>\n", f);
        }
        fputs(close_tag[i], f);
    }
    fputs("</Piece>\n</UnstructuredGrid>\n", f);
    if (binary) {
        fputs("<AppendedData encoding=\"raw\">\n_", f);
        for (int i = 0; i < 6; i++)
            put_block(f, a[i].data, a[i].bytes);
        fputs("\n</AppendedData>\n", f);
    }
    fputs("</VTKFile>\n", f);
    free(pts);
    free(mark);
    free(conn);
    free(offs);
    free(type);
    free(crank);
    return meshio_wclose(&w, 0);
}

int meshio_pwrite_pvtu(MPI_Comm comm, const mesh_flat *local, int binary, const char *prefix,
                       char *err, size_t errlen) {
    int rank, size;
    MESH_MPI(MPI_Comm_rank(comm, &rank));
    MESH_MPI(MPI_Comm_size(comm, &size));
    if (errlen) err[0] = '\0';
    char path[PATH_MAX_LEN + 32];
    int ok = strlen(prefix) < PATH_MAX_LEN;
    if (!ok) efmt(err, errlen, "%s: path too long", prefix);
    if (ok) {
        snprintf(path, sizeof path, "%s_%d.vtu", prefix, rank);
        ok = meshio_write_vtu(local, rank, binary, path, err, errlen) == 0;
    }
    if (agree(comm, ok, err, errlen)) return -1;
    if (rank == 0) {
        const char *slash = strrchr(prefix, '/');
        const char *base = slash ? slash + 1 : prefix;
        snprintf(path, sizeof path, "%s.pvtu", prefix);
        wfile w;
        ok = meshio_wopen(&w, path, err, errlen) == 0;
        if (ok) {
            fprintf(w.f,
                    "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" "
                    "byte_order=\"%s\" header_type=\"UInt64\">\n"
                    "<PUnstructuredGrid GhostLevel=\"0\">\n"
                    "<PPointData Scalars=\"marker\"><PDataArray type=\"Int32\" "
                    "Name=\"marker\"/></PPointData>\n"
                    "<PCellData Scalars=\"rank\"><PDataArray type=\"Int32\" "
                    "Name=\"rank\"/></PCellData>\n"
                    "<PPoints><PDataArray type=\"Float64\" NumberOfComponents=\"3\"/></PPoints>\n",
                    little_endian() ? "LittleEndian" : "BigEndian");
            for (int r = 0; r < size; r++)
                fprintf(w.f, "<Piece Source=\"%s_%d.vtu\"/>\n", base, r);
            fputs("</PUnstructuredGrid>\n</VTKFile>\n", w.f);
            ok = meshio_wclose(&w, 0) == 0;
        }
    }
    return agree(comm, ok, err, errlen);
}
