#!/usr/bin/env bash
# The one front end (apps/cli.c) seen from outside, for ./mesh, ./meshcheck, ./pcdm and ./pbw
# (the parallel ones at 1 and 2 ranks): --help exits 0 and lists the exit statuses; usage
# errors (unknown option, missing value, -q nan, -q inf, -a -1, -a 1e400, integer overflow,
# missing input argument) exit 2 with one line "PROG: ... (try --help)"; a missing input file
# exits 1 naming the file; every rank of a parallel run exits with the same status, and none
# hangs (timeout); the shared options' help lines are the same in every mesher.  Triangle's
# syntax end to end (issue 15): switch strings, NAME.1 output next to the input, -NEP, -N, -Q,
# -V, --version, letters not supported (triangle_cases below).  --stats' times (stats_cases
# below): every phase field present (read_s, mesh_s, output_s; the parallel programs also
# start_s and decomp_s) and wall_s the whole run -- at least the phases' sum, and at least a
# read held up on purpose (the input a pipe that delivers it 1 s after it is opened).
. "$(dirname "$0")/lib.sh"

# run PROG NP ARGS...: runs the program (NP = 0: directly; else at NP ranks by mpi_run, which
# records every rank's exit status); sets rc (the status every rank agreed on; a hang, ranks
# that disagree or a rank without a status fail here), out (stdout) and err (stderr).
run() {
    local prog=$1 np=$2
    shift 2
    if [ "$np" = 0 ]; then
        timeout 60 "$BIN/$prog" "$@" >"$T/out" 2>"$T/err"
        rc=$?
    else
        TIMEOUT=60 mpi_run "$np" "$BIN/$prog" "$@" >"$T/out" 2>"$T/err"
        rc=$?
        case $rc in
        124) fail "$prog -np $np $*: hang (killed by timeout)" ;;
        255) fail "$prog -np $np $*: the ranks exit [$rcs], not all alike (or mpirun failed)" ;;
        esac
    fi
    out=$(cat "$T/out")
    err=$(cat "$T/err")
}

# expect_usage PROG NP PATTERN ARGS...: exit 2 and one "PROG: ...PATTERN... (try --help)" line.
expect_usage() {
    local prog=$1 np=$2 pat=$3
    shift 3
    run "$prog" "$np" "$@"
    local lines
    lines=$(grep -c "^$prog: " <<<"$err")
    if [ "$rc" -ne 2 ]; then
        fail "$prog (np $np) $*: exit $rc, expected 2: $err"
    elif [ "$lines" -ne 1 ]; then
        fail "$prog (np $np) $*: $lines '$prog:' lines on stderr, expected one: $err"
    elif ! grep "^$prog: " <<<"$err" | grep -q -- "$pat.*(try --help)$"; then
        fail "$prog (np $np) $*: message lacks '$pat ... (try --help)': $err"
    else
        ok "$prog (np $np) $*: exit 2, '$pat'"
    fi
}

# expect_input_error PROG NP ARGS...: exit 1, the missing file named in a "PROG:" line.
expect_missing_file() {
    local prog=$1 np=$2
    shift 2
    run "$prog" "$np" "$@"
    if [ "$rc" -ne 1 ]; then
        fail "$prog (np $np) $*: exit $rc, expected 1: $err"
    elif [ "$(grep -c "^$prog: .*$T/nosuch" <<<"$err")" -ne 1 ]; then
        fail "$prog (np $np) $*: no single '$prog:' line naming $T/nosuch: $err"
    else
        ok "$prog (np $np) $*: exit 1, the file named"
    fi
}

expect_help() {
    local prog=$1 np=$2
    run "$prog" "$np" --help
    if [ "$rc" -ne 0 ]; then
        fail "$prog (np $np) --help: exit $rc"
    elif ! grep -q "^usage: .*$prog" <<<"$out"; then
        fail "$prog (np $np) --help: no usage line: $out"
    elif ! grep -q "^Exit status: 0 success; 1 bad input" <<<"$out" ||
        ! grep -q "2 usage error" <<<"$out"; then
        fail "$prog (np $np) --help: exit statuses not listed: $out"
    elif [ "$np" -gt 1 ] && [ "$(grep -c '^usage:' <<<"$out")" -ne 1 ]; then
        fail "$prog (np $np) --help: printed by more than one rank"
    else
        ok "$prog (np $np) --help"
    fi
    run "$prog" "$np" -h
    [ "$rc" -eq 0 ] && grep -q "^usage: " <<<"$out" || fail "$prog (np $np) -h: exit $rc"
}

