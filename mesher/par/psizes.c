/* psizes: the size rules of ./pcdm and ./pbw (-r's .area, --size) loaded on every rank.
 *
 * Every rank reads the same files (as it reads the input), so every rank holds the same rule
 * and size_field_unsuitable answers alike everywhere; a failure on any rank fails all of them
 * through par_fail_any, the first failing rank's message printed by rank 0.
 */
#include "par/par.h"

#include "rt.h"

#include <stdio.h>
#include <string.h>

int par_load_sizes(par_opts *o, const pslg *in, size_field *S) {
    char err[1024], msg[1200];
    const char *old = o->refine && o->region_area ? o->input : NULL;
    int rc = size_field_load(S, old, o->size_field, in->scale_exp, err, sizeof err);
    snprintf(msg, sizeof msg, "%s: %s", o->prog ? o->prog : "mesh", err);
    if (par_fail_any(rc != 0, msg)) {
        if (rc == 0) size_field_free(S);
        return -1;
    }
    o->unsuitable = S->active ? size_field_unsuitable : NULL;
    o->unsuitable_ctx = S->active ? S : NULL;
    return 0;
}
