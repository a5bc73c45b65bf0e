/* pslg_impl: what pslg.c and pslg_split.c share (not part of the public interface). */
#ifndef PSLG_IMPL_H
#define PSLG_IMPL_H

#include <stddef.h>
#include <stdint.h>

#include "geom/pslg.h"

/* Splits the conflicting segment pairs pairs[2k], pairs[2k+1] (k < npairs; crossing in their
 * interiors or overlapping collinearly, found by pslg_check_ex's exact tests) at their
 * intersection: an overlap at the endpoints of each that lie strictly inside the other, a
 * crossing at a new vertex (the intersection point rounded, or an existing new vertex on either
 * segment within a few ulps of it, so that segments through one point share it).  The pieces
 * replace the segments, keeping their markers and lines; new vertices get marker 0, the line
 * of the first segment and attributes interpolated linearly along it.  The caller normalises
 * again (new pieces may repeat each other; rounded points may make new crossings).  Returns 0,
 * or -1 with a message (out of memory). */
int pslg_split_pairs(pslg *g, const int32_t *pairs, int64_t npairs, char *err, size_t errlen);

/* Replaces g's segments by n pieces: seg (2 per piece), their markers smk and lines sln (each
 * may be NULL); g takes ownership of the three arrays and frees its old ones. */
void pslg_set_segments(pslg *g, int32_t *seg, int32_t *smk, int32_t *sln, int32_t n);

#endif
