/* ptext: a text file made of sections of records, written by one process or by every rank of a
 * communicator into one shared file (the writers of io/xwrite.c: .edge, .neigh, -o2 .node/.ele,
 * Gmsh .msh, quadratic VTK).
 *
 * A file is the concatenation of its sections in order; within a section, rank 0's text comes
 * first, then rank 1's, ...  Each rank's text of a section is its head (may be empty), its
 * records in order, its tail (may be empty); the callbacks decide per rank what the head and
 * tail hold (e.g. a file header on rank 0 only, a Gmsh block header on every rank).  The
 * callbacks are pure functions of (ctx, i): they are called twice per record in the parallel
 * writer (once to count the bytes, once to write them) and must give the same text both times.
 * Every file appears whole or not at all (temporary name, renamed after success).
 */
#ifndef MESH_IO_PTEXT_H
#define MESH_IO_PTEXT_H

#include <mpi.h>
#include <stddef.h>
#include <stdint.h>

typedef struct mesh_text_sec {
    int64_t nrec;                                /* this rank's records */
    char *(*head)(void *ctx, char *q);           /* NULL: none; at most headmax bytes */
    char *(*rec)(void *ctx, int64_t i, char *q); /* record i at q, returns the end */
    char *(*tail)(void *ctx, char *q);           /* NULL: none; at most headmax bytes */
    void *ctx;                                   /* borrowed */
    size_t headmax, recmax;                      /* room the callbacks may use */
} mesh_text_sec;

#define MESH_TEXT_MAXSEC 8

/* Local.  Writes the sections s[0 .. ns) (one process: every rank is this one) to path.
 * Returns 0, or -1 with "path: problem" in err. */
int meshio_write_sections(const char *path, const mesh_text_sec *s, int ns, char *err,
                          size_t errlen);

/* Collective over comm.  Every rank gives its part of the ns (same on every rank) sections;
 * one pass counts each rank's bytes, an MPI_Exscan and an MPI_Allreduce place them, and each
 * rank writes chunk after chunk at its offsets (MPI-IO, independent writes).  Returns 0, or -1
 * on every rank with the first failing rank's message in err. */
int meshio_pwrite_sections(MPI_Comm comm, const char *path, const mesh_text_sec *s, int ns,
                           char *err, size_t errlen);

/* The two primitives every MPI-IO writer here shares (ptext.c, pwrite.c). */

/* Collective over comm.  0 when ok on every rank, else -1 everywhere with the lowest failing
 * rank's message in err. */
int meshio_pagree(MPI_Comm comm, int ok, char *err, size_t errlen);

/* Local.  Writes n bytes of b at byte off of fh (pieces of at most 1 GiB: MPI counts are int);
 * 0, or -1 with "path: write failed at byte N" in err. */
int meshio_pwrite_at(MPI_File fh, long long off, const char *b, size_t n, const char *path,
                     char *err, size_t errlen);

#endif
