/* oset.c: the files of one run committed as one unit, and their removal on SIGINT, SIGTERM,
 * SIGHUP and fatal exits (oset.h).
 *
 * The list of live sets is changed with the three signals blocked, so the handler never sees a
 * set half changed; the handler only calls unlink (async-signal-safe) on the names, then gives
 * the signal its default action back and raises it again, so the process ends as it would have
 * (the exit status a shell or mpirun reports is the signal's).
 */
#include "io/oset.h"

#include "base/base.h"

#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "io/meshio.h"
#include "io/wfile.h"

static meshio_set *live; /* the sets holding temporary files (oset.h: the one global) */
static const int sigs[3] = {SIGINT, SIGTERM, SIGHUP};

static void remove_all(void) {
    for (meshio_set *s = live; s; s = s->next)
        for (int i = 0; i < s->n; i++)
            if (s->f[i].tmp[0]) unlink(s->f[i].tmp);
}

static void on_signal(int sig) {
    remove_all();
    signal(sig, SIG_DFL);
    raise(sig);
}

static void block(sigset_t *old) {
    sigset_t b;
    sigemptyset(&b);
    for (int k = 0; k < 3; k++)
        sigaddset(&b, sigs[k]);
    pthread_sigmask(SIG_BLOCK, &b, old);
}

static void unblock(const sigset_t *old) {
    pthread_sigmask(SIG_SETMASK, old, NULL);
}

void meshio_set_init(meshio_set *s) {
    static int installed;
    memset(s, 0, sizeof *s);
    sigset_t old;
    block(&old);
    if (!installed) {
        installed = 1;
        for (int k = 0; k < 3; k++) {
            struct sigaction now;
            if (sigaction(sigs[k], NULL, &now) == 0 && now.sa_handler == SIG_DFL) {
                struct sigaction a;
                memset(&a, 0, sizeof a);
                a.sa_handler = on_signal;
                sigemptyset(&a.sa_mask);
                sigaction(sigs[k], &a, NULL);
            }
        }
        mesh_on_fatal(remove_all);
    }
    s->next = live;
    live = s;
    unblock(&old);
}

static int ends_with(const char *s, const char *t) {
    size_t n = strlen(s), m = strlen(t);
    return n >= m && !strcmp(s + n - m, t);
}

int meshio_set_add(meshio_set *s, const char *tmp, const char *path, char *err, size_t errlen) {
    if (!s) return 0;
    if (strlen(tmp) >= sizeof s->f[0].tmp || strlen(path) >= sizeof s->f[0].path)
        return mesh_fail(err, errlen, "%s: path too long", path);
    sigset_t old;
    block(&old);
    if (s->n == s->cap) {
        if (s->nretired == MESHIO_SET_RETIRED) MESH_BUG("too many files in one output set");
        int cap = s->cap ? 2 * s->cap : 8;
        meshio_set_file *f = mesh_xmalloc((size_t)cap, sizeof *f);
        if (s->n) memcpy(f, s->f, (size_t)s->n * sizeof *f);
        /* the old array is freed with the set: a handler running on another thread may still
         * read it */
        if (s->f) s->retired[s->nretired++] = s->f;
        s->f = f;
        s->cap = cap;
    }
    meshio_set_file *e = &s->f[s->n];
    snprintf(e->tmp, sizeof e->tmp, "%s", tmp);
    snprintf(e->path, sizeof e->path, "%s", path);
    e->done = 0;
    e->entry = ends_with(path, ".node") || ends_with(path, ".pvtu");
    s->n++;
    unblock(&old);
    return 0;
}

static meshio_set_file *find(meshio_set *s, const char *tmp) {
    for (int i = 0; s && i < s->n; i++)
        if (!strcmp(s->f[i].tmp, tmp)) return &s->f[i];
    return NULL;
}

void meshio_set_done(meshio_set *s, const char *tmp) {
    meshio_set_file *e = find(s, tmp);
    if (e) e->done = 1;
}

void meshio_set_drop(meshio_set *s, const char *tmp) {
    meshio_set_file *e = find(s, tmp);
    if (!e) return;
    unlink(e->tmp);
    sigset_t old;
    block(&old);
    e->tmp[0] = '\0';
    unblock(&old);
}

/* Test-only fault: PCDM_TEST_COMMIT_KILL=K sends the process a signal -- SIGKILL, as a crash
 * would, or PCDM_TEST_COMMIT_SIG's number -- before the commit's (K+1)-th removal or rename, so
 * tests/t_outset.sh reaches every point of it. */
static void test_kill_point(void) {
    static int count, at = -2, sig = SIGKILL;
    if (at == -2) {
        const char *e = getenv("PCDM_TEST_COMMIT_KILL"), *g = getenv("PCDM_TEST_COMMIT_SIG");
        at = e && *e ? atoi(e) : -1;
        if (g && *g) sig = atoi(g);
    }
    if (at >= 0 && count++ == at) raise(sig);
}

int meshio_set_step(meshio_set *s, int step, char *err, size_t errlen) {
    for (int i = 0; i < s->n; i++) {
        meshio_set_file *e = &s->f[i];
        if (!e->tmp[0]) continue;
        if (!e->done) return mesh_fail(err, errlen, "%s: not written whole", e->path);
        if (step == 1 && e->entry) {
            test_kill_point();
            if (unlink(e->path) != 0 && errno != ENOENT)
                return mesh_fail(err, errlen, "%s: cannot remove the previous file: %s", e->path,
                                 strerror(errno));
        }
        if ((step == 2 && !e->entry) || (step == 3 && e->entry)) {
            test_kill_point();
            if (rename(e->tmp, e->path) != 0)
                return mesh_fail(err, errlen, "%s: cannot rename the written file %s: %s", e->path,
                                 e->tmp, strerror(errno));
            sigset_t old;
            block(&old);
            e->tmp[0] = '\0';
            unblock(&old);
        }
    }
    return 0;
}

int meshio_set_commit(meshio_set *s, char *err, size_t errlen) {
    for (int step = 1; step <= 3; step++)
        if (meshio_set_step(s, step, err, errlen) != 0) return -1;
    return 0;
}

void meshio_set_free(meshio_set *s) {
    sigset_t old;
    block(&old);
    for (int i = 0; i < s->n; i++)
        if (s->f[i].tmp[0]) unlink(s->f[i].tmp);
    for (meshio_set **p = &live; *p; p = &(*p)->next)
        if (*p == s) {
            *p = s->next;
            break;
        }
    unblock(&old);
    free(s->f);
    for (int k = 0; k < s->nretired; k++)
        free(s->retired[k]);
    memset(s, 0, sizeof *s);
}

int meshio_probe(const char *path, char *err, size_t errlen) {
    char tmp[1100];
    if (strlen(path) + 12 > sizeof tmp) return mesh_fail(err, errlen, "%s: path too long", path);
    snprintf(tmp, sizeof tmp, "%s.tmpXXXXXX", path);
    int fd = mkstemp(tmp);
    if (fd < 0)
        return mesh_fail(err, errlen, "%s: cannot create files in its folder: %s", path,
                         strerror(errno));
    close(fd);
    unlink(tmp);
    return 0;
}
