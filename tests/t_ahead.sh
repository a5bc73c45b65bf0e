#!/usr/bin/env bash
# t_ahead: ./pcdm's rank 0 triangulates the input's vertices on a second thread while it checks
# the input (mesher/run/run_ahead.c); the decomposition may start from that triangulation only
# when the check left the vertices exactly as they were.  Inputs where the check does change
# them -- a duplicate vertex (merged), coordinates that must be scaled into the working range,
# a hole point that makes the whole input scale although the vertices alone need not -- and the
# plain lake: at 1 rank (no thread ahead), 2 ranks and --threads 2, every run passes --check and
# the mesh hash is one value.  A stale copy of the vertices (one moved by an ulp: the test-only
# fault PCDM_TEST_AHEAD_STALE) is refused by the comparison: the same mesh.  The test can fail:
# the stale copy taken without the comparison (PCDM_TEST_AHEAD_TRUST too) must change the lake's
# mesh at 2 ranks.
. "$(dirname "$0")/lib.sh"

# make_input NAME: writes $T/NAME.poly from data/lake.poly (196 vertices, 2 holes)
make_input() {
    python3 - "$1" "$T/$1.poly" <<'PY'
import sys
kind, out = sys.argv[1], sys.argv[2]
src = open("data/lake.poly").read().split("\n")
k = 2.0 ** -700 * 1.37 if kind == "tiny" else None
res, n, c, ns, cs, nh, ch, first = [], None, 0, None, 0, None, 0, None
for line in src:
    t = line.split("#")[0].split()
    if not t:
        res.append(line)
        continue
    if n is None:
        n = int(t[0])
        t[0] = str(n + (kind == "dup"))
        res.append(" ".join(t))
    elif c < n:
        c += 1
        first = first or list(t)
        if k:
            t[1], t[2] = repr(float(t[1]) * k), repr(float(t[2]) * k)
        res.append(" ".join(t))
        if c == n and kind == "dup":  # vertex 1 again, as the last vertex
            res.append(" ".join([str(n + 1)] + first[1:]))
    elif ns is None:
        ns = int(t[0])
        res.append(line)
    elif cs < ns:
        cs += 1
        res.append(line)
    elif nh is None:
        nh = int(t[0])
        res.append(str(nh + (kind == "hole")))
    elif ch < nh:
        ch += 1
        if k:
            t[1], t[2] = repr(float(t[1]) * k), repr(float(t[2]) * k)
        res.append(" ".join(t))
        if ch == nh and kind == "hole":  # outside the domain, off the predicates' grid
            res.append("%d 3.0000000000000004e-70 50" % (nh + 1))
    else:
        res.append(line)
open(out, "w").write("\n".join(res) + "\n")
PY
}

# hash_of NP THREADS FILE: the mesh hash of a checked run, or "exit N" / "no check"
hash_of() {
    local out st
    out=$(mpi_run "$1" "$BIN/pcdm" --threads "$2" -q 30 --subdomains 4 --check --stats -NEP "$3" 2>&1)
    st=$?
    if [ $st -ne 0 ]; then
        echo "exit $st"
    elif ! printf '%s\n' "$out" | grep -q 'check: OK'; then
        echo "no check"
    else
        printf '%s\n' "$out" | grep '^stats:' | field hash
    fi
}

cp data/lake.poly "$T/lake.poly"
for kind in dup tiny hole; do make_input $kind || fatal "cannot write the $kind input"; done
for kind in lake dup tiny hole; do
    f=$T/$kind.poly
    h1=$(hash_of 1 1 "$f") h2=$(hash_of 2 1 "$f") ht=$(hash_of 1 2 "$f")
    if [ ${#h1} -eq 16 ] && [ "$h1" = "$h2" ] && [ "$h1" = "$ht" ]; then
        ok "$kind: 1 rank, 2 ranks, --threads 2: checked, hash $h1"
    else
        fail "$kind: hashes 1 rank '$h1', 2 ranks '$h2', --threads 2 '$ht'"
    fi
done
h1=$(hash_of 1 1 "$T/lake.poly")
h=$(PCDM_TEST_AHEAD_STALE=1 MPI_X="-x PCDM_TEST_AHEAD_STALE" hash_of 2 1 "$T/lake.poly")
if [ "$h" = "$h1" ]; then
    ok "a stale triangulation is refused: hash $h"
else
    fail "a stale triangulation: hash '$h', not $h1"
fi
# the planted fault: the stale triangulation taken without the comparison
h=$(PCDM_TEST_AHEAD_STALE=1 PCDM_TEST_AHEAD_TRUST=1 \
    MPI_X="-x PCDM_TEST_AHEAD_STALE -x PCDM_TEST_AHEAD_TRUST" hash_of 2 1 "$T/lake.poly")
if [ "$h" != "$h1" ]; then
    ok "fault: a stale triangulation taken without the comparison gives '$h', not $h1"
else
    fail "fault: PCDM_TEST_AHEAD_TRUST did not change the lake's mesh ($h)"
fi
finish
