/* ptext.c: sectioned text files with MPI-IO (ptext.h; the one-process writer is text.c).
 *
 * Pass 1 formats every record of this rank into a scratch line to count its bytes
 * (the shortest round-trip coordinates have no cheaper length), per section; an MPI_Allreduce of
 * the section sizes and an MPI_Exscan of this rank's give its offset in each section: the
 * sections of all ranks before, then the lower ranks' bytes of this section.  Rank 0 creates
 * the temporary file (mkstemp) and names it to all; pass 2 formats the records again into a
 * 1 MiB chunk and writes each full chunk at its offset (independent MPI_File_write_at, so no
 * rank waits for another inside the loop), its disk write started at once (wfile.h).  Each rank
 * checks that pass 2 made exactly pass 1's bytes; after MPI_File_close the ranks agree, and rank 0
 * renames or removes the file. Invariant: every rank returns the same status.
 */
#include "io/ptext.h"

#include "base/base.h"
#include "base/base_mpi.h"
#include "io/oset.h"
#include "io/wfile.h"

#include <errno.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/statvfs.h>
#include <unistd.h>

#define PT_CHUNK ((size_t)1 << 20)

static int pt_put(void *ctx, struct meshio_set *set, const char *path, const mesh_text_sec *s,
                  int ns, char *err, size_t errlen) {
    return meshio_pwrite_sections(*(MPI_Comm *)ctx, set, path, s, ns, err, errlen);
}

mesh_text_out meshio_ptext_out(MPI_Comm *comm) {
    mesh_text_out o = {0, 1, pt_put, comm};
    MESH_MPI(MPI_Comm_rank(*comm, &o.rank));
    MESH_MPI(MPI_Comm_size(*comm, &o.size));
    return o;
}

int meshio_pagree(MPI_Comm comm, int ok, char *err, size_t errlen) {
    return mesh_agree(comm, !ok, errlen ? err : NULL, err, errlen) ? -1 : 0;
}

/* Why a write that MPI-IO reported as short stopped (Open MPI returns success with fewer bytes
 * on a full disk or past the file size limit): the file size limit, or the space left in the
 * file's file system; NULL when neither explains it. */
static const char *short_cause(const char *path, long long end) {
    struct rlimit rl;
    if (getrlimit(RLIMIT_FSIZE, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
        (unsigned long long)end > (unsigned long long)rl.rlim_cur)
        return "File too large (past the file size limit, ulimit -f)";
    struct statvfs fs;
    char dir[1100];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash)
        slash[1] = '\0';
    else
        snprintf(dir, sizeof dir, ".");
    if (statvfs(dir, &fs) == 0) {
        unsigned long long blocks = geteuid() == 0 ? fs.f_bfree : fs.f_bavail;
        if (blocks * fs.f_frsize < ((unsigned long long)1 << 20)) return "No space left on device";
    }
    return NULL;
}

int meshio_pwrite_at(MPI_File fh, int wb, long long off, const char *b, size_t n, const char *path,
                     char *err, size_t errlen) {
    size_t done = 0;
    while (done < n) {
        size_t piece = n - done < ((size_t)1 << 30) ? n - done : (size_t)1 << 30;
        MPI_Status st;
        int got = 0, rc = MPI_File_write_at(fh, (MPI_Offset)(off + (long long)done), b + done,
                                            (int)piece, MPI_BYTE, &st);
        if (rc == MPI_SUCCESS) MPI_Get_count(&st, MPI_BYTE, &got);
        if (rc != MPI_SUCCESS || got <= 0) { /* a short write is tried again for the rest */
            char why[MPI_MAX_ERROR_STRING];
            const char *cause = short_cause(path, off + (long long)n);
            if (rc == MPI_SUCCESS && !cause) cause = "no byte written, no error given";
            mesh_fail(err, errlen, "%s: write failed at byte %lld: %s", path, off + (long long)done,
                      cause ? cause : meshio_mpi_strerror(rc, why));
            return -1;
        }
        done += (size_t)got;
    }
    meshio_writeback(wb, off, (long long)n);
    return 0;
}

