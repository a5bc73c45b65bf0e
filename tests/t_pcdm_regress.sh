#!/usr/bin/env bash
# t_pcdm_regress: the fuzz regression table (tests/fuzz/regress/TABLE: inputs the fuzzer and
# issue 10 found) through ./pcdm at 2 and 3 ranks, each rank's exit status recorded.  ./pcdm
# must never hang (timeout = failure), crash, exit with anything but 0 or 1, or exit 0 without
# its distributed --check saying OK.  Rows ./mesh answers "cannot meet the bounds" must get
# that answer on every rank; rows ./mesh meshes must be meshed, or refused on every rank with a
# clear message: "cannot decompose" (a domain too small or too degenerate to cut, issue 11) or
# "cannot meet the bounds" (a decomposition cut through a region ./mesh resolves only through
# the shells of one far input corner); rows ./mesh cannot meet may also be refused by the
# decomposition, or met (another insertion order can reach a bound ./mesh does not; --check
# must say OK).  Rows where ./mesh stops at the Steiner limit (exit 3) must exit 3 or 0 with
# --check OK, or be refused as above.  The refusals are counted and printed.  Found this way:
# a point set 8e29 long and 2 wide (point_sliver_8e29.node) ran until killed at 3 ranks; the
# rows of tests/fuzz/pending_par's replay (iface_*, cuts_tiny_angle_*, sliver_one_triangle) ran
# for minutes or failed the interface check.  Last, iface_fan_steiner_limit.poly at 8 ranks with
# --async (below).
# Env: BIN, MPIRUN as the other tests; SANITIZE=1 (3 ranks only).
. "$(dirname "$0")/lib.sh"
refused=0
NPS="2 3"
[ "${SANITIZE:-}" = 1 ] && NPS="3"
while IFS='|' read -r f opts want pat; do
    f=$(echo $f) opts=$(echo $opts) want=$(echo $want)
    case "$f" in '#'* | '') continue ;; esac
    case "$opts" in *--cdt-only* | *--lens*) continue ;; esac # ./mesh only
    if [ "$want" = 0 ]; then
        kind=meshed
    elif grep -q 'cannot meet the bounds' <<<"$pat"; then
        kind=unmet
    elif [ "$want" = 3 ]; then
        kind=limit
    else
        continue
    fi
    for np in $NPS; do
        # shellcheck disable=SC2086
        out=$(mpi_run "$np" "$BIN/pcdm" -NEP $opts --check "tests/fuzz/regress/$f" 2>&1 </dev/null)
        rc=$?
        rcs=$(cat "$T/rcs")
        name="$f $opts np=$np"
        if [ "$rc" = 124 ]; then
            fail "$name: timeout (120 s)"
            continue
        fi
        st=$(tr ' ' '\n' <<<"$rcs" | sort -u | tr '\n' ' ')
        case " $rcs " in *" none "*)
            fail "$name: not every rank ended: [$rcs]"
            continue
            ;;
        esac
        if [ "$st" = "0 " ]; then
            if ! grep -q '^meshcheck: OK' <<<"$out"; then
                fail "$name: exit 0 without --check OK"
                continue
            fi
            [ "$kind" = meshed ] || echo "met: $name: ./mesh exit $want, ./pcdm met the bounds"
        elif [ "$st" = "3 " ] && [ "$kind" = limit ]; then
            if ! grep -q '^meshcheck: OK' <<<"$out"; then
                fail "$name: exit 3 without --check OK"
                continue
            fi
        elif [ "$st" = "1 " ] && grep -q 'cannot meet the bounds' <<<"$out"; then
            [ "$kind" = meshed ] && refused=$((refused + 1)) && echo "refused: $name: cannot meet the bounds"
        elif [ "$st" = "1 " ] && grep -q 'cannot decompose' <<<"$out"; then
            refused=$((refused + 1))
            echo "refused: $name: cannot decompose"
        else
            fail "$name ($kind): exit [$st]: $(grep -v '^ ' <<<"$out" | grep -v warning | head -n 2)"
            continue
        fi
        ok "$name ($kind): exit [$st]"
    done
done <tests/fuzz/regress/TABLE
echo "$TEST: $refused refused by ./pcdm (cannot decompose, or cannot meet the bounds where ./mesh meshes)"

# The asynchronous protocol at 8 ranks on the interface fan at a tiny feature under the Steiner
# limit: named interface splits received past the limit, at points rounded off their line,
# left fan edges that were not locally Delaunay in one rank's mesh, and ./pcdm wrote that mesh
# with exit 3 on every run (the schedule explorer, make stress).  Each rank's mesh is made
# Delaunay again by flips after refinement: exit 3 with the mesh valid (--check, and ./meshcheck
# on the files written without --check), or the interface error on every rank, nothing written.
f=tests/fuzz/regress/iface_fan_steiner_limit.poly
if [ "${SANITIZE:-}" != 1 ]; then
    for run in 1 2; do
        name="iface_fan_steiner_limit.poly -q 30 -S 20000 --async np=8 run $run"
        rm -f "$T/fan".*
        out=$(mpi_run 8 "$BIN/pcdm" -q 30 -S 20000 --async --stats -o "$T/fan" "$f" 2>&1 </dev/null)
        rc=$?
        if [ "$rc" = 3 ]; then
            chk=$("$BIN/meshcheck" -q 0 "$f" "$T/fan" 2>&1)
            flips=$(sed -n 's/^rank .* flips=\([0-9]*\).*/\1/p' <<<"$out" | awk '{ s += $1 } END { print s + 0 }')
            if grep -q '^meshcheck: OK' <<<"$chk"; then
                ok "$name: exit 3, ./meshcheck OK ($flips flips)"
            else
                fail "$name: exit 3 with a mesh ./meshcheck refuses: $(head -c 300 <<<"$chk")"
            fi
        elif [ "$rc" = 1 ] && grep -q 'cannot meet the bounds' <<<"$out" && ! [ -e "$T/fan.ele" ]; then
            ok "$name: cannot meet the bounds on every rank, nothing written"
        else
            fail "$name: exit [$(cat "$T/rcs")]: $(grep -v '^ ' <<<"$out" | grep -v '^rank\|^rsr\|^stats' | head -n 2)"
        fi
    done
    out=$(mpi_run 8 "$BIN/pcdm" -NEP -q 30 -S 20000 --async --check "$f" 2>&1 </dev/null)
    rc=$?
    name="iface_fan_steiner_limit.poly -q 30 -S 20000 --async np=8 --check"
    if [ "$rc" = 3 ] && grep -q '^meshcheck: OK' <<<"$out"; then
        ok "$name: exit 3, --check OK"
    elif [ "$rc" = 1 ] && grep -q 'cannot meet the bounds' <<<"$out"; then
        ok "$name: cannot meet the bounds on every rank"
    else
        fail "$name: exit [$(cat "$T/rcs")]: $(grep -E '^meshcheck|^pcdm' <<<"$out" | head -n 2 | head -c 400)"
    fi
fi
finish
