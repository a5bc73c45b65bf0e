/* rt_handler.c - the handler table of the control module (TR-97-17 section 4, DMCS RSRs).
 *
 * Handlers are registered SPMD-style: the same names in the same order on every rank, so the
 * id of a handler (its registration index) means the same thing everywhere and can travel in
 * a message header.  Every slot starts out holding a fatal "unregistered handler" stub, and
 * rt_start compares the tables of all ranks slot by slot (rt_hsig_compare) so that a
 * mismatch is reported by name instead of running the wrong handler.  Each handler declares
 * its payload size (exact, or a maximum with RT_VARSIZE); a message violating it is a bug.
 */
#include "rt_internal.h"

#include <string.h>

void rt_handler_unregistered(const rt_msg *m, void *arg) {
    (void)arg;
    RT_FATAL("message from rank %d names unregistered handler %d", m->src, m->handler);
}

void rt_htable_init(rt_htable *t) {
    memset(t, 0, sizeof *t);
    for (int i = 0; i < RT_MAX_HANDLERS; i++) {
        t->e[i].fn = rt_handler_unregistered;
        strcpy(t->e[i].name, "(unregistered)");
    }
}

int rt_htable_add(rt_htable *t, const char *name, rt_handler_fn fn, void *arg, unsigned flags,
                  uint32_t size) {
    if (t->frozen) return RT_ESTATE;
    if (!name || !fn || (flags & ~(unsigned)(RT_THREADED | RT_VARSIZE)) || size > RT_MAX_PAYLOAD)
        return RT_EINVAL;
    size_t len = strlen(name);
    if (len == 0 || len >= RT_NAME_MAX) return RT_EINVAL;
    if (t->n >= RT_MAX_HANDLERS) return RT_ENOSPC;
    rt_hentry *e = &t->e[t->n];
    memset(e, 0, sizeof *e);
    memcpy(e->name, name, len + 1);
    e->fn = fn;
    e->arg = arg;
    e->flags = flags;
    e->size = size;
    e->registered = true;
    return t->n++;
}

int rt_htable_check(const rt_htable *t, uint32_t id, uint32_t len) {
    if (id >= RT_MAX_HANDLERS || !t->e[id].registered) return RT_EHANDLER;
    const rt_hentry *e = &t->e[id];
    if (e->flags & RT_VARSIZE) return len <= e->size ? RT_OK : RT_ELEN;
    return len == e->size ? RT_OK : RT_ELEN;
}

void rt_htable_sig(const rt_htable *t, rt_hsig out[RT_MAX_HANDLERS]) {
    memset(out, 0, sizeof(rt_hsig) * RT_MAX_HANDLERS);
    for (int i = 0; i < t->n; i++) {
        memcpy(out[i].name, t->e[i].name, RT_NAME_MAX);
        out[i].flags = t->e[i].flags;
        out[i].size = t->e[i].size;
    }
}

int rt_hsig_compare(const rt_hsig a[RT_MAX_HANDLERS], const rt_hsig b[RT_MAX_HANDLERS]) {
    for (int i = 0; i < RT_MAX_HANDLERS; i++) {
        if (strncmp(a[i].name, b[i].name, RT_NAME_MAX) != 0 || a[i].flags != b[i].flags ||
            a[i].size != b[i].size)
            return i;
    }
    return -1;
}
