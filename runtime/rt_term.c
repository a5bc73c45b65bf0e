/* rt_term.c - distributed termination detection by a counting token ring (Safra, EWD998).
 *
 * TR-97-17 section 2 ends each REPEAT iteration with "check termination conditions ... set
 * termination flag to true if all local work is completed or no more remote requests are on
 * the way".  A token travels the ring 0 -> 1 -> ... -> p-1 -> 0 as a control record in the
 * runtime's own message stream (never counted as an RSR), carrying {RSRs sent, RSRs received
 * (= fully processed: handler finished), black}.  Each rank has a colour, rt_term.active:
 * black after any activity (received, processed or sent an RSR, or did local work) since it
 * last passed the token.  A rank passes the token on only while locally passive, adding its
 * counts and its colour, and turns white.  Rank 0 starts a round (after RT_WAVE_DELAY of
 * quiet) with a white, zero token and turns white; when the token is back and rank 0 is
 * passive, termination is declared iff the token is white, rank 0 is white and
 * sent + sent0 == received + received0.  Rank 0 then sends a TERM control record to every
 * other rank.  Why this is safe (EWD998): with t the token's position, the invariant is
 * B = sum(sent - received) over all ranks (B: RSRs sent and not yet processed), and
 * P1: every rank the token has visited is passive and the token's counts are their sum, or
 * P2: (sent - received) summed over the unvisited ranks plus the token's (sent - received)
 * is > 0, or P3: an unvisited rank is black, or P4: the token is black.  A visited passive
 * rank becomes non-passive only by the arrival of an RSR, which was counted in B, so P2 held
 * before and still holds; passing the token keeps the disjunction (a black rank makes the
 * token black); turning black never falsifies it.  At the decision P2, P3 and P4 are false,
 * so P1 holds: every rank is passive and B == 0, nothing can wake anyone again.  The
 * assumption (as with any counting detector): a passive rank becomes active only by an RSR;
 * local work that returns BUSY again without a message is an application bug.
 * No collective is open while RSRs flow: a rank holding the token costs nothing.
 */
#include "rt_internal.h"

#include <string.h>

void rt_term_init(rt_term *t, int rank) {
    memset(t, 0, sizeof *t);
    t->active = true;
    t->have_token = rank == 0;
}

bool rt_term_decide(const int64_t result[3]) {
    return result[2] == 0 && result[0] == result[1];
}

void rt_term_token(rt_term *t, const int64_t tok[3]) {
    if (t->have_token) RT_FATAL("termination token received twice");
    memcpy(t->tok, tok, sizeof t->tok);
    t->have_token = true;
}

bool rt_term_step(rt_term *t, int rank, int size, uint64_t sent, uint64_t recvd, bool may_start) {
    if (!t->have_token) return false;
    int64_t v[3] = {t->tok[0] + (int64_t)sent, t->tok[1] + (int64_t)recvd,
                    (t->tok[2] || t->active) ? 1 : 0};
    if (rank != 0) {
        t->have_token = false;
        t->active = false;
        t->waves++;
        rt_send_ctl((rank + 1) % size, RT_CTL_TOKEN, v, sizeof v);
        return false;
    }
    if (t->round_open) { /* the token is back */
        t->round_open = false;
        if (rt_term_decide(v)) {
            for (int r = 1; r < size; r++)
                rt_send_ctl(r, RT_CTL_TERM, NULL, 0);
            t->active = true; /* the next rt_run starts black */
            return true;
        }
    }
    if (!may_start) return false;
    memset(t->tok, 0, sizeof t->tok);
    t->round_open = true;
    t->active = false;
    t->waves++;
    if (size > 1) { /* with one rank the token is back at once: decided at the next step */
        t->have_token = false;
        rt_send_ctl(1, RT_CTL_TOKEN, t->tok, sizeof t->tok);
    }
    return false;
}
