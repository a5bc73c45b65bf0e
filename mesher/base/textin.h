/* textin: an input text file (.poly, .node, .ele, .area) loaded whole and walked line by line,
 * for the readers of every layer (geom/pslg_read.c, io/meshio.c's .ele, bounds/sizefield.c's
 * .area), so they all take the same files and refuse the same ones.
 *
 * Loading reads the file in chunks into one NUL-terminated buffer and refuses, with
 * "PATH:LINE: problem", a NUL byte (not a text file: /dev/zero, /dev/urandom and binary files
 * stop at their first chunk), UTF-16 text, a line of more than 64 KiB before the first count and
 * a first MiB without one (endless comments).  The first data line's first token is looked at as
 * soon as it is complete: when it cannot be a count (an optional sign and digits), loading stops
 * there (the rest is never read) and the reader's own parse refuses that line as it would in a
 * small file, so the same first line gets the same message whatever the file's size.  Accepted: a
 * UTF-8 byte-order mark (skipped), and LF, CRLF and CR-only (old Mac) line ends; a file whose first
 * line ends in a lone CR is a CR file (there CR, LF and CRLF each end a line), any other is read
 * exactly as an LF file (a CR before the LF, or anywhere else, is a blank like a tab).
 *
 * A data line: what is left of a line once a comment ('#' to the line's end) is cut, when that
 * holds more than blanks (" \t\r\v\f").  All functions here are Local.
 */
#ifndef MESH_BASE_TEXTIN_H
#define MESH_BASE_TEXTIN_H

#include <stddef.h>

typedef struct mesh_textin {
    char *buf;  /* the bytes loaded, NUL-terminated (free with mesh_textin_free) */
    char *end;  /* buf + the bytes loaded */
    char *next; /* the start of the next unread line; NULL after the last */
    long line;  /* the current line's number, 1-based (0 before the first; at the end of the
                   file, its last line) */
    int cr;     /* a CR file: a lone CR ends a line */
} mesh_textin;

/* Loads path into t.  Returns 0, or -1 with "PATH: cannot open: reason", "PATH: cannot read:
 * reason" or "PATH:LINE: problem" in err (t then holds nothing). */
int mesh_textin_load(mesh_textin *t, const char *path, char *err, size_t errlen);

/* The next data line, its comment cut and its leading blanks skipped, NUL-terminated in place;
 * NULL at the end of the file.  t->line is its line's number. */
char *mesh_textin_line(mesh_textin *t);

/* Bytes not yet walked: an upper bound for what the rest of the file can hold. */
size_t mesh_textin_left(const mesh_textin *t);

void mesh_textin_free(mesh_textin *t);

#endif
