/* rt_wait.c - the idle main thread waits in the kernel for the transport's sockets.
 *
 * When a rank has nothing to do, the scheduler (rt.c) sleeps with a growing backoff and polls
 * MPI again.  Between hosts that costs latency twice: a message that arrives during a sleep
 * waits for its end, and a rank woken by a timer on a busy machine waits again for the CPU.
 * Measured between two network namespaces over veth (make bench-hosts, a machine under load):
 * raw TCP 15-50 us round trip, the runtime's null RSR 130-200 us with the timed sleep, and a
 * busy-polling MPI_Recv several ms (a spinning rank gets the CPU only for its share of time
 * slices; a rank sleeping in the kernel is woken by the packet and preempts).  So when Open MPI
 * reaches other ranks through TCP sockets (the TCP BTL), the idle wait is a ppoll(2) on those
 * sockets (connected AF_INET/AF_INET6 stream sockets of this process, found in /proc/self/fd
 * and looked up again every RESCAN_S) and on an eventfd that worker threads write when they
 * hand work to the main thread: an arriving message wakes the rank at once, like a blocking
 * read.  ppoll only watches; Open MPI reads the sockets when the scheduler next calls MPI (its
 * event loop; after a wake-up that finds nothing the scheduler polls MPI SPIN_AFTER_WAKE times
 * before it waits again, as Open MPI may run that loop on only one progress call in eight).
 *
 * The timeout.  With the backoff (2 us to 1 ms) as timeout, most waits arm a timer that
 * expires before the kernel's next tick, so entering the wait reprograms the CPU's timer and
 * leaving it early (the message came first) reprograms it back; in a virtual machine each is
 * a trap to the hypervisor.  Measured with two processes on one core over veth, 1-byte round
 * trip, median of 3 runs' median trials: ppoll on the socket then read, 27.6 us with a 1 ms
 * timeout, 18.2 us with 10 ms, 18.3 us with 1 ms and 4 ms of timer slack; a blocking read
 * 16.1 us.  In the null RSR the step from one rank entering its wait to the other leaving
 * its own took 10 us with the backoff, 3.4 us with the lazy timer.  So when every message
 * arrives on a socket -- Open MPI's ob1 layer over the tcp and self transports only, asked
 * for with mpirun --mca pml ob1 --mca btl tcp,self (sockets_only) -- and no send of ours
 * waits for room on a socket, the timeout is only a safety net: the caller's long_ns (1 ms,
 * or the rest of rank 0's wave delay) with RT_WAIT_SLACK_NS of timer slack, so the kernel
 * fires it with its tick instead of a timer of its own.  Otherwise (shared memory between the
 * ranks of a host, InfiniBand: messages that wake no socket) the backoff stays the timeout.
 * RT_WAIT_LAZY=0 keeps the backoff in every case.
 *
 * Used when the job spans hosts (Open MPI's OMPI_COMM_WORLD_LOCAL_SIZE below
 * OMPI_COMM_WORLD_SIZE) or when RT_SOCKET_WAIT=1; RT_SOCKET_WAIT=0 turns it off.  Without
 * sockets (shared memory on one host) the timed condition-variable wait of rt_worker.c stays.
 * Invariants: the main thread never sleeps past its backoff, or past long_ns plus the slack
 * in the long wait (and the slack is the thread's own again outside that ppoll); a worker's
 * hand-over is never missed (the main thread announces main_polling before it checks
 * wposted, a worker bumps wposted before it checks main_polling, both sequentially
 * consistent, so one of them sees the other); a socket that stays readable while MPI finds
 * nothing (data for another layer, or a closed peer) cannot make the rank spin: after
 * MAX_IDLE_WAKES such wake-ups in a row the sockets are ignored until the next rescan.
 */
#define _GNU_SOURCE /* ppoll */
#include "rt_internal.h"

#include <dirent.h>
#include <errno.h>
#include <poll.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/eventfd.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define RESCAN_S 0.01     /* seconds between two lookups of the socket set */
#define MAX_IDLE_WAKES 64 /* socket wake-ups in a row with nothing received */
/* Open MPI reads its sockets in the event loop that opal_progress runs on every 8th call:
 * after a wake-up the scheduler polls MPI this many times without waiting. */
