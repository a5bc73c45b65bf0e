/* rt_net.c - the network model: messages held at the receiver until a slower network would
 * have delivered them (rt.h, "network model").
 *
 * With a latency L and a bandwidth B (rt_net_set, rt_config, env PCDM_NET), every MPI message
 * the transport receives from another rank is copied out of its preposted receive buffer into
 * the FIFO of its source with a delivery time: the link from that source carries one message
 * at a time, so the message occupies it for size/B from the later of its arrival and the end
 * of the previous message on the link, and is due L after that.  Due times therefore increase
 * along each source's FIFO, and the order from each source (MPI's non-overtaking rule, on
 * which the applications rely) is kept.  The main loop calls rt_net_release at every poll; it
 * hands the due heads to rt_comm_process, which unpacks and dispatches them as if they had
 * just arrived.  The sender is never delayed: the cost is paid at the receiver, where a real
 * network would have made it wait.  Held messages are received but not processed, so the rank
 * is not passive while it holds one and the termination detector (which also sees sent >
 * received) cannot end a run early.  Invariant: nheld = the sum of the FIFO lengths.
 */
#include "rt_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int rt_net_parse(const char *spec, double *latency_s, double *bytes_per_s) {
    if (!spec) return RT_EINVAL;
    if (strcmp(spec, "off") == 0 || strcmp(spec, "0") == 0 || strcmp(spec, "none") == 0) {
        *latency_s = 0;
        *bytes_per_s = 0;
        return RT_OK;
    }
    if (strcmp(spec, "sp2") == 0) { /* TR-97-17 section 4: DMCS on the IBM SP2 */
        *latency_s = 29e-6;
        *bytes_per_s = 33.6e6;
        return RT_OK;
    }
    char *end = NULL;
    double lat = strtod(spec, &end), mbps = 0;
    if (end == spec || !isfinite(lat) || lat < 0) return RT_EINVAL;
    if (*end == ',') {
        const char *b = end + 1;
        mbps = strtod(b, &end);
        if (end == b || !isfinite(mbps) || mbps < 0) return RT_EINVAL;
    }
    if (*end != '\0') return RT_EINVAL;
    *latency_s = lat * 1e-6;
    *bytes_per_s = mbps * 1e6;
    return RT_OK;
}

void rt_net_init(rt_net *n, int nsrc, double latency_s, double bytes_per_s) {
    memset(n, 0, sizeof *n);
    n->latency_s = latency_s;
    n->bytes_per_s = bytes_per_s;
    n->on = latency_s > 0 || bytes_per_s > 0;
    if (!n->on) return;
    n->nsrc = nsrc;
    n->held = rt_xmalloc(sizeof *n->held * (size_t)nsrc);
    n->link_end = rt_xmalloc(sizeof *n->link_end * (size_t)nsrc);
    for (int i = 0; i < nsrc; i++) {
        rt_queue_init(&n->held[i]);
        n->link_end[i] = 0;
    }
}

void rt_net_destroy(rt_net *n) {
    if (n->held) {
        for (int i = 0; i < n->nsrc; i++) {
            rt_qnode *q;
            while ((q = rt_queue_pop(&n->held[i])))
                rt_xfree(RT_CONTAINER(q, rt_netmsg, q));
        }
    }
    rt_xfree(n->held);
    rt_xfree(n->link_end);
    memset(n, 0, sizeof *n);
}

void rt_net_hold(rt_net *n, const unsigned char *buf, size_t len, int src, double now) {
    RT_CHECK(n->on && src >= 0 && src < n->nsrc);
    rt_netmsg *m = rt_xmalloc(sizeof *m + (len ? len : 1));
    memcpy(m->data, buf, len);
    m->n = len;
    m->src = src;
    double start = now > n->link_end[src] ? now : n->link_end[src];
    double xfer = n->bytes_per_s > 0 ? (double)len / n->bytes_per_s : 0;
    n->link_end[src] = start + xfer;
    m->due = start + xfer + n->latency_s;
    rt_queue_push(&n->held[src], &m->q);
    n->nheld++;
    n->delayed++;
}

bool rt_net_release(rt_net *n, double now) {
    bool any = false;
    for (int s = 0; s < n->nsrc && n->nheld > 0; s++) {
        rt_queue *q = &n->held[s];
        while (q->head && RT_CONTAINER(q->head, rt_netmsg, q)->due <= now) {
            rt_netmsg *m = RT_CONTAINER(rt_queue_pop(q), rt_netmsg, q);
            n->nheld--;
            any |= rt_comm_process(m->data, m->n, m->src);
            rt_xfree(m);
        }
    }
    return any;
}

double rt_net_wait(const rt_net *n, double now) {
    double best = INFINITY;
    for (int s = 0; s < n->nsrc; s++)
        if (n->held[s].head) {
            double d = RT_CONTAINER(n->held[s].head, rt_netmsg, q)->due;
            if (d < best) best = d;
        }
    return best <= now ? 0 : best - now;
}
