/* run_stats.c: the --stats table (run_stats.h).  The values cross the ranks once, through
 * par_stats_collect (only these few numbers per rank; the mesh never moves). */
#include "run/run_stats.h"

#include "base/base.h"
#include "par/pout.h"

#include <stdlib.h>
#include <string.h>

static int find(const run_stats *s, const char *key) {
    for (int i = 0; i < s->n; i++)
        if (strcmp(s->key[i], key) == 0) return i;
    return -1;
}

void run_stats_set(run_stats *s, const char *key, int decimals, int in_rank, double v) {
    int i = find(s, key);
    if (i < 0) {
        if (s->n == RUN_STATS_MAX) MESH_BUG("more than %d statistics", RUN_STATS_MAX);
        i = s->n++;
        s->key[i] = key;
        s->decimals[i] = decimals;
        s->in_rank[i] = in_rank;
    }
    s->v[i] = v;
}

double run_stats_get(const run_stats *s, const char *key) {
    int i = find(s, key);
    return i < 0 ? 0 : s->v[i];
}

int run_stats_collect(run_stats *s, int on) {
    s->all = par_stats_collect(s->v, s->n, on, s->tot, s->mx);
    return s->all != NULL;
}

double run_stats_sum(const run_stats *s, const char *key) {
    int i = find(s, key);
    if (i < 0) MESH_BUG("no statistic %s", key);
    return s->tot[i];
}

double run_stats_max(const run_stats *s, const char *key) {
    int i = find(s, key);
    if (i < 0) MESH_BUG("no statistic %s", key);
    return s->mx[i];
}

void run_stats_rank_lines(const run_stats *s, int nranks, FILE *out) {
    for (int r = 0; r < nranks; r++) {
        const double *x = s->all + (size_t)r * s->n;
        fprintf(out, "rank %d:", r);
        for (int i = 0; i < s->n; i++)
            if (s->in_rank[i]) fprintf(out, " %s=%.*f", s->key[i], s->decimals[i], x[i]);
        fputc('\n', out);
    }
}

void run_stats_free(run_stats *s) {
    free(s->all);
    s->all = NULL;
}
