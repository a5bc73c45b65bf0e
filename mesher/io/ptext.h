/* ptext: sectioned text files (text.h) written by every rank of a communicator into one shared
 * file with MPI-IO (the parallel half of the derived outputs' writers, io/xwrite.c), and the
 * primitives every MPI-IO writer here shares.
 */
#ifndef MESH_IO_PTEXT_H
#define MESH_IO_PTEXT_H

#include <mpi.h>
#include <stddef.h>
#include <stdint.h>

#include "io/text.h"

/* Collective over comm.  Every rank gives its part of the ns (same on every rank) sections;
 * one pass counts each rank's bytes, an MPI_Exscan and an MPI_Allreduce place them, and each
 * rank writes chunk after chunk at its offsets (MPI-IO, independent writes).  Returns 0, or -1
 * on every rank with the first failing rank's message in err. */
struct meshio_set;
int meshio_pwrite_sections(MPI_Comm comm, struct meshio_set *set, const char *path,
                           const mesh_text_sec *s, int ns, char *err, size_t errlen);

/* Local.  A writer (text.h) that writes every file collectively over *comm (borrowed: it must
 * outlive the writer) with meshio_pwrite_sections. */
mesh_text_out meshio_ptext_out(MPI_Comm *comm);

/* The two primitives every MPI-IO writer here shares (ptext.c, pwrite.c). */

/* Collective over comm.  0 when ok on every rank, else -1 everywhere with the lowest failing
 * rank's message in err. */
int meshio_pagree(MPI_Comm comm, int ok, char *err, size_t errlen);

/* Local.  Writes n bytes of b at byte off of fh (pieces of at most 1 GiB: MPI counts are int)
 * and starts their disk write (meshio_writeback on wb, a descriptor of the same file from
 * meshio_writeback_open, or -1: none); 0, or -1 with "path: write failed at byte N" in err. */
int meshio_pwrite_at(MPI_File fh, int wb, long long off, const char *b, size_t n, const char *path,
                     char *err, size_t errlen);

/* Local.  MPI's message for error code rc into buf (MPI_MAX_ERROR_STRING bytes); returns buf. */
const char *meshio_mpi_strerror(int rc, char *buf);

/* Collective over comm, the file's communicator.  Writes *fh to the disk (MPI_File_sync) and
 * closes it, the ranks that arrive first waiting asleep (mesh_mpi_settle); ok: nothing failed
 * before on this rank (a failure here is then reported).  0, or -1 with "path: problem: MPI's
 * cause" in err. */
int meshio_pclose(MPI_Comm comm, MPI_File *fh, int ok, const char *path, char *err, size_t errlen);

/* Collective over comm.  Commits every rank's files of s (oset.h) step by step, all ranks
 * agreeing after each step (so no entry file is renamed before every other file is in place).
 * Returns 0, or -1 on every rank with the first failing rank's message in err; then call
 * meshio_set_free, which removes what is left. */
int meshio_pset_commit(MPI_Comm comm, struct meshio_set *s, char *err, size_t errlen);

#endif
