/* oset: the files of one run as one unit -- they appear together or not at all (the programs'
 * ends: ./mesh's writers, the parallel writers of ./pcdm and ./pbw).
 *
 * Every writer puts its file under "PATH.tmpXXXXXX" (wfile.h, ptext.h).  Given a set, a writer
 * flushes the finished temporary file to the disk (fsync) and leaves it in the set instead of
 * renaming it; the set is then committed in three steps:
 *   1. the targets of the set's entry files are removed -- the .node of Triangle's files (the
 *      file a reader opens first) and the .pvtu index of VTK pieces;
 *   2. every other file is renamed over its target;
 *   3. the entry files are renamed last.
 * So at every moment -- a kill, a full disk, a failed rename -- the final names hold the
 * previous run's complete set, or no entry file (a reader finds no mesh), or this run's
 * complete set, never a mixture.  A failure before the commit removes every temporary file and
 * leaves the previous run's files as they were.  Files of a previous run that this run does not
 * write (a .edge when -e is not given) are left alone.
 *
 * While a set holds temporary files it is on a process-wide list, the one global of mesher/io:
 * SIGINT, SIGTERM and SIGHUP (whose handlers have no context to be passed) and a fatal exit
 * (out of memory, a bug report: mesh_on_fatal in base.h) remove them before the process ends.
 * Sets are used from one thread at a time; the list is changed with those signals blocked.
 */
#ifndef MESH_IO_OSET_H
#define MESH_IO_OSET_H

#include <stddef.h>

typedef struct meshio_set_file {
    char tmp[1100], path[1100];
    int done;  /* written whole and flushed: waiting for the commit */
    int entry; /* committed last (step 3) */
} meshio_set_file;

#define MESHIO_SET_RETIRED 24

typedef struct meshio_set {
    meshio_set_file *f;
    int n, cap;
    void *retired[MESHIO_SET_RETIRED]; /* arrays outgrown (freed with the set) */
    int nretired;
    struct meshio_set *next; /* the process-wide list */
} meshio_set;

/* Local.  An empty set, put on the process-wide list; installs the signal handlers the first
 * time (only where a signal still has its default action: a host's own handlers are kept). */
void meshio_set_init(meshio_set *s);

/* Local.  Records the temporary file tmp for path (the writers call it when they create tmp;
 * s may be NULL: no set).  Returns 0, or -1 with "path: problem" in err. */
int meshio_set_add(meshio_set *s, const char *tmp, const char *path, char *err, size_t errlen);

/* Local.  tmp is written whole and flushed: it waits for the commit. */
void meshio_set_done(meshio_set *s, const char *tmp);

/* Local.  Removes tmp (the writer failed) and forgets it. */
void meshio_set_drop(meshio_set *s, const char *tmp);

/* Local.  Step 1, 2 or 3 of the commit (above) for this process's files.  Returns 0, or -1
 * with "path: problem (cause)" in err; after a failure call meshio_set_free, which removes what
 * is left.  The parallel writers run the steps on every rank with an agreement between them
 * (ptext.h: meshio_pset_commit). */
int meshio_set_step(meshio_set *s, int step, char *err, size_t errlen);

/* Local.  The three steps.  Returns 0, or -1 with err. */
int meshio_set_commit(meshio_set *s, char *err, size_t errlen);

/* Local.  Removes every temporary file still in s, takes s off the list and frees it. */
void meshio_set_free(meshio_set *s);

/* Local.  Checks before any work that path's folder takes new files: creates and removes
 * "PATH.tmpXXXXXX".  Returns 0, or -1 with "path: cannot create files in its folder: cause" in
 * err. */
int meshio_probe(const char *path, char *err, size_t errlen);

#endif
