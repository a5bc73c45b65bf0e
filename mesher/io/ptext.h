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
int meshio_pwrite_sections(MPI_Comm comm, const char *path, const mesh_text_sec *s, int ns,
                           char *err, size_t errlen);

/* Local.  A writer (text.h) that writes every file collectively over *comm (borrowed: it must
 * outlive the writer) with meshio_pwrite_sections. */
mesh_text_out meshio_ptext_out(MPI_Comm *comm);

/* The two primitives every MPI-IO writer here shares (ptext.c, pwrite.c). */

/* Collective over comm.  0 when ok on every rank, else -1 everywhere with the lowest failing
 * rank's message in err. */
int meshio_pagree(MPI_Comm comm, int ok, char *err, size_t errlen);

/* Local.  Writes n bytes of b at byte off of fh (pieces of at most 1 GiB: MPI counts are int);
 * 0, or -1 with "path: write failed at byte N" in err. */
int meshio_pwrite_at(MPI_File fh, long long off, const char *b, size_t n, const char *path,
                     char *err, size_t errlen);

#endif
