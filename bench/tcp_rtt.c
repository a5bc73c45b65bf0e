/* tcp_rtt.c - round trip of a 1-byte message over a plain TCP connection, the floor under any
 * MPI transport on the same link (make bench-hosts sets it beside the runtime's null RSR and a
 * raw MPI round trip between two hosts).  One side serves (`tcp_rtt serve PORT`: accepts one
 * connection and echoes every byte until the peer closes), the other measures
 * (`tcp_rtt ping ADDR PORT`): TCP_NODELAY on both ends, blocking reads and writes, TRIALS
 * trials of ITERS round trips after WARM unmeasured ones; it prints the best and the median
 * trial in microseconds per round trip, last the machine-readable line
 *   tcp_rtt: best_us=X median_us=Y
 * No MPI; exit status 1 with a message on any socket error.
 */
#define _GNU_SOURCE
#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

enum { TRIALS = 9, ITERS = 2000, WARM = 200 };

static double now_s(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int die(const char *what) {
    fprintf(stderr, "tcp_rtt: %s: %s\n", what, strerror(errno));
    return 1;
}

static int nodelay(int fd) {
    int one = 1;
    return setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

/* one byte each way; 0 on success */
static int xfer(int fd, int send_first) {
    char c = 'x';
    if (send_first && write(fd, &c, 1) != 1) return -1;
    if (read(fd, &c, 1) != 1) return -1;
    if (!send_first && write(fd, &c, 1) != 1) return -1;
    return 0;
}

static int serve(int port) {
    int ls = socket(AF_INET, SOCK_STREAM, 0), one = 1;
    if (ls < 0) return die("socket");
    setsockopt(ls, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = htons((uint16_t)port)};
    a.sin_addr.s_addr = htonl(INADDR_ANY);
    if (bind(ls, (struct sockaddr *)&a, sizeof a) != 0) return die("bind");
    if (listen(ls, 1) != 0) return die("listen");
    printf("tcp_rtt: serving on port %d\n", port);
    fflush(stdout);
    int fd = accept(ls, NULL, NULL);
    if (fd < 0) return die("accept");
    nodelay(fd);
    while (xfer(fd, 0) == 0) {
    }
    close(fd);
    close(ls);
    return 0;
}

static int cmp_dbl(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int ping(const char *addr, int port) {
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = htons((uint16_t)port)};
    if (inet_pton(AF_INET, addr, &a.sin_addr) != 1) {
        fprintf(stderr, "tcp_rtt: '%s' is not an IPv4 address\n", addr);
        return 1;
    }
    int fd = -1;
    for (int tries = 0; tries < 100; tries++) { /* the server may still be starting */
        fd = socket(AF_INET, SOCK_STREAM, 0);
        if (fd < 0) return die("socket");
        if (connect(fd, (struct sockaddr *)&a, sizeof a) == 0) break;
        close(fd);
        fd = -1;
        struct timespec ts = {0, 50000000};
        nanosleep(&ts, NULL);
    }
    if (fd < 0) return die("connect");
    nodelay(fd);
    double t[TRIALS];
    for (int i = 0; i < WARM; i++)
        if (xfer(fd, 1) != 0) return die("warm-up");
    for (int k = 0; k < TRIALS; k++) {
        double t0 = now_s();
        for (int i = 0; i < ITERS; i++)
            if (xfer(fd, 1) != 0) return die("round trip");
        t[k] = 1e6 * (now_s() - t0) / ITERS;
    }
    close(fd);
    qsort(t, TRIALS, sizeof t[0], cmp_dbl);
    printf("tcp_rtt: best_us=%.2f median_us=%.2f\n", t[0], t[TRIALS / 2]);
    return 0;
}

int main(int argc, char **argv) {
    if (argc == 3 && strcmp(argv[1], "serve") == 0) return serve(atoi(argv[2]));
    if (argc == 4 && strcmp(argv[1], "ping") == 0) return ping(argv[2], atoi(argv[3]));
    fprintf(stderr, "usage: tcp_rtt serve PORT | tcp_rtt ping IPV4-ADDRESS PORT\n");
    return 2;
}