# Usage errors every program shares (the brief list: for the parallel programs at 1 and 2 ranks).
# meshcheck takes two arguments.
common_cases() {
    local prog=$1 np=$2
    shift 2
    local args=("$@")
    expect_help "$prog" "$np"
    expect_usage "$prog" "$np" "unknown option '--no-such-option'" --no-such-option "${args[@]}"
    # a value letter last: -S always needs its value (./meshcheck's -a too; the meshers' lone -a
    # is Triangle's "regional bounds")
    local vopt=-S
    [ "$prog" = meshcheck ] && vopt=-a
    expect_usage "$prog" "$np" "option $vopt needs a value" "${args[@]}" "$vopt"
    expect_usage "$prog" "$np" "bad value 'nan': -q needs a non-negative number" -q nan "${args[@]}"
    expect_usage "$prog" "$np" "bad value 'inf': -q" -q inf "${args[@]}"
    expect_usage "$prog" "$np" "bad value '-1': -a needs a non-negative number" -a -1 "${args[@]}"
    expect_usage "$prog" "$np" "bad value '1e400': -a" -a 1e400 "${args[@]}"
}

# The parser's finer points; the parser is one, so the parallel programs run these at 2 ranks.
more_cases() {
    local prog=$1 np=$2
    shift 2
    local args=("$@")
    expect_usage "$prog" "$np" "unknown option '-Z'" -Z "${args[@]}"
    expect_usage "$prog" "$np" "bad value '-inf': -q" -q -inf "${args[@]}"
    expect_usage "$prog" "$np" "bad value '30x': -q" -q 30x "${args[@]}"
    if [ "$prog" = meshcheck ]; then # a check may hold a mesh to 60 degrees
        expect_usage "$prog" "$np" "bad value '70': -q .*at most 60" -q 70 "${args[@]}"
    else # no mesh meets a bound of 60: below 60, as the library's rule
        expect_usage "$prog" "$np" "bad value '70': -q .*below 60" -q 70 "${args[@]}"
        expect_usage "$prog" "$np" "bad value '60': -q .*below 60" -q 60 "${args[@]}"
    fi
    expect_usage "$prog" "$np" "unknown option '-x' in '-q30x'" -q30x "${args[@]}"
    expect_usage "$prog" "$np" "missing input.poly; usage: " -q 20
}

mesher_cases() {
    local prog=$1 np=$2
    expect_usage "$prog" "$np" "bad value '99999999999999999999': -S needs a non-negative integer" \
        -S 99999999999999999999 data/square.poly
    expect_usage "$prog" "$np" "bad value '1.5': -S" -S 1.5 data/square.poly
    expect_usage "$prog" "$np" "option --vtk needs a value" data/square.poly --vtk
    expect_usage "$prog" "$np" "option --stats takes no value" --stats=1 data/square.poly
    expect_usage "$prog" "$np" "unexpected argument 'data/lake.poly'" data/square.poly data/lake.poly
    expect_missing_file "$prog" "$np" -q30 -a0.1 "$T/nosuch.poly"
    # accepted forms: glued values, --name=value, "--" before a name starting with '-'
    run "$prog" "$np" -NEP -q30 -a0.05 --vtk="$T/v.vtk" -- data/square.poly
    # ./mesh writes FILE; the parallel meshers FILE's .pvtu index and one .vtu piece per rank
    local vok=0
    if [ "$np" -eq 0 ]; then
        [ -s "$T/v.vtk" ] && vok=1
    else
        [ -s "$T/v.pvtu" ] && [ -s "$T/v_0.vtu" ] && vok=1
    fi
    [ "$rc" -eq 0 ] && [ "$vok" = 1 ] && ok "$prog (np $np) -q30 -a0.05 --vtk=F" || fail "$prog (np $np) -q30 -a0.05 --vtk=F: exit $rc: $err"
    rm -f "$T"/v.vtk "$T"/v.pvtu "$T"/v_*.vtu
    # -q above what refinement can promise warns (once) and runs
    run "$prog" "$np" -NEP -q 35 -a 0.05 data/square.poly
    [ "$rc" -eq 0 ] && [ "$(grep -c "^$prog: warning: -q 35 above about 34" <<<"$err")" -eq 1 ] && ok "$prog (np $np) -q 35: one warning" ||
        fail "$prog (np $np) -q 35: exit $rc, expected one warning: $err"
}

