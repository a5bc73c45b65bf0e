/* text.c: sectioned text files written by one process (text.h): each section's head, records
 * and tail formatted into one line buffer and appended through a wfile (temporary name,
 * renamed on success).  The collective writer over MPI-IO is ptext.c.
 */
#include "io/text.h"

#include "base/base.h"
#include "io/wfile.h"

#include <stdio.h>
#include <stdlib.h>

long long meshio_text_len(ptrdiff_t n, size_t room) {
    if (n < 0 || (size_t)n > room)
        MESH_BUG("ptext: %lld bytes in a room of %zu", (long long)n, room);
    return (long long)n;
}

size_t meshio_text_room(const mesh_text_sec *s, int ns) {
    size_t room = 256;
    for (int k = 0; k < ns; k++) {
        if (s[k].headmax + 64 > room) room = s[k].headmax + 64;
        if (s[k].recmax + 64 > room) room = s[k].recmax + 64;
    }
    return room;
}

int meshio_write_sections(struct meshio_set *set, const char *path, const mesh_text_sec *s, int ns,
                          char *err, size_t errlen) {
    wfile w;
    if (meshio_wopen(&w, set, path, err, errlen)) return -1;
    char *line = mesh_xmalloc(meshio_text_room(s, ns), 1);
    for (int k = 0; k < ns; k++) {
        const mesh_text_sec *c = &s[k];
        if (c->head)
            fwrite(line, 1, (size_t)meshio_text_len(c->head(c->ctx, line) - line, c->headmax), w.f);
        for (int64_t i = 0; i < c->nrec; i++)
            fwrite(line, 1, (size_t)meshio_text_len(c->rec(c->ctx, i, line) - line, c->recmax),
                   w.f);
        if (c->tail)
            fwrite(line, 1, (size_t)meshio_text_len(c->tail(c->ctx, line) - line, c->headmax), w.f);
    }
    free(line);
    return meshio_wclose(&w, 0);
}
