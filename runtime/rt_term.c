/* rt_term.c - distributed termination detection by counting waves.
 *
 * TR-97-17 section 2 ends each REPEAT iteration with "check termination conditions ... set
 * termination flag to true if all local work is completed or no more remote requests are on
 * the way".  We decide it with waves of a nonblocking MPI_Iallreduce (sum) over three
 * numbers per rank: RSRs sent, RSRs received (= fully processed: handler finished), and an
 * activity flag (did this rank receive, process, send or work since its previous
 * contribution).  A rank contributes to a wave only while it is locally passive; it keeps
 * serving messages while the wave is open.  Termination is declared on wave k+1 when its
 * reduced activity is 0 and sent == received.  Why this is safe: wave k completed at a time
 * T after every rank's k-th contribution and before any rank's (k+1)-th; no rank had any
 * activity between the two, so all ranks were passive at T with the counts they reported in
 * k+1; sent == received then means no RSR was in flight at T (every received RSR was sent),
 * so nothing can ever wake anyone again.  The first wave of rt_run always reports activity.
 * Every rank sees the same reduced values, so all decide on the same wave.
 */
#include "rt_internal.h"

#include <string.h>

void rt_term_init(rt_term *t) {
    memset(t, 0, sizeof *t);
    t->req = MPI_REQUEST_NULL;
    t->active = true;
}

bool rt_term_decide(const int64_t result[3]) {
    return result[2] == 0 && result[0] == result[1];
}

bool rt_term_step(rt_term *t, MPI_Comm comm, uint64_t sent, uint64_t recvd) {
    if (!t->wave_open) {
        t->contrib[0] = (int64_t)sent;
        t->contrib[1] = (int64_t)recvd;
        t->contrib[2] = t->active ? 1 : 0;
        t->active = false;
        RT_MPI(MPI_Iallreduce(t->contrib, t->result, 3, MPI_INT64_T, MPI_SUM, comm, &t->req));
        t->wave_open = true;
        t->waves++;
    }
    int done = 0;
    RT_MPI(MPI_Test(&t->req, &done, MPI_STATUS_IGNORE));
    if (!done) return false;
    t->wave_open = false;
    if (!rt_term_decide(t->result)) return false;
    /* Declared: by the argument above nothing may have happened here since contributing. */
    if (t->active)
        RT_FATAL("termination declared while this rank was active (local work returned BUSY "
                 "without a message, or a runtime bug)");
    t->active = true; /* the next rt_run starts with an active wave */
    return true;
}
