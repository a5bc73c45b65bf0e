/* rt_comm.c - the communication module: RSR transport over MPI point-to-point.
 *
 * Sending (TR-97-17 section 4, DMCS communication module over active messages): an RSR is a
 * record (rt_msg.c) appended to the open aggregation buffer of its destination.  A buffer is
 * sent with MPI_Isend when it is full, at the end of every scheduler iteration
 * (rt_comm_flush_all) and before the rank can count as passive, so no RSR is held longer
 * than one iteration.  With aggregation off every RSR is its own MPI message.  A record
 * larger than a buffer travels alone in a buffer of its own size.  Sent buffers wait in a
 * request array (MPI_Testsome) and return to a free pool.  Self-sends never touch MPI: they
 * are copied to a local FIFO and dispatched by the same code as remote ones.
 * Receiving: RT_NPOST persistent receives (ANY_SOURCE; MPI_Recv_init once, MPI_Start to
 * repost: no request is made and freed per message, which took the null RSR round trip from
 * 1.34-1.37x a raw MPI round trip to 1.25-1.28x) stay preposted into buffers of the largest
 * aggregation size of any rank, so a message lands without a probe; they are consumed in
 * posting order, which is MPI's matching order, so the order from each source is kept (a
 * consumed one is reposted at the next call, in the same order, off the path to the reply).
 * Control records (rt_send_ctl: the termination token, TERM and DEADLOCK, rt_term.c) share
 * the stream under handler ids above the table and are neither counted nor activity.  A
 * record too large for an aggregation buffer is announced by a small control record in the
 * ordinary stream and follows as its own message on RT_TAG_BIG, received (blocking, it is
 * already on its way) when the control record is unpacked.  Each record is checked against
 * the handler table (unknown id or bad length aborts naming rank, handler and source), then
 * dispatched: a non-threaded handler runs at once on the receive buffer, a
 * threaded one gets a copy queued to the worker pool, and with perturbation on every record
 * is copied into the holding pool first.  rt_complete does the bookkeeping when a handler
 * has finished (received count for termination, statistics, reply token).
 * With the network model on (rt_net.c) a received message is copied into its source's
 * holding queue instead and processed by the same code (rt_comm_process) when it is due.
 * Communication time (rt_stats.comm_s) is the time of flushes to MPI and of the polls that
 * received an RSR (or a message the network model held), from the first clock reading inside
 * them, handler bodies excluded; an empty poll reads no clock and adds nothing, nor do the
 * termination detector's control records.
 * All of this is main-thread only; it is the only code that calls point-to-point MPI.
 */
#include "rt_internal.h"

#include <string.h>

enum { RT_TAG_MSG = 17, RT_TAG_BIG = 18, RT_RECV_BURST = 64, RT_NPOST = 4 };

#define RT_BIG_ID 0xFFFFu /* handler id of the control record announcing a large message */

struct rt_sendbuf {
    rt_sendbuf *next_free;
    unsigned char *buf;
    size_t cap, used;
    int dest;
    bool pooled; /* standard size: back to the pool after the send completes */
};

/* Communication time (rt_stats.comm_s): stretches opened by comm_begin and closed by
 * comm_end, nested (a flush inside a send, a send inside a poll) and counted once, at the
 * outermost end, unless that end says the stretch was not communication (an empty poll).
 * A non-threaded handler run inside one pauses it (run_inline): its body is handler time. */
static inline void comm_begin(void) {
    if (rt_g.comm_depth++ == 0) rt_g.comm_t0 = rt_now();
}

/* A poll's stretch begins without a clock read: the first reading inside it (a handler's
 * start, a threaded dispatch, a held message's arrival) becomes its start (comm_resolve), so
 * the unpacking before the first handler is not counted but no rdtsc is added to the path
 * from a message to its handler. */
static inline void comm_begin_lazy(void) {
    if (rt_g.comm_depth++ == 0) rt_g.comm_lazy = true;
}