#define SPIN_AFTER_WAKE 16
/* timer slack of the long wait (see above): at least one scheduler tick (4 ms at HZ=250) */
#define RT_WAIT_SLACK_NS 4000000ul

static bool wanted(void) {
    const char *e = getenv("RT_SOCKET_WAIT");
    if (e && *e) return *e == '1';
    const char *n = getenv("OMPI_COMM_WORLD_SIZE"), *l = getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
    return n && l && atoi(l) < atoi(n);
}

/* Every peer is reached through TCP sockets: Open MPI's ob1 layer asked for (mpirun --mca pml
 * ob1 sets OMPI_MCA_pml) with the transports listed (--mca btl) and all of them tcp or self.
 * Then every message from another rank makes a socket readable; otherwise (shared memory
 * between the ranks of a host, InfiniBand, a layer Open MPI chose) some arrive unseen. */
static bool sockets_only(void) {
    const char *lazy = getenv("RT_WAIT_LAZY");
    if (lazy && *lazy == '0') return false;
    const char *pml = getenv("OMPI_MCA_pml"), *btl = getenv("OMPI_MCA_btl");
    if (!pml || strcmp(pml, "ob1") != 0 || !btl || !*btl) return false;
    for (const char *b = btl; *b;) {
        size_t n = strcspn(b, ",");
        if (!((n == 3 && strncmp(b, "tcp", 3) == 0) || (n == 4 && strncmp(b, "self", 4) == 0)))
            return false;
        b += n;
        if (*b == ',') b++;
    }
    return true;
}

void rt_wait_init(void) {
    rt_g.wt.on = wanted();
    rt_g.wt.only = rt_g.wt.on && sockets_only();
    int slack = prctl(PR_GET_TIMERSLACK, 0, 0, 0, 0);
    rt_g.wt.slack0 = slack > 0 ? (unsigned long)slack : 0; /* 0: the thread's default */
    rt_g.wt.wake_fd = -1;
    rt_g.wt.talked = NULL;
    if (rt_g.wt.on) {
        rt_g.wt.talked = rt_xmalloc((size_t)rt_g.size);
        memset(rt_g.wt.talked, 0, (size_t)rt_g.size);
    }
    rt_g.wt.nsock = 0;
    rt_g.wt.scanned = -1;
    rt_g.wt.idle_wakes = 0;
    rt_g.wt.spin = 0;
    atomic_store(&rt_g.wt.polling, 0);
    if (rt_g.wt.on && rt_g.nthreads > 0) {
        rt_g.wt.wake_fd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
        if (rt_g.wt.wake_fd < 0) rt_g.wt.on = false; /* keep the condition-variable wait */
    }
}

void rt_wait_sent_to(int dest) {
    if (!rt_g.wt.talked || rt_g.wt.talked[dest]) return;
    rt_g.wt.talked[dest] = 1;
    rt_g.wt.scanned = -1; /* Open MPI opens its connection to dest on the first send */
}

void rt_wait_fini(void) {
    rt_xfree(rt_g.wt.talked);
    rt_g.wt.talked = NULL;
    if (rt_g.wt.wake_fd >= 0) close(rt_g.wt.wake_fd);
    rt_g.wt.wake_fd = -1;
    rt_g.wt.on = false;
}

void rt_wait_wake(void) {
    if (atomic_load(&rt_g.wt.polling) && rt_g.wt.wake_fd >= 0) {
        uint64_t one = 1;
        ssize_t w = write(rt_g.wt.wake_fd, &one, sizeof one);
        (void)w; /* EAGAIN: the counter is already nonzero, the main thread wakes anyway */
    }
}

/* TCP sockets of this process: the connected ones are what Open MPI's TCP transport reads, a
 * listening one becomes readable when a peer connects (its first message to this rank). */
