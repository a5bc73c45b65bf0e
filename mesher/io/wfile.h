/* wfile: an output file that appears whole or not at all (internal to mesher/io).
 *
 * meshio_wopen creates "PATH.tmpXXXXXX" (mkstemp) in the destination folder with the usual
 * permissions and a 1 MiB stdio buffer; meshio_wclose flushes, checks every error (fclose
 * included), writes the file to the disk (fsync) and renames it over PATH -- or, with an output
 * set (oset.h), leaves it in the set for the set's commit -- or removes it when anything failed
 * (failed != 0 or a write error, whose cause, errno, the message names).  Both return 0, or -1
 * with "PATH: problem" in err.  Local.
 *
 * The disk write is started while the file is still being written (meshio_writeback every 8
 * MiB), so that the fsync before the rename finds little left to do: the formatting of what
 * follows and the disk overlap (measured: ./mesh's fsyncs of North America's 810 MB of Triangle
 * files 0.31 s, now 0.007 s).
 */
#ifndef MESH_IO_WFILE_H
#define MESH_IO_WFILE_H

#include <stddef.h>
#include <stdio.h>

struct meshio_set;

typedef struct wfile {
    FILE *f;
    int fd;                 /* the stream's descriptor (the stream writes through it) */
    long long at, hinted;   /* bytes written; of them, handed to meshio_writeback */
    struct meshio_set *set; /* NULL: renamed at close */
    char tmp[1100];
    const char *path;
    char *vbuf;
    char *err;
    size_t errlen;
} wfile;

/* Creates the empty file "PATH.tmpXXXXXX" (name in tmp) with the usual permissions; returns its
 * descriptor, or -1 with the message in err. */
int meshio_mktemp(const char *path, char *tmp, size_t tmplen, char *err, size_t errlen);

int meshio_wopen(wfile *w, struct meshio_set *set, const char *path, char *err, size_t errlen);
int meshio_wclose(wfile *w, int failed);

/* Local.  Starts the disk write of bytes [off, off + n) of the file open as fd, which were just
 * written, and returns at once (Linux's sync_file_range, SYNC_FILE_RANGE_WRITE; elsewhere
 * nothing): a hint, whose failures are ignored -- the fsync (MPI_File_sync) before the rename
 * reports any.  fd < 0: nothing. */
void meshio_writeback(int fd, long long off, long long n);

/* Local.  A descriptor of the file at path for meshio_writeback (the MPI-IO writers, whose own
 * descriptor is MPI's), or -1: then no hints.  Closed with close(). */
int meshio_writeback_open(const char *path);

#endif
