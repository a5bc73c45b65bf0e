/* pexchange: the all-to-all of fixed-size records over rt_app_comm() (pexchange.c). */
#ifndef CHECK_PEXCHANGE_H
#define CHECK_PEXCHANGE_H

#include <stddef.h>
#include <stdint.h>

/* Collective.  Sends record i of recs (n records of sz bytes) to rank dest[i] over
 * rt_app_comm(); returns the records this rank received (grouped by source rank, in rank order;
 * free with free()) and their number in *nout. */
void *par_exchange(const void *recs, size_t sz, const int *dest, int64_t n, int64_t *nout);

#endif
