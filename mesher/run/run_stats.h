/* run_stats: per-rank statistics as a table -- rows of key, value and the decimals to print,
 * reduced over the ranks (sum and maximum of every row), for --stats.  The rank lines print the
 * rows marked for them in the order they were first set; the summary lines look rows up by key
 * (run_stats_sum, run_stats_max).  Collective: run_stats_collect; the rest is Local.
 */
#ifndef RUN_STATS_H
#define RUN_STATS_H

#include <stdio.h>

#define RUN_STATS_MAX 64

typedef struct run_stats {
    int n;
    const char *key[RUN_STATS_MAX];
    int decimals[RUN_STATS_MAX];                  /* as printed in the rank lines */
    int in_rank[RUN_STATS_MAX];                   /* 1: printed in the rank lines */
    double v[RUN_STATS_MAX];                      /* this rank's value */
    double tot[RUN_STATS_MAX], mx[RUN_STATS_MAX]; /* rank 0, after run_stats_collect */
    double *all; /* rank 0: every rank's values, rank-major (NULL elsewhere) */
} run_stats;

/* Local.  Sets row key (a string literal) to v, adding it at the end the first time. */
void run_stats_set(run_stats *s, const char *key, int decimals, int in_rank, double v);

/* Local.  Row key's value on this rank (0 when absent). */
double run_stats_get(const run_stats *s, const char *key);

/* Collective.  When on, rank 0 gathers every rank's rows (s->all) and their sums and maxima.
 * Returns 1 on rank 0 when on (the lines may be printed), else 0. */
int run_stats_collect(run_stats *s, int on);

/* Local, rank 0 after run_stats_collect.  The sum and the maximum over the ranks of row key. */
double run_stats_sum(const run_stats *s, const char *key);
double run_stats_max(const run_stats *s, const char *key);

/* Local, rank 0 after run_stats_collect.  "rank R: key=value ..." per rank. */
void run_stats_rank_lines(const run_stats *s, int nranks, FILE *out);

/* Local.  Frees s->all. */
void run_stats_free(run_stats *s);

#endif