static inline void comm_resolve(double now) {
    if (rt_g.comm_lazy) {
        rt_g.comm_t0 = now;
        rt_g.comm_lazy = false;
    }
}

static inline void comm_end(bool count) {
    if (--rt_g.comm_depth == 0) {
        if (count) {
            rt_g.comm_t1 = rt_now();
            comm_resolve(rt_g.comm_t1);
            rt_g.st.comm_s += rt_g.comm_t1 - rt_g.comm_t0;
        }
        rt_g.comm_lazy = false;
    }
}

int rt_comm_init(void) {
    int p = rt_g.size;
    rt_g.agg = rt_xmalloc(sizeof *rt_g.agg * (size_t)p);
    rt_g.dirty = rt_xmalloc(sizeof *rt_g.dirty * (size_t)p);
    for (int i = 0; i < p; i++)
        rt_g.agg[i] = NULL;
    rt_g.ndirty = 0;
    rt_g.pool = NULL;
    rt_g.nreq = 0;
    rt_g.capreq = 0;
    rt_g.reqs = NULL;
    rt_g.reqbuf = NULL;
    rt_g.reqidx = NULL;
    rt_g.rcap = rt_g.cfg.agg_bytes;
    rt_g.rbuf = rt_xmalloc(rt_g.rcap);
    rt_queue_init(&rt_g.selfq);
    /* Preposted receives must hold the largest aggregate any rank may send. */
    unsigned long mine = rt_g.cfg.agg_bytes, most = 0;
    if (MPI_Allreduce(&mine, &most, 1, MPI_UNSIGNED_LONG, MPI_MAX, rt_g.comm) != MPI_SUCCESS)
        return RT_EMPI;
    rt_g.pcap = most;
    rt_g.pbuf = rt_xmalloc(sizeof *rt_g.pbuf * RT_NPOST);
    rt_g.preq = rt_xmalloc(sizeof *rt_g.preq * RT_NPOST);
    for (int i = 0; i < RT_NPOST; i++) {
        rt_g.pbuf[i] = rt_xmalloc(rt_g.pcap);
        RT_MPI(MPI_Recv_init(rt_g.pbuf[i], (int)rt_g.pcap, MPI_BYTE, MPI_ANY_SOURCE, RT_TAG_MSG,
                             rt_g.comm, &rt_g.preq[i]));
        RT_MPI(MPI_Start(&rt_g.preq[i]));
    }
    rt_g.phead = 0;
    rt_g.nrepost = 0;
    return RT_OK;
}

static void repost_pending(void);

static void sendbuf_free(rt_sendbuf *sb) {
    rt_xfree(sb->buf);
    rt_xfree(sb);
}

void rt_comm_destroy(void) {
    for (int i = 0; i < rt_g.size; i++)
        if (rt_g.agg[i]) sendbuf_free(rt_g.agg[i]);
    while (rt_g.pool) {
        rt_sendbuf *sb = rt_g.pool;
        rt_g.pool = sb->next_free;
        sendbuf_free(sb);
    }
    rt_qnode *n;
    while ((n = rt_queue_pop(&rt_g.selfq)))
        rt_xfree(RT_CONTAINER(n, rt_item, q));
    repost_pending(); /* every slot active again, then cancelled */
    for (int i = 0; i < RT_NPOST; i++) {
        RT_MPI(MPI_Cancel(&rt_g.preq[i]));
        RT_MPI(MPI_Wait(&rt_g.preq[i], MPI_STATUS_IGNORE));
        RT_MPI(MPI_Request_free(&rt_g.preq[i])); /* persistent: inactive now, freed */
        rt_xfree(rt_g.pbuf[i]);
    }
    rt_xfree(rt_g.pbuf);
    rt_xfree(rt_g.preq);
    rt_g.pbuf = NULL;
    rt_g.preq = NULL;
    rt_xfree(rt_g.agg);
    rt_xfree(rt_g.dirty);
    rt_xfree(rt_g.reqs);
    rt_xfree(rt_g.reqbuf);
    rt_xfree(rt_g.reqidx);
    rt_xfree(rt_g.rbuf);
    rt_g.agg = NULL;
    rt_g.dirty = NULL;
    rt_g.reqs = NULL;
    rt_g.reqbuf = NULL;
    rt_g.reqidx = NULL;
    rt_g.rbuf = NULL;
}

