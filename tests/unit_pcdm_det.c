/* unit_pcdm_det: Check suite for the held set of --balance dynamic (det_hold / det_release,
 * mesher/pcdm/pcdm_det.c), what pcdm_move.c changes while rt_run runs.
 *
 * Subdomains arrive in any order and leave from anywhere but the one being refined; the held
 * records must stay in ascending subdomain order, D->local must name each held record's index
 * (-1 for the others), and D->cur must keep naming the same record (the one whose refinement is
 * in progress) while records before it come and go.  No MPI: the records are empty meshes.
 */
#include "check_run.h"
#include "pcdm/pcdm_det_impl.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

enum { NSUB = 40 };

static det_sub *fake(int32_t id) {
    det_sub *s = calloc(1, sizeof *s);
    s->id = id;
    mesh_init(&s->m);
    return s;
}

/* every invariant of the held set; returns the number held */
static int32_t check_set(const pcdm_det *D, const uint8_t *held) {
    int32_t n = 0;
    for (int32_t sub = 0; sub < NSUB; sub++) {
        if (!held[sub]) {
            ck_assert_msg(D->local[sub] == -1, "subdomain %d not held, local %d", sub,
                          D->local[sub]);
            continue;
        }
        int32_t i = D->local[sub];
        ck_assert_msg(i >= 0 && i < D->n, "subdomain %d held at index %d of %d", sub, i, D->n);
        ck_assert_int_eq(D->s[i]->id, sub);
        n++;
    }
    ck_assert_int_eq(n, D->n);
    for (int32_t i = 1; i < D->n; i++)
        ck_assert_msg(D->s[i - 1]->id < D->s[i]->id, "index %d: %d after %d", i, D->s[i]->id,
                      D->s[i - 1]->id);
    return n;
}

START_TEST(test_hold_release) {
    pcdm_det D;
    memset(&D, 0, sizeof D);
    int32_t local[NSUB];
    for (int32_t s = 0; s < NSUB; s++)
        local[s] = -1;
    D.local = local;
    D.cur = -1;
    uint8_t held[NSUB] = {0};
    uint64_t rng = 88172645463325252ull;
    int32_t cur_id = -1;
    for (int step = 0; step < 2000; step++) {
        rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
        int32_t sub = (int32_t)(rng % NSUB);
        if (!held[sub]) { /* arrives */
            det_hold(&D, fake(sub));
            held[sub] = 1;
        } else if (sub != cur_id) { /* leaves */
            det_sub *s = det_release(&D, sub);
            ck_assert_int_eq(s->id, sub);
            det_sub_free(s);
            held[sub] = 0;
        }
        if (cur_id < 0 && D.n > 0 && (rng >> 32) % 3 == 0) { /* a refinement begins */
            D.cur = (int32_t)((rng >> 40) % (uint64_t)D.n);
            cur_id = D.s[D.cur]->id;
        } else if (cur_id >= 0 && (rng >> 32) % 5 == 0) { /* ... and ends */
            D.cur = -1;
            cur_id = -1;
        }
        check_set(&D, held);
        if (cur_id >= 0) ck_assert_int_eq(D.s[D.cur]->id, cur_id);
    }
    for (int32_t i = 0; i < D.n; i++)
        det_sub_free(D.s[i]);
    free(D.s);
}
END_TEST

int main(void) {
    return ck_run(ck_suite("pcdm_det", 0, CK_TESTS(test_hold_release)));
}