parallel_cases() {
    local prog=$1 np=$2
    expect_usage "$prog" "$np" "bad value '2.5': --subdomains needs a positive integer" \
        --subdomains 2.5 data/square.poly
    expect_usage "$prog" "$np" "bad value '9999999999': --subdomains" \
        --subdomains 9999999999 data/square.poly
    expect_usage "$prog" "$np" "bad value '0': --imbalance needs a positive number" \
        --imbalance 0 data/square.poly
    expect_usage "$prog" "$np" "bad value '-1': --perturb" --perturb -1 data/square.poly
    expect_usage "$prog" "$np" "bad value '18446744073709551616': --perturb" \
        --perturb 18446744073709551616 data/square.poly
    expect_usage "$prog" "$np" "option --cuts needs a value" data/square.poly --cuts
}

common_cases mesh 0 data/square.poly
more_cases mesh 0 data/square.poly
expect_missing_file mesh 0 "$T/nosuch.poly"
mesher_cases mesh 0
expect_usage mesh 0 "unknown option '--phases'" --phases data/square.poly
expect_usage mesh 0 "unknown option '--subdomains'" --subdomains 2 data/square.poly

common_cases meshcheck 0 data/square.poly "$T/m"
more_cases meshcheck 0 data/square.poly "$T/m"
expect_usage meshcheck 0 "missing PREFIX; usage: meshcheck" data/square.poly
expect_usage meshcheck 0 "unknown option '--stats'" --stats data/square.poly "$T/m"
"$BIN/mesh" -q 30 -o "$T/m" data/square.poly >/dev/null 2>&1 || fail "./mesh -o $T/m"
expect_missing_file meshcheck 0 "$T/nosuch.poly" "$T/m"
expect_missing_file meshcheck 0 data/square.poly "$T/nosuch"
run meshcheck 0 -q 30 data/square.poly "$T/m"
[ "$rc" -eq 0 ] || fail "meshcheck -q 30 on ./mesh -q 30: exit $rc: $out $err"
run meshcheck 0 -q 59 data/square.poly "$T/m"
[ "$rc" -eq 1 ] || fail "meshcheck -q 59 (a bound the mesh misses): exit $rc, expected 1"

for np in 1 2; do
    for prog in pcdm pbw; do
        common_cases "$prog" "$np" data/square.poly
        expect_missing_file "$prog" "$np" "$T/nosuch.poly"
    done
done
for prog in pcdm pbw; do
    more_cases "$prog" 2 data/square.poly
    mesher_cases "$prog" 2
    parallel_cases "$prog" 2
done
# rank 0 reads the input and sends it: the file need not exist where the other ranks run (a
# machine without it), and a different file there is not read -- the mesh is rank 0's input's
# (./meshcheck holds the written mesh to data/square.poly)
cp data/square.poly "$T/rankin.0"
for prog in pcdm pbw; do
    for other in "$T/nosuch.poly" data/lake.poly; do
        [ "$other" = data/lake.poly ] && cp data/lake.poly "$T/rankin.1" || rm -f "$T/rankin.1"
        rm -f "$T"/rk.*
        mpi_run 2 sh -c "exec \"$BIN/$prog\" -q 20 -a 0.01 -o \"$T/rk\" \"$T/rankin.\$OMPI_COMM_WORLD_RANK\"" \
            >"$T/out" 2>"$T/err"
        if ! all_ranks 2 0; then
            fail "$prog, rank 1 given ${other##*/}: exits $rcs, stderr: $(head -c 400 "$T/err")"
        elif ! "$BIN/meshcheck" data/square.poly "$T/rk" >"$T/mc" 2>&1; then
            fail "$prog, rank 1 given ${other##*/}: not a mesh of rank 0's input: $(head -c 300 "$T/mc")"
        else
            ok "$prog, rank 1 given ${other##*/}: every rank exits 0, the mesh is rank 0's input's"
        fi
    done
done
expect_usage pcdm 2 "unknown option '--phases'" --phases data/square.poly
expect_usage pcdm 2 "unknown option '--lens'" --lens data/square.poly
expect_usage mesh 0 "unknown option '--poll'" --poll 1 data/square.poly
for prog in pcdm pbw; do expect_usage "$prog" 2 "--poll" --poll 0 data/square.poly; done

# the shared options are one set of rows: the same help lines in every mesher
for prog in mesh pcdm pbw; do
    "$BIN/$prog" --help | awk '/^  (-[qaSo] |--(vtk|svg|stats|check|progress|circumcenters|help)|-h,)/ { p = 1 }
        /^  -/ && !/^  (-[qaSo] |--(vtk|svg|stats|check|progress|circumcenters)|-h,)/ { p = 0 }
        /^[^ ]/ { p = 0 } p' >"$T/help.$prog"
    [ -s "$T/help.$prog" ] || fail "$prog --help: no shared option lines"