static rt_sendbuf *sendbuf_get(int dest, size_t need) {
    rt_sendbuf *sb;
    if (need <= rt_g.cfg.agg_bytes && rt_g.pool) {
        sb = rt_g.pool;
        rt_g.pool = sb->next_free;
    } else {
        sb = rt_xmalloc(sizeof *sb);
        sb->pooled = need <= rt_g.cfg.agg_bytes;
        sb->cap = sb->pooled ? rt_g.cfg.agg_bytes : need;
        sb->buf = rt_xmalloc(sb->cap);
    }
    sb->next_free = NULL;
    sb->used = 0;
    sb->dest = dest;
    return sb;
}

static void sendbuf_done(rt_sendbuf *sb) {
    if (sb->pooled) {
        sb->next_free = rt_g.pool;
        rt_g.pool = sb;
    } else {
        sendbuf_free(sb);
    }
}

/* Isend a filled buffer; it is recycled when the request completes. */
static void sendbuf_post(rt_sendbuf *sb, int tag) {
    if (rt_g.nreq == rt_g.capreq) {
        rt_g.capreq = rt_g.capreq ? 2 * rt_g.capreq : 16;
        rt_g.reqs = rt_xrealloc(rt_g.reqs, sizeof *rt_g.reqs * (size_t)rt_g.capreq);
        rt_g.reqbuf = rt_xrealloc(rt_g.reqbuf, sizeof *rt_g.reqbuf * (size_t)rt_g.capreq);
        rt_g.reqidx = rt_xrealloc(rt_g.reqidx, sizeof *rt_g.reqidx * (size_t)rt_g.capreq);
    }
    RT_CHECK(sb->used <= (size_t)0x7fffffff);
    RT_MPI(MPI_Isend(sb->buf, (int)sb->used, MPI_BYTE, sb->dest, tag, rt_g.comm,
                     &rt_g.reqs[rt_g.nreq]));
    rt_g.reqbuf[rt_g.nreq++] = sb;
    rt_wait_sent_to(sb->dest);
    rt_g.st.mpi_sent++;
    rt_g.st.mpi_bytes_sent += sb->used;
}

static void flush_dest(int dest) {
    rt_sendbuf *sb = rt_g.agg[dest];
    if (!sb) return;
    comm_begin();
    rt_g.agg[dest] = NULL;
    for (int i = 0; i < rt_g.ndirty; i++)
        if (rt_g.dirty[i] == dest) {
            rt_g.dirty[i] = rt_g.dirty[--rt_g.ndirty];
            break;
        }
    sendbuf_post(sb, RT_TAG_MSG);
    comm_end(true);
}

void rt_comm_flush_all(void) {
    if (rt_g.ndirty == 0) return;
    comm_begin();
    while (rt_g.ndirty > 0)
        flush_dest(rt_g.dirty[0]);
    comm_end(true);
}

void rt_comm_flush_all_at(double now) {
    if (rt_g.ndirty == 0) return;
    if (rt_g.comm_depth++ == 0) rt_g.comm_t0 = now;
    while (rt_g.ndirty > 0)
        flush_dest(rt_g.dirty[0]);
    comm_end(true);
}

bool rt_comm_flushed(void) {
    return rt_g.ndirty == 0 && rt_queue_empty(&rt_g.selfq);
}

