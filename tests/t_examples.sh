#!/usr/bin/env bash
# t_examples: inputs we did not write.  Triangle's example files (the letter A, the face, the
# boxes, the double hexagons, Greenland's 33,343 points, ...), as the PyPI `triangle` package
# ships them, through ./mesh, ./pcdm and ./pbw.
#
# The files are not in our tree (their licence is not ours); the test fetches the package's wheel
# from PyPI once into build/examples (or takes EXAMPLES=DIR holding .poly/.node files) and skips,
# saying why, when neither works (no python3 or no network).
#
# For every file and bound: ./mesh --check decides what is expected.  Where it meshes (exit 0,
# "meshcheck: OK"), ./pcdm at 3 and 8 ranks and ./pbw at 3 ranks must mesh too and pass their
# distributed --check; where ./mesh refuses (exit 1, e.g. "cannot meet the bounds"), they must
# refuse too (exit 1), never exit 0 and never hang (exit 124 = killed by timeout = failure).
# Env: BIN (programs, default .), MPIRUN (default "mpirun --oversubscribe"), EXAMPLES (a
# directory instead of the download), SANITIZE=1 (one bound only).
set -u
cd "$(dirname "$0")/.."
BIN=${BIN:-.}
MPIRUN=${MPIRUN:-mpirun --oversubscribe}
if [ "$(id -u)" -eq 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/t_examples.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

# The package version is pinned, so every run sees the same files.
VERSION=20250106
dir=${EXAMPLES:-build/examples/triangle-$VERSION}
if [ ! -d "$dir" ]; then
    if ! command -v python3 >/dev/null 2>&1; then
        echo "t_examples: SKIP: no python3 to fetch Triangle's examples (set EXAMPLES=DIR)"
        exit 0
    fi
    mkdir -p "$(dirname "$dir")"
    if ! timeout 300 python3 - "$VERSION" "$tmp/ex" <<'EOF' >"$tmp/fetch.txt" 2>&1; then
# The data files of the PyPI package `triangle`: from an installed copy of the pinned version,
# else its wheel by pip download, else the wheel's address from PyPI's JSON API.
import glob, io, json, os, shutil, subprocess, sys, tempfile, urllib.request, zipfile
version, out = sys.argv[1], sys.argv[2]
os.makedirs(out)
def keep(name):
    return name.endswith((".poly", ".node"))
try:
    import importlib.metadata, triangle
    if importlib.metadata.version("triangle") != version:
        raise ImportError("not the pinned version")
    src = os.path.join(os.path.dirname(triangle.__file__), "data")
    for f in os.listdir(src):
        if keep(f):
            shutil.copy(os.path.join(src, f), out)
    print("copied from the installed package")
    sys.exit(0)
except Exception:
    pass
data = None
with tempfile.TemporaryDirectory() as d:
    r = subprocess.run([sys.executable, "-m", "pip", "download", "-q", "--no-deps",
                        "--only-binary=:all:", "-d", d, "triangle==" + version],
                       capture_output=True)
    whl = glob.glob(os.path.join(d, "*.whl"))
    if r.returncode == 0 and whl:
        data = open(whl[0], "rb").read()
if data is None:
    meta = json.load(urllib.request.urlopen("https://pypi.org/pypi/triangle/json", timeout=60))
    wheels = [u["url"] for u in meta["releases"].get(version, [])
              if u["filename"].endswith(".whl")]
    if not wheels:
        sys.exit("no wheel for triangle " + version)
    data = urllib.request.urlopen(wheels[0], timeout=60).read()
n = 0
with zipfile.ZipFile(io.BytesIO(data)) as z:
    for name in z.namelist():
        base = os.path.basename(name)
        if name.startswith("triangle/data/") and keep(base):
            with open(os.path.join(out, base), "wb") as f:
                f.write(z.read(name))
            n += 1
print("fetched", n, "files")
EOF
        echo "t_examples: SKIP: cannot fetch Triangle's examples from PyPI: $(tail -1 "$tmp/fetch.txt")"
        exit 0
    fi
    mv "$tmp/ex" "$dir"
fi

pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); printf 'FAIL %s\n' "$*"; }
first() { grep -v -e 'warning' -e '^---' -e '^$' "$1" | head -1 | cut -c1-200; }

bounds=("-q 25" "-q 30")
[ "${SANITIZE:-}" = 1 ] && bounds=("-q 25")
n=0
for f in "$dir"/*.poly "$dir"/*.node; do
    [ -e "$f" ] || continue
    n=$((n + 1))
    for b in "${bounds[@]}"; do
        # shellcheck disable=SC2086
        timeout 120 "$BIN/mesh" -NEP $b --check "$f" >"$tmp/m.txt" 2>&1
        want=$?
        name="$(basename "$f") $b"
        if [ "$want" = 0 ] && ! grep -q '^meshcheck: OK' "$tmp/m.txt"; then
            bad "$name: ./mesh exit 0 without meshcheck: OK"
            continue
        fi
        if [ "$want" != 0 ] && [ "$want" != 1 ]; then
            bad "$name: ./mesh exit $want: $(first "$tmp/m.txt")"
            continue
        fi
        ok
        for run in "pcdm 3" "pcdm 8" "pbw 3"; do
            set -- $run
            # shellcheck disable=SC2086
            timeout 300 $MPIRUN -np "$2" "$BIN/$1" -NEP $b --check "$f" >"$tmp/p.txt" 2>&1
            got=$?
            if [ "$got" != "$want" ]; then
                bad "$name: ./$1 at $2 ranks exit $got, ./mesh exit $want: $(first "$tmp/p.txt")"
            elif [ "$got" = 0 ] && ! grep -q '^meshcheck: OK' "$tmp/p.txt"; then
                bad "$name: ./$1 at $2 ranks: exit 0 without meshcheck: OK"
            else
                ok
            fi
        done
    done
done
[ "$n" -gt 0 ] || bad "no .poly or .node files in $dir"
echo "t_examples: $n files, $pass passed, $fail failed"
[ "$fail" -eq 0 ]
