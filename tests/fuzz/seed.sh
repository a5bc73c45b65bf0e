#!/usr/bin/env bash
# Re-creates the seed corpus tests/fuzz/corpus from data/ and tests/bad/: each file prefixed
# by one option byte (fuzz_mesh.c: bits 0-2 angle bound, 3 circumcenters, 4 lenses, 5 area
# bound, 7 .node).  Corpus file names are the content's sha1, as libFuzzer names them.
set -eu
cd "$(dirname "$0")/../.."
out=tests/fuzz/corpus
mkdir -p "$out"
add() { # option-byte-octal file
    local t
    t=$(mktemp)
    {
        printf "\\$1"
        cat "$2"
    } >"$t"
    mv "$t" "$out/$(sha1sum <"$t" | cut -c1-40)"
}
for f in data/*.poly; do for o in 001 002 043 014 023; do add "$o" "$f"; done; done
for f in tests/bad/*.poly; do add 001 "$f"; done
for f in tests/bad/*.node; do add 201 "$f"; done
for f in tests/fuzz/regress/*.poly; do if [ -e "$f" ]; then add 003 "$f"; fi; done
for f in tests/fuzz/regress/*.node; do if [ -e "$f" ]; then add 203 "$f"; fi; done