static void test_sends(void) {
    if (rt_g.nreq == 0) return;
    int nd = 0;
    int *idx = rt_g.reqidx;
    RT_MPI(MPI_Testsome(rt_g.nreq, rt_g.reqs, &nd, idx, MPI_STATUSES_IGNORE));
    if (nd != MPI_UNDEFINED && nd > 0) {
        for (int i = 0; i < nd; i++) {
            sendbuf_done(rt_g.reqbuf[idx[i]]);
            rt_g.reqbuf[idx[i]] = NULL;
        }
        int k = 0;
        for (int i = 0; i < rt_g.nreq; i++)
            if (rt_g.reqbuf[i]) {
                rt_g.reqs[k] = rt_g.reqs[i];
                rt_g.reqbuf[k++] = rt_g.reqbuf[i];
            }
        rt_g.nreq = k;
    }
}

void rt_comm_wait_sends(void) {
    if (rt_g.nreq == 0) return; /* after termination: not communication time (done sends) */
    RT_MPI(MPI_Waitall(rt_g.nreq, rt_g.reqs, MPI_STATUSES_IGNORE));
    for (int i = 0; i < rt_g.nreq; i++)
        sendbuf_done(rt_g.reqbuf[i]);
    rt_g.nreq = 0;
}

/* Appends one record (that fits in a standard buffer) to to's open aggregation buffer. */
static void append_record(int to, const rt_hdr *h, const void *payload) {
    size_t need = rt_wire_size(h->len);
    rt_sendbuf *sb = rt_g.agg[to];
    if (sb && sb->cap - sb->used < need) {
        flush_dest(to);
        sb = NULL;
    }
    if (!sb) {
        sb = sendbuf_get(to, need);
        rt_g.agg[to] = sb;
        rt_g.dirty[rt_g.ndirty++] = to;
    }
    RT_CHECK(rt_pack(sb->buf, sb->cap, &sb->used, h, payload) == RT_OK);
}

void rt_send_hdr(int to, rt_hdr *h, const void *payload) {
    RT_CHECK(!rt_in_worker);
    rt_hentry *e = &rt_g.ht.e[h->handler];
    e->sent++;
    e->bytes_sent += h->len;
    rt_g.st.rsr_sent++;
    rt_g.st.rsr_bytes_sent += h->len;
    rt_g.sent++;
    rt_g.term.active = true;
    h->src = rt_g.rank;
    if (to == rt_g.rank) {
        e->sent_self++;
        rt_queue_push(&rt_g.selfq, &rt_item_new(h, payload)->q);
        return;
    }
    /* Appending a record (a copy of header and payload) stays in the caller's time; the
     * flushes (MPI_Isend) are communication time (flush_dest). */
    size_t need = rt_wire_size(h->len);
    if (need > rt_g.cfg.agg_bytes) {
        comm_begin();
        /* Announce it in the ordinary stream (keeps the order), then send it alone. */
        uint64_t n = need;
        rt_hdr c = {.handler = RT_BIG_ID, .src = rt_g.rank, .len = sizeof n, .tok_rank = -1};
        append_record(to, &c, &n);
        flush_dest(to);
        rt_sendbuf *big = sendbuf_get(to, need);
        RT_CHECK(rt_pack(big->buf, big->cap, &big->used, h, payload) == RT_OK);
        sendbuf_post(big, RT_TAG_BIG);
        comm_end(true);
        return;
    }
    append_record(to, h, payload);
    if (!rt_g.cfg.aggregate || rt_g.agg[to]->used == rt_g.agg[to]->cap) flush_dest(to);
}

void rt_send_ctl(int to, uint16_t id, const void *payload, uint32_t len) {
    RT_CHECK(!rt_in_worker && to != rt_g.rank && rt_wire_size(len) <= rt_g.cfg.agg_bytes);
    rt_hdr c = {.handler = id, .src = rt_g.rank, .len = len, .tok_rank = -1};
    comm_begin();
    append_record(to, &c, payload);
    flush_dest(to);
    comm_end(false); /* the termination detector's, not the application's */
}