static void scan(void) {
    rt_g.wt.nsock = 0;
    rt_g.wt.idle_wakes = 0;
    DIR *d = opendir("/proc/self/fd");
    if (!d) return;
    int self = dirfd(d);
    struct dirent *de;
    while ((de = readdir(d)) && rt_g.wt.nsock < RT_WAIT_MAXSOCK) {
        char *end;
        long fd = strtol(de->d_name, &end, 10);
        if (*end || end == de->d_name || fd == self || fd == rt_g.wt.wake_fd) continue;
        struct stat st;
        if (fstat((int)fd, &st) != 0 || !S_ISSOCK(st.st_mode)) continue;
        int type = 0, listening = 0;
        socklen_t len = sizeof type;
        if (getsockopt((int)fd, SOL_SOCKET, SO_TYPE, &type, &len) != 0 || type != SOCK_STREAM)
            continue;
        len = sizeof listening;
        if (getsockopt((int)fd, SOL_SOCKET, SO_ACCEPTCONN, &listening, &len) != 0) continue;
        struct sockaddr_storage a;
        len = sizeof a;
        if (getsockname((int)fd, (struct sockaddr *)&a, &len) != 0 ||
            (a.ss_family != AF_INET && a.ss_family != AF_INET6))
            continue;
        rt_g.wt.listening[rt_g.wt.nsock] = listening != 0;
        rt_g.wt.sock[rt_g.wt.nsock++] = (int)fd;
    }
    closedir(d);
}

bool rt_wait_sockets(uint64_t ns, uint64_t long_ns) {
    if (!rt_g.wt.on) return false;
    double now = rt_wtime();
    if (rt_g.wt.scanned < 0 || now - rt_g.wt.scanned > RESCAN_S) {
        scan();
        rt_g.wt.scanned = now;
    }
    if (rt_g.wt.nsock == 0 || rt_g.wt.idle_wakes >= MAX_IDLE_WAKES) return false;
    if (rt_g.recvd != rt_g.wt.recvd_seen) {
        rt_g.wt.idle_wakes = 0;
        rt_g.wt.spin = 0;
    }
    rt_g.wt.recvd_seen = rt_g.recvd;
    if (rt_g.wt.spin > 0) { /* data arrived: poll MPI again at once until it is read */
        rt_g.wt.spin--;
        return true;
    }
    /* Only time can bring what the sockets do not announce: with every message on them and
     * no send of ours waiting for room on one (it would need POLLOUT), wait longer. */
    bool lazy = rt_g.wt.only && rt_g.nreq == 0 && long_ns > ns;
    if (lazy) ns = long_ns;
    struct pollfd p[RT_WAIT_MAXSOCK + 1];
    int n = 0;
    for (int i = 0; i < rt_g.wt.nsock; i++)
        p[n++] = (struct pollfd){.fd = rt_g.wt.sock[i], .events = POLLIN};
    if (rt_g.wt.wake_fd >= 0) p[n++] = (struct pollfd){.fd = rt_g.wt.wake_fd, .events = POLLIN};
    struct timespec ts = {(time_t)(ns / 1000000000u), (long)(ns % 1000000000u)};
    atomic_store(&rt_g.wt.polling, 1);
    int r = 0;
    if (atomic_load(&rt_g.wposted) == 0) {
        if (lazy) prctl(PR_SET_TIMERSLACK, RT_WAIT_SLACK_NS);
        r = ppoll(p, (nfds_t)n, &ts, NULL);
        if (lazy) prctl(PR_SET_TIMERSLACK, rt_g.wt.slack0);
    }
    atomic_store(&rt_g.wt.polling, 0);
    if (rt_g.wt.wake_fd >= 0 && (p[n - 1].revents & POLLIN)) {
        uint64_t v;
        ssize_t rd = read(rt_g.wt.wake_fd, &v, sizeof v);
        (void)rd;
    }
    if (r > 0) {
        rt_g.wt.idle_wakes++;
        rt_g.wt.spin = SPIN_AFTER_WAKE;
        for (int i = 0; i < rt_g.wt.nsock; i++)
            if (rt_g.wt.listening[i] && p[i].revents)
                rt_g.wt.scanned = -1; /* a new connection: watch it from the next wait on */
    }
    if (r < 0 && errno != EINTR) rt_g.wt.on = false; /* fall back for good */
    return true;
}
