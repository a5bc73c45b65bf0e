/* text: a text file made of sections of records, and the writer interface the derived outputs
 * (io/xwrite.c: .edge, .neigh, -o2 .node/.ele, Gmsh .msh, quadratic VTK) write through -- one
 * process here (meshio_write_sections), every rank of a communicator into one shared file in
 * ptext.h (MPI-IO).  This half needs no MPI: the sequential library is built from it alone.
 *
 * A file is the concatenation of its sections in order; within a section, rank 0's text comes
 * first, then rank 1's, ...  Each rank's text of a section is its head (may be empty), its
 * records in order, its tail (may be empty); the callbacks decide per rank what the head and
 * tail hold (e.g. a file header on rank 0 only, a Gmsh block header on every rank).  The
 * callbacks are pure functions of (ctx, i): they are called twice per record in the parallel
 * writer (once to count the bytes, once to write them) and must give the same text both times.
 * Every file appears whole or not at all (temporary name, renamed after success).
 */
#ifndef MESH_IO_TEXT_H
#define MESH_IO_TEXT_H

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
struct meshio_set;
int meshio_write_sections(struct meshio_set *set, const char *path, const mesh_text_sec *s, int ns,
                          char *err, size_t errlen);

/* Where sectioned files go: this process's rank among size writers and the function that
 * writes one file's sections (Collective over the writers when size > 1: ptext.h's
 * meshio_ptext_out; every writer returns the same status).  A NULL mesh_text_out means one
 * process and meshio_write_sections. */
typedef struct mesh_text_out {
    int rank, size;
    int (*put)(void *ctx, struct meshio_set *set, const char *path, const mesh_text_sec *s, int ns,
               char *err, size_t errlen);
    void *ctx; /* borrowed */
} mesh_text_out;

/* Local.  The longest line the callbacks of s[0 .. ns) may write, with a margin. */
size_t meshio_text_room(const mesh_text_sec *s, int ns);

/* Local.  n, the bytes a callback wrote, after checking that it kept within its room (a bug
 * otherwise). */
long long meshio_text_len(ptrdiff_t n, size_t room);

#endif