/* A control record from src (rt_send_ctl): the termination token, TERM or DEADLOCK. */
static void control_record(const rt_hdr *h, const void *payload) {
    if (h->handler == RT_CTL_TOKEN && h->len == RT_TOK_N * sizeof(int64_t)) {
        int64_t tok[RT_TOK_N];
        memcpy(tok, payload, sizeof tok);
        rt_term_token(&rt_g.term, tok);
    } else if (h->handler == RT_CTL_TERM && h->len == 0 && h->src == 0 && rt_g.rank != 0) {
        rt_g.term.done = true;
    } else if (h->handler == RT_CTL_DEADLOCK && h->len == sizeof(int64_t) && h->src == 0 &&
               rt_g.rank != 0) {
        memcpy(&rt_g.term.deadlock_blocked, payload, sizeof(int64_t));
        rt_g.term.deadlock = true; /* reported by rt_run */
    } else {
        RT_FATAL("malformed control record %u (length %u) from rank %d", (unsigned)h->handler,
                 (unsigned)h->len, (int)h->src);
    }
}

void rt_complete(const rt_hdr *h, double elapsed) {
    rt_hentry *e = &rt_g.ht.e[h->handler];
    e->recv++;
    e->bytes_recv += h->len;
    e->time += elapsed;
    rt_g.st.rsr_recv++;
    rt_g.st.rsr_bytes_recv += h->len;
    rt_g.st.time[RT_TIME_HANDLER] += elapsed;
    rt_g.recvd++;
    rt_g.term.active = true;
    if (h->flags & RT_HF_REPLY) {
        rt_token tok = {h->tok_rank, h->tok_slot, h->tok_gen};
        rt_task *t = rt_tasks_lookup(&rt_g.tasks, tok);
        if (!t || tok.rank != rt_g.rank)
            RT_FATAL("reply from rank %d (handler '%s') names no waiting task (slot %u gen %u)",
                     (int)h->src, e->name, (unsigned)tok.slot, (unsigned)tok.gen);
        rt_tasks_reply(&rt_g.tasks, t);
    }
}

static void check_record(const rt_hdr *h, int mpi_src) {
    if (mpi_src >= 0 && h->src != mpi_src)
        RT_FATAL("record claims source %d but arrived from rank %d (handler %u)", (int)h->src,
                 mpi_src, (unsigned)h->handler);
    int rc = rt_htable_check(&rt_g.ht, h->handler, h->len);
    if (rc == RT_EHANDLER)
        RT_FATAL("message from rank %d names unknown handler id %u", (int)h->src,
                 (unsigned)h->handler);
    if (rc == RT_ELEN) {
        const rt_hentry *e = &rt_g.ht.e[h->handler];
        RT_FATAL("message from rank %d for handler %u '%s' has payload length %u, declared %s%u",
                 (int)h->src, (unsigned)h->handler, e->name, (unsigned)h->len,
                 (e->flags & RT_VARSIZE) ? "at most " : "", (unsigned)e->size);
    }
}

/* Runs a non-threaded handler on (h, payload) now. */
static void run_inline(const rt_hdr *h, const void *payload) {
    const rt_hentry *e = &rt_g.ht.e[h->handler];
    rt_msg m = {.src = h->src,
                .handler = h->handler,
                .data = payload,
                .len = h->len,
                .token = {h->tok_rank, h->tok_slot, h->tok_gen},
                .task = NULL};
    if (!(h->flags & (RT_HF_TOKEN | RT_HF_REPLY))) m.token.rank = -1;
    if (h->flags & RT_HF_REPLY) {
        m.task = rt_tasks_lookup(&rt_g.tasks, m.token);
        if (!m.task || m.token.rank != rt_g.rank)
            RT_FATAL("reply from rank %d (handler '%s') names no waiting task", (int)h->src,
                     e->name);
    }
    bool nested = rt_g.in_handler;
    rt_g.in_handler = true;
    double t0 = rt_now();
    /* pause the open communication stretch: the body is handler time, except its own sends */
    int depth = rt_g.comm_depth;
    comm_resolve(t0);
    if (depth) rt_g.st.comm_s += t0 - rt_g.comm_t0;
    rt_g.comm_depth = 0;
    double c0 = rt_g.st.comm_s;
    e->fn(&m, e->arg);
    double t1 = rt_now();
    double dt = t1 - t0 - (rt_g.st.comm_s - c0);
    rt_g.comm_depth = depth;
    rt_g.comm_t0 = t1;
    rt_g.inline_time += dt;
    rt_g.in_handler = nested;
    rt_complete(h, dt);
}