int meshio_pwrite_sections(MPI_Comm comm, struct meshio_set *set, const char *path,
                           const mesh_text_sec *s, int ns, char *err, size_t errlen) {
    int rank;
    MESH_MPI(MPI_Comm_rank(comm, &rank));
    if (errlen) err[0] = '\0';
    if (ns > MESH_TEXT_MAXSEC) MESH_BUG("ptext: %d sections", ns);
    size_t room = meshio_text_room(s, ns);
    char *line = mesh_xmalloc(room, 1);
    /* pass 1: this rank's bytes per section */
    long long mine[MESH_TEXT_MAXSEC] = {0}, tot[MESH_TEXT_MAXSEC] = {0},
              below[MESH_TEXT_MAXSEC] = {0};
    for (int k = 0; k < ns; k++) {
        const mesh_text_sec *c = &s[k];
        if (c->head) mine[k] += meshio_text_len(c->head(c->ctx, line) - line, c->headmax);
        for (int64_t i = 0; i < c->nrec; i++)
            mine[k] += meshio_text_len(c->rec(c->ctx, i, line) - line, c->recmax);
        if (c->tail) mine[k] += meshio_text_len(c->tail(c->ctx, line) - line, c->headmax);
    }
    mesh_mpi_settle(comm); /* the ranks that formatted fewer bytes wait asleep */
    MESH_MPI(MPI_Allreduce(mine, tot, ns, MPI_LONG_LONG, MPI_SUM, comm));
    MESH_MPI(MPI_Exscan(mine, below, ns, MPI_LONG_LONG, MPI_SUM, comm));
    if (rank == 0) memset(below, 0, sizeof below);
    /* the temporary file, created by rank 0 */
    char tmp[1100] = "";
    int ok = 1;
    if (rank == 0) {
        int fd = meshio_mktemp(path, tmp, sizeof tmp, err, errlen);
        if (fd < 0) {
            ok = 0;
        } else {
            close(fd);
            if (meshio_set_add(set, tmp, path, err, errlen) != 0) {
                ok = 0;
                unlink(tmp);
            }
        }
    }
    if (meshio_pagree(comm, ok, err, errlen)) {
        free(line);
        return -1;
    }
    MESH_MPI(MPI_Bcast(tmp, (int)sizeof tmp, MPI_CHAR, 0, comm));
    MPI_File fh;
    int orc = MPI_File_open(comm, tmp, MPI_MODE_WRONLY, MPI_INFO_NULL, &fh);
    if (orc != MPI_SUCCESS) {
        ok = 0;
        char why[MPI_MAX_ERROR_STRING];
        mesh_fail(err, errlen, "%s: cannot open for parallel writing: %s", path,
                  meshio_mpi_strerror(orc, why));
    }
    if (meshio_pagree(comm, ok, err, errlen)) {
        if (rank == 0) {
            unlink(tmp);
            meshio_set_drop(set, tmp);
        }
        free(line);
        return -1;
    }
    MESH_MPI(MPI_File_set_errhandler(fh, MPI_ERRORS_RETURN));
    int wb = meshio_writeback_open(tmp);
    /* pass 2: format again, chunk by chunk */
    char *buf = mesh_xmalloc(PT_CHUNK + room, 1);
    long long base = 0;
    for (int k = 0; k < ns && ok; k++) {
        const mesh_text_sec *c = &s[k];
        long long at = base + below[k], start = at;
        char *q = buf;
        if (c->head) q = c->head(c->ctx, q);
        for (int64_t i = 0; i <= c->nrec && ok; i++) {
            if (i < c->nrec) q = c->rec(c->ctx, i, q);
            if (i == c->nrec && c->tail) q = c->tail(c->ctx, q);
            if ((size_t)(q - buf) >= PT_CHUNK || i == c->nrec) {
                size_t n = (size_t)(q - buf);
                if (n && meshio_pwrite_at(fh, wb, at, buf, n, path, err, errlen) != 0) ok = 0;
                at += (long long)n;
                q = buf;
            }
        }
        if (ok && at - start != mine[k]) {
            ok = 0;
            mesh_fail(err, errlen, "%s: internal error: %lld bytes counted, %lld written", path,
                      mine[k], at - start);
        }
        base += tot[k];
    }
    free(buf);
    free(line);
    if (meshio_pclose(comm, &fh, ok, path, err, errlen) != 0) ok = 0;
    if (wb >= 0) close(wb);
    int all = meshio_pagree(comm, ok, err, errlen) == 0;
    ok = 1;
    if (rank == 0) {
        if (!all) {
            unlink(tmp);
            meshio_set_drop(set, tmp);
        } else if (set) {
            meshio_set_done(set, tmp);
        } else if (rename(tmp, path) != 0) {
            ok = 0;
            mesh_fail(err, errlen, "%s: cannot rename the written file: %s", path, strerror(errno));
            unlink(tmp);
        }
    }
    if (!all) return -1;
    return meshio_pagree(comm, ok, err, errlen);
}

const char *meshio_mpi_strerror(int rc, char *buf) {
    int len = 0;
    buf[0] = '\0';
    if (MPI_Error_string(rc, buf, &len) != MPI_SUCCESS || !buf[0])
        snprintf(buf, MPI_MAX_ERROR_STRING, "MPI error %d", rc);
    return buf;
}

int meshio_pclose(MPI_Comm comm, MPI_File *fh, int ok, const char *path, char *err, size_t errlen) {
    /* the ranks that wrote less wait asleep: MPI_File_sync's barrier spins */
    mesh_mpi_settle(comm);
    int rc = MPI_File_sync(*fh), bad = 0; /* collective: on every rank, whatever ok is */
    char why[MPI_MAX_ERROR_STRING];
    if (rc != MPI_SUCCESS && ok) {
        bad = 1;
        mesh_fail(err, errlen, "%s: writing to the disk failed: %s", path,
                  meshio_mpi_strerror(rc, why));
    }
    rc = MPI_File_close(fh);
    if (rc != MPI_SUCCESS && ok && !bad) {
        bad = 1;
        mesh_fail(err, errlen, "%s: closing failed: %s", path, meshio_mpi_strerror(rc, why));
    }
    return bad ? -1 : 0;
}

int meshio_pset_commit(MPI_Comm comm, meshio_set *s, char *err, size_t errlen) {
    for (int step = 1; step <= 3; step++)
        if (meshio_pagree(comm, meshio_set_step(s, step, err, errlen) == 0, err, errlen) != 0)
            return -1;
    return 0;
}
