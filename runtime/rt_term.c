/* rt_term.c - distributed termination detection by a counting token ring (Safra, EWD998),
 * and deadlock detection on the same ring.
 *
 * TR-97-17 section 2 ends each REPEAT iteration with "check termination conditions ... set
 * termination flag to true if all local work is completed or no more remote requests are on
 * the way".  A token travels the ring 0 -> 1 -> ... -> p-1 -> 0 as a control record in the
 * runtime's own message stream (never counted as an RSR), carrying {RSRs sent, RSRs received
 * (= fully processed: handler finished), black, blocked tasks}.  A rank is QUIESCENT when it
 * has no ready task, its local work returned IDLE, no threaded handler is queued, running or
 * unfinished and no RSR is buffered, self-queued or held; it may still hold BLOCKED tasks
 * (waiting for replies).  It is PASSIVE when it is quiescent and holds no blocked task.  Each
 * rank has a colour, rt_term.active: black after any activity (received, processed or sent
 * an RSR, ran a task, or did local work) since it last passed the token.  A rank passes the
 * token on only while quiescent, adding its counts, its colour and its number of blocked
 * tasks, and turns white.  Rank 0 starts a round (after RT_WAVE_DELAY of quiet) with a
 * white, zero token and turns white; when the token is back and rank 0 is quiescent, the
 * round is DECIDED iff the token is white, rank 0 is white and sent + sent0 == received +
 * received0.  Then, with blocked = the token's blocked sum plus rank 0's: blocked == 0 is
 * termination (rank 0 sends TERM to every other rank); blocked > 0 is a DEADLOCK (rank 0
 * sends DEADLOCK, carrying the sum, to every other rank; each rank prints its blocking
 * queue and the job aborts, rt.c).  A failed round just starts another.
 * Why this is safe (EWD998, with quiescent for passive): with t the token's position, the
 * invariant is B = sum(sent - received) over all ranks (B: RSRs sent and not yet processed),
 * and P1: every rank the token has visited is quiescent and the token's counts (sent,
 * received, blocked) are the sums of those ranks' current counts, or P2: (sent - received)
 * summed over the unvisited ranks plus the token's (sent - received) is > 0, or P3: an
 * unvisited rank is black, or P4: the token is black.  The key fact: a quiescent rank
 * becomes non-quiescent, or changes its number of blocked tasks, only by the arrival of an
 * RSR.  Its local work stays IDLE until a handler or a task ran on it (rt_work_fn's
 * contract); a task enters the blocking queue only by running (so the rank was not
 * quiescent); and a blocked task becomes ready only when the reply that brings its pending
 * count to 0 has been processed, and a reply is an RSR, counted in B.  So a visited rank
 * that leaves P1's state does so by an arrival: P2 held before and still holds (and the
 * rank turns black, P3/P4 follow once it passes the token); passing the token keeps the
 * disjunction (a black rank makes the token black); turning black never falsifies it.  At
 * a decision P2, P3 and P4 are false, so P1 holds: every rank is quiescent, B == 0 and the
 * token's blocked sum is the number of tasks blocked right now.  Nothing can wake anyone
 * any more, because waking takes a message and there is none.  Hence blocked == 0 means
 * every rank is passive (the old termination condition: a correct program terminates
 * exactly as before, and is never declared deadlocked, since its blocked tasks' replies are
 * in flight or being produced by a non-quiescent rank), and blocked > 0 means those tasks
 * wait for replies that will never come (a handler that never replies, a lost rt_reply, a
 * cycle of waits through application state): a deadlock, reported instead of a hang.  All
 * of it works while RSRs are in flight (they keep P2 true and make the round fail) and
 * needs no timeout.  The assumption (as with any counting detector): a quiescent rank
 * becomes active only by an RSR; local work that returns BUSY again without a message is
 * an application bug.  No collective is open while RSRs flow: a rank holding the token
 * costs nothing.
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

void rt_term_token(rt_term *t, const int64_t tok[RT_TOK_N]) {
    if (t->have_token) RT_FATAL("termination token received twice");
    memcpy(t->tok, tok, sizeof t->tok);
    t->have_token = true;
}

rt_term_verdict rt_term_pass(rt_term *t, int rank, int size, uint64_t sent, uint64_t recvd,
                             uint64_t nblocked, bool may_start) {
    if (!t->have_token) return RT_TERM_GOING;
    int64_t v[RT_TOK_N];
    v[RT_TOK_SENT] = t->tok[RT_TOK_SENT] + (int64_t)sent;
    v[RT_TOK_RECV] = t->tok[RT_TOK_RECV] + (int64_t)recvd;
    v[RT_TOK_BLACK] = (t->tok[RT_TOK_BLACK] || t->active) ? 1 : 0;
    v[RT_TOK_BLOCKED] = t->tok[RT_TOK_BLOCKED] + (int64_t)nblocked;
    if (rank != 0) {
        t->have_token = false;
        t->active = false;
        t->waves++;
        rt_send_ctl((rank + 1) % size, RT_CTL_TOKEN, v, sizeof v);
        return RT_TERM_GOING;
    }
    if (t->round_open) { /* the token is back */
        t->round_open = false;
        if (rt_term_decide(v)) {
            if (v[RT_TOK_BLOCKED] > 0) {
                t->deadlock = true;
                t->deadlock_blocked = v[RT_TOK_BLOCKED];
                for (int r = 1; r < size; r++)
                    rt_send_ctl(r, RT_CTL_DEADLOCK, &t->deadlock_blocked,
                                sizeof t->deadlock_blocked);
                return RT_TERM_DEADLOCK;
            }
            for (int r = 1; r < size; r++)
                rt_send_ctl(r, RT_CTL_TERM, NULL, 0);
            t->active = true; /* the next rt_run starts black */
            return RT_TERM_DONE;
        }
    }
    if (!may_start) return RT_TERM_GOING;
    memset(t->tok, 0, sizeof t->tok);
    t->round_open = true;
    t->active = false;
    t->waves++;
    if (size > 1) { /* with one rank the token is back at once: decided at the next step */
        t->have_token = false;
        rt_send_ctl(1, RT_CTL_TOKEN, t->tok, sizeof t->tok);
    }
    return RT_TERM_GOING;
}