void rt_dispatch_item(rt_item *it) {
    if (rt_g.ht.e[it->h.handler].flags & RT_THREADED) {
        if (it->h.flags & RT_HF_REPLY)
            RT_FATAL("reply handler '%s' must be non-threaded", rt_g.ht.e[it->h.handler].name);
        rt_workers_submit(it);
        return;
    }
    run_inline(&it->h, it->data);
    rt_xfree(it);
}

/* A record just arrived (from MPI or the self FIFO). */
static void deliver(const rt_hdr *h, const void *payload, rt_item *owned) {
    rt_g.term.active = true;
    if (rt_g.perturbing) {
        rt_perturb_hold(&rt_g.pert, owned ? owned : rt_item_new(h, payload), h->src);
        return;
    }
    if (owned) {
        rt_dispatch_item(owned);
    } else if (rt_g.ht.e[h->handler].flags & RT_THREADED) {
        if (rt_g.comm_lazy) comm_resolve(rt_now());
        rt_dispatch_item(rt_item_new(h, payload));
    } else {
        run_inline(h, payload);
    }
}

bool rt_local_deliver(void) {
    if (rt_queue_empty(&rt_g.selfq)) return false;
    comm_begin();
    /* Only what is queued now: handlers may self-send more, which waits for the next round. */
    rt_queue q;
    rt_queue_init(&q);
    rt_queue_append(&q, &rt_g.selfq);
    rt_qnode *n;
    while ((n = rt_queue_pop(&q))) {
        rt_item *it = RT_CONTAINER(n, rt_item, q);
        deliver(&it->h, it->data, it);
    }
    comm_end(true);
    return true;
}

/* A control record announced a large message from src: receive and deliver it now. */
static void receive_big(int src, const void *payload) {
    uint64_t n;
    memcpy(&n, payload, sizeof n);
    if (n > (uint64_t)RT_MAX_PAYLOAD + 64)
        RT_FATAL("rank %d announces a message of %llu bytes", src, (unsigned long long)n);
    if (n > rt_g.rcap) {
        rt_xfree(rt_g.rbuf);
        rt_g.rcap = (size_t)n;
        rt_g.rbuf = rt_xmalloc(rt_g.rcap);
    }
    int got = 0;
    MPI_Status st;
    RT_MPI(MPI_Recv(rt_g.rbuf, (int)n, MPI_BYTE, src, RT_TAG_BIG, rt_g.comm, &st));
    RT_MPI(MPI_Get_count(&st, MPI_BYTE, &got));
    rt_g.st.mpi_recv++;
    rt_g.st.mpi_bytes_recv += (uint64_t)got;
    size_t off = 0;
    rt_hdr h;
    const unsigned char *p;
    if ((uint64_t)got != n || rt_unpack(rt_g.rbuf, (size_t)got, &off, &h, &p) != 1 ||
        off != (size_t)got)
        RT_FATAL("malformed large message of %d bytes from rank %d", got, src);
    check_record(&h, src);
    deliver(&h, p, NULL);
}

/* Reposts, in completion order, the receives consumed since the last call: they are the
 * nrepost slots before phead, so MPI's matching order stays phead, phead+1, ... */
static void repost_pending(void) {
    for (int i = rt_g.nrepost; i > 0; i--) {
        int k = (rt_g.phead - i + RT_NPOST) % RT_NPOST;
        RT_MPI(MPI_Start(&rt_g.preq[k])); /* a persistent receive (MPI_Recv_init) */
    }
    rt_g.nrepost = 0;
}

/* The records of one MPI message: control records, large-message announcements, RSRs;
 * *nrec gets the number of records. */
