/* wfile: an output file that appears whole or not at all (internal to mesher/io).
 *
 * meshio_wopen creates "PATH.tmpXXXXXX" (mkstemp) in the destination folder with the usual
 * permissions and a 1 MiB stdio buffer; meshio_wclose flushes, checks every error (fclose
 * included), writes the file to the disk (fsync) and renames it over PATH -- or, with an output
 * set (oset.h), leaves it in the set for the set's commit -- or removes it when anything failed
 * (failed != 0 or a write error, whose cause, errno, the message names).  Both return 0, or -1
 * with "PATH: problem" in err.  Local.
 */
#ifndef MESH_IO_WFILE_H
#define MESH_IO_WFILE_H

#include <stddef.h>
#include <stdio.h>

struct meshio_set;

typedef struct wfile {
    FILE *f;
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

#endif
