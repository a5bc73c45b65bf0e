/* rt_msg.c - the wire format of RSRs and the packing of several RSRs into one MPI message.
 *
 * An MPI message of the runtime is a sequence of records; a record is a fixed 24-byte
 * header (rt_hdr: handler id, flags, source rank, payload length, reply token) followed by
 * the payload, zero-padded to a multiple of 8 so that every header and payload in a receive
 * buffer is 8-byte aligned.  Aggregation (DMCS communication module, TR-97-17 section 4) is
 * just appending records to a per-destination buffer until it is full.  Unpacking validates
 * that each record lies inside the buffer; the handler id and length are checked by the
 * caller against the handler table.
 */
#include "rt_internal.h"

#include <string.h>

static size_t pad8(size_t n) {
    return (n + 7u) & ~(size_t)7u;
}

size_t rt_wire_size(uint32_t len) {
    return sizeof(rt_hdr) + pad8(len);
}

int rt_pack(unsigned char *buf, size_t cap, size_t *used, const rt_hdr *h, const void *payload) {
    size_t need = rt_wire_size(h->len);
    if (*used > cap || cap - *used < need) return RT_ENOSPC;
    unsigned char *p = buf + *used;
    memcpy(p, h, sizeof *h);
    if (h->len) memcpy(p + sizeof *h, payload, h->len);
    memset(p + sizeof *h + h->len, 0, need - sizeof *h - h->len);
    *used += need;
    return RT_OK;
}

int rt_unpack(const unsigned char *buf, size_t n, size_t *off, rt_hdr *h,
              const unsigned char **payload) {
    if (*off == n) return 0;
    if (*off > n || n - *off < sizeof *h) return RT_EPROTO;
    memcpy(h, buf + *off, sizeof *h);
    if (h->len > RT_MAX_PAYLOAD || n - *off - sizeof *h < pad8(h->len)) return RT_EPROTO;
    *payload = buf + *off + sizeof *h;
    *off += rt_wire_size(h->len);
    return 1;
}

rt_item *rt_item_new(const rt_hdr *h, const void *payload) {
    rt_item *it = rt_xmalloc(sizeof *it + (h->len ? h->len : 1));
    it->q.next = NULL;
    it->h = *h;
    it->release_at = 0;
    it->elapsed = 0;
    if (h->len) memcpy(it->data, payload, h->len);
    return it;
}