static bool process(const unsigned char *buf, size_t n, int src, int *nrec) {
    size_t off = 0;
    rt_hdr h;
    const unsigned char *payload;
    int rc;
    bool any = false;
    *nrec = 0;
    while ((rc = rt_unpack(buf, n, &off, &h, &payload)) == 1) {
        ++*nrec;
        if (h.handler == RT_BIG_ID && h.len == sizeof(uint64_t) && h.src == src) {
            if (rt_g.comm_lazy) comm_resolve(rt_now());
            receive_big(src, payload);
            any = true;
            continue;
        }
        if ((h.handler == RT_CTL_TOKEN || h.handler == RT_CTL_TERM ||
             h.handler == RT_CTL_DEADLOCK) &&
            h.src == src) {
            control_record(&h, payload);
            continue;
        }
        check_record(&h, src);
        deliver(&h, payload, NULL);
        any = true; /* an RSR: control records alone are not activity */
    }
    if (rc != 0) RT_FATAL("malformed message of %zu bytes from rank %d at offset %zu", n, src, off);
    return any;
}

bool rt_comm_process(const unsigned char *buf, size_t n, int src) {
    int nrec;
    return process(buf, n, src, &nrec);
}

bool rt_comm_progress(void) {
    /* timed from the first message found: an empty poll reads no clock */
    bool any = false, held = false, timing = false;
    if (rt_g.nrepost) repost_pending();
    if (rt_g.net.nheld) { /* the network model's messages, now due */
        comm_begin();
        timing = true;
        any = rt_net_release(&rt_g.net, rt_g.comm_t0);
    }
    for (int k = 0; k < RT_RECV_BURST; k++) {
        int flag = 0, n = 0;
        if (rt_g.nrepost == RT_NPOST) repost_pending(); /* phead's own receive is consumed */
        MPI_Status st;
        MPI_Request *req = &rt_g.preq[rt_g.phead];
        RT_MPI(MPI_Test(req, &flag, &st));
        if (!flag) break;
        if (!timing) {
            comm_begin_lazy();
            timing = true;
        }
        RT_MPI(MPI_Get_count(&st, MPI_BYTE, &n));
        /* Handlers run on this buffer; they may not poll, so it is not reposted meanwhile. */
        unsigned char *buf = rt_g.pbuf[rt_g.phead];
        rt_g.st.mpi_recv++;
        rt_g.st.mpi_bytes_recv += (uint64_t)n;
        int nrec = 0;      /* 1: a message of one record (light traffic) */
        if (rt_g.net.on) { /* held RSRs stay counted as in flight (sent, not received) */
            double now = rt_now();
            comm_resolve(now);
            rt_net_hold(&rt_g.net, buf, (size_t)n, st.MPI_SOURCE, now);
            held = true;
        } else {
            any |= process(buf, (size_t)n, st.MPI_SOURCE, &nrec);
        }
        /* Reposted later (repost_pending), off the path from this message to the reply. */
        rt_g.phead = (rt_g.phead + 1) % RT_NPOST;
        rt_g.nrepost++;
        /* The replies to the first message leave before the next test (which progresses
         * MPI): a lone request is answered at once; those of a burst are aggregated.  A
         * first message of one record (light traffic) ends the burst: the scheduler comes
         * straight back after one local-work step, which may be what answers it. */
        if (k == 0) {
            if (rt_g.ndirty) rt_comm_flush_all();
            if (nrec == 1) break;
        }
    }
    /* Replies the handlers just produced leave now (not after the rest of the scheduler
     * iteration); the sends are tested after the receive, the latency-critical test of an
     * empty poll, and while messages flow only when many are outstanding. */
    if (rt_g.ndirty) rt_comm_flush_all();
    if (rt_g.nreq && (!any || rt_g.nreq > 16)) test_sends();
    /* a poll that found nothing, or only the termination detector's records, is not
     * communication time */
    if (timing) comm_end(any || held);
    return any;
}