done
cmp -s "$T/help.mesh" "$T/help.pcdm" || fail "shared help differs: mesh vs pcdm: $(diff "$T/help.mesh" "$T/help.pcdm")"
cmp -s "$T/help.mesh" "$T/help.pbw" || fail "shared help differs: mesh vs pbw: $(diff "$T/help.mesh" "$T/help.pbw")"
[ "$(grep -c '^  -' "$T/help.mesh")" -eq 12 ] || fail "expected 12 shared options in --help: $(cat "$T/help.mesh")"

# Triangle's syntax end to end (issue 15; the parse of every switch string against its spaced
# form is unit_cli's): a switch string meshes as its spaced form does (./mesh: the same bytes;
# the parallel meshers: both pass ./meshcheck with the bounds), the files land where Triangle
# puts them (NAME.1 next to the input), -NEP writes none and -N no .node, -Q prints nothing
# (not the -q 35 warning, not --check's OK), -V prints a summary, --version, a Triangle letter
# we do not implement is refused by name.
same_mesh() { # PROG WHAT PREFIX1 PREFIX2 INPUT Q A
    local prog=$1 what=$2 p1=$3 p2=$4 in=$5 q=$6 a=$7 e
    for e in node ele poly; do [ -s "$p1.$e" ] && [ -s "$p2.$e" ] || {
        fail "$what: no $e files"
        return
    }; done
    if [ "$prog" = mesh ]; then
        for e in node ele poly; do cmp -s "$p1.$e" "$p2.$e" || {
            fail "$what: .$e files differ"
            return
        }; done
    else
        for p in "$p1" "$p2"; do
            "$BIN/meshcheck" -q "$q" -a "$a" "$in" "$p" >/dev/null 2>&1 || {
                fail "$what: $p fails ./meshcheck"
                return
            }
        done
    fi
    ok "$what"
}
triangle_cases() {
    local prog=$1 np=$2 d="$T/tri.$1"
    rm -rf "$d" && mkdir -p "$d" && cp data/lake.poly "$d/lake.poly"
    run "$prog" "$np" -pq30a0.01Q "$d/lake.poly"
    [ "$rc" -eq 0 ] && [ -z "$out$err" ] ||
        fail "$prog (np $np) -pq30a0.01Q: exit $rc, output '$out$err'"
    run "$prog" "$np" -p -q 30 -a 0.01 -Q -o "$d/spaced" "$d/lake.poly"
    same_mesh "$prog" "$prog (np $np) -pq30a0.01Q vs -p -q 30 -a 0.01 -Q" "$d/lake.1" "$d/spaced" \
        "$d/lake.poly" 30 0.01
    run "$prog" "$np" -q -o "$d/bare" "$d/lake.poly"
    run "$prog" "$np" -q 20 -o "$d/twenty" "$d/lake.poly"
    same_mesh "$prog" "$prog (np $np) -q vs -q 20" "$d/bare" "$d/twenty" "$d/lake.poly" 20 0
    # -o PREFIX opens its argument (a prefix is no switch): -Ao is refused, not read as -A -o
    expect_usage "$prog" "$np" "option -o (PREFIX) must open its argument" -Ao "$d/long" data/square.poly
    # -NEP writes nothing, -N all but the .node
    rm -f "$d"/lake.1.*
    run "$prog" "$np" -pqNEP "$d/lake.poly"
    [ "$rc" -eq 0 ] && ! ls "$d"/lake.1.* >/dev/null 2>&1 || fail "$prog (np $np) -pqNEP: exit $rc, or files: $(ls "$d")"
    run "$prog" "$np" -pqN "$d/lake.poly"
    [ "$rc" -eq 0 ] && [ ! -e "$d/lake.1.node" ] && [ -s "$d/lake.1.ele" ] && [ -s "$d/lake.1.poly" ] && ok "$prog (np $np) -pqN" ||
        fail "$prog (np $np) -pqN: exit $rc, files: $(ls "$d")"
    # -Q: nothing but errors; -V: a summary on stderr
    run "$prog" "$np" -NEPQ -q 35 -a 0.05 --check data/square.poly
    [ "$rc" -eq 0 ] && [ -z "$out$err" ] && ok "$prog (np $np) -Q: silent" || fail "$prog (np $np) -Q: exit $rc, printed '$out$err'"
    run "$prog" "$np" -NEPQ tests/bad/duplicate_points.poly # the reader's "merged" warning too
    [ "$rc" -eq 0 ] && [ -z "$out$err" ] && ok "$prog (np $np) -Q duplicates: silent" || fail "$prog (np $np) -Q duplicates: exit $rc, '$out$err'"
    run "$prog" "$np" -NEPV data/square.poly
    [ "$rc" -eq 0 ] && grep -q "^$prog: data/square.poly: 4 vertices, 4 segments" <<<"$err" &&
        grep -q "^$prog: .*[0-9]* triangles" <<<"$err" && ok "$prog (np $np) -V" || fail "$prog (np $np) -V: exit $rc, '$err'"
    expect_usage "$prog" "$np" "option -D in '-pqcD' is not supported (in Triangle: conforming Delaunay)" \
        -pqcD data/square.poly
}
triangle_cases mesh 0
triangle_cases pcdm 2
triangle_cases pbw 2
# --stats' times: PROG NP.  A run with a large-ish output (-o, about 340K triangles, and
# --check): each phase field present, and wall_s at least their sum (0.01 s: the printed values'
# rounding) -- so at least output_s + mesh_s.  Then the input read from a pipe that delivers it
# 1 s after the program opens it: read_s and wall_s at least that second.
stats_cases() {
    local prog=$1 np=$2 what="$1 (np $2) --stats" phases="read_s mesh_s output_s" k v sl
    [ "$np" = 0 ] || phases="start_s read_s decomp_s mesh_s output_s"
    rm -f "$T"/st.*
    run "$prog" "$np" -q 30 -a 1e-5 -o "$T/st" --check --stats data/lake.poly
    sl=$(grep '^stats:' <<<"$out" | tail -n 1)
    if [ "$rc" -ne 0 ] || [ -z "$sl" ]; then
        fail "$what -o: exit $rc, stats line '$sl': $err"
    else
        local sum=0 missing="" w m o
        for k in $phases wall_s; do # a missing phase counts 0 in the sum
            v=$(field "$k" <<<"$sl")
            [[ "$v" =~ ^[0-9]+\.[0-9]+$ ]] || missing="$missing $k"
            [ "$k" = wall_s ] || sum=$(awk -v a="$sum" -v b="${v:-0}" 'BEGIN { print a + b }')
        done
        [ -z "$missing" ] && ok "$what -o: $phases wall_s present" ||
            fail "$what -o: no numeric$missing in: $sl"
        w=$(field wall_s <<<"$sl") m=$(field mesh_s <<<"$sl") o=$(field output_s <<<"$sl")
        if awk -v w="${w:-0}" -v s="$sum" -v m="${m:-0}" -v o="${o:-0}" \
            'BEGIN { exit !(w >= s - 0.01 && w >= m + o - 0.01) }'; then
            ok "$what -o: wall_s=$w >= the phases' sum $sum (mesh_s=$m output_s=$o)"
        else
            fail "$what -o: wall_s='$w' below the phases' sum $sum ($phases; mesh_s='$m' output_s='$o')"
        fi
    fi
    rm -f "$T"/st.* "$T/slow.poly"
    mkfifo "$T/slow.poly" || {
        fail "$what: cannot make a pipe"
        return
    }
    # the writer's open waits for the program's; then 1 s before the input comes
    timeout 60 sh -c 'exec 3>"$1"; sleep 1; cat data/lake.poly >&3' sh "$T/slow.poly" &
    local feeder=$!
    run "$prog" "$np" -NEP -q 30 --stats "$T/slow.poly"
    wait "$feeder"
    sl=$(grep '^stats:' <<<"$out" | tail -n 1)
    local r
    r=$(field read_s <<<"$sl") w=$(field wall_s <<<"$sl")
    if [ "$rc" -ne 0 ] || [ -z "$sl" ]; then
        fail "$what, input from a slow pipe: exit $rc, stats line '$sl': $err"
    elif ! awk -v r="${r:-0}" -v w="${w:-0}" 'BEGIN { exit !(r >= 1 && w >= r) }'; then
        fail "$what, input from a pipe 1 s late: read_s='$r' wall_s='$w', expected both >= 1"
    else
        ok "$what, input from a pipe 1 s late: read_s=$r, wall_s=$w"
    fi
    rm -f "$T/slow.poly"
}
stats_cases mesh 0
stats_cases pcdm 1
stats_cases pcdm 3
stats_cases pbw 2

for prog in mesh meshcheck pcdm pbw; do
    np=0
    [ "$prog" = pcdm ] || [ "$prog" = pbw ] && np=2
    run "$prog" "$np" --version
    [ "$rc" -eq 0 ] && [[ "$out" =~ ^$prog\ \(pcdm\)\ [0-9]+\.[0-9]+\.[0-9]+$ ]] && ok "$prog (np $np) --version" ||
        fail "$prog (np $np) --version: exit $rc, '$out'"
done

finish
