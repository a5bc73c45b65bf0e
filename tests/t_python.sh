#!/usr/bin/env bash
# t_python: the Python package as a user gets it -- `pip install .` into a virtual environment
# (build/pyvenv, made once, seeing the system's packages), then its pytest suite
# (python/tests/test_pcdm.py: Triangle's example files through pcdm and the triangle package,
# keys, dtypes, shapes, the validator, Steiner counts; bad input as ValueError; memory over
# 10,000 calls; the GIL; python -m pcdm; python/tests/test_triangle_api.py: delaunay,
# convex_hull, voronoi, the file readers, plot and compare against the triangle package).  What
# the environment lacks is installed there from PyPI with pip (setuptools, numpy, pytest,
# triangle, pinned as tests/t_examples.sh pins it; matplotlib, without which plot and compare
# are skipped, saying so).
# With MPI (mpicc, METIS), pcdm.parallel too: python/tests/par_check.py under mpirun at 2 and 3
# ranks (mpi4py from PyPI when missing).  Skips, saying why, without python3 (with venv and pip); the sanitizer and debug builds skip it
# (the package is built by setup.py, not by their flags).
. "$(dirname "$0")/lib.sh"
if [ "${SANITIZE:-}" = 1 ] || [ "${DEBUG:-}" = 1 ] || [ "$B" != build ]; then
    skip "sanitizer/debug build (the package is built by setup.py with its own flags)"
fi
command -v python3 >/dev/null 2>&1 || skip "no python3"
V=$PWD/$B/pyvenv
if [ ! -x "$V/bin/python" ]; then
    python3 -m venv --system-site-packages "$V" >"$T/venv.log" 2>&1 ||
        skip "python3 cannot make a virtual environment: $(tail -1 "$T/venv.log")"
fi
py=$V/bin/python
pip_in() { "$py" -m pip install -q --disable-pip-version-check "$@" >>"$T/pip.log" 2>&1; }
"$py" -c 'import setuptools, sys; sys.exit(int(setuptools.__version__.split(".")[0]) < 77)' 2>/dev/null ||
    pip_in "setuptools>=77" wheel || fatal "pip install setuptools: $(tail -3 "$T/pip.log")"
"$py" -c 'import numpy, sys; sys.exit(int(numpy.__version__.split(".")[0]) < 2)' 2>/dev/null ||
    pip_in "numpy>=2" || fatal "pip install numpy: $(tail -3 "$T/pip.log")"
"$py" -c 'import pytest' 2>/dev/null || pip_in pytest || fatal "pip install pytest: $(tail -3 "$T/pip.log")"
"$py" -c 'import triangle' 2>/dev/null || pip_in triangle==20250106 ||
    fatal "pip install triangle: $(tail -3 "$T/pip.log")"
"$py" -c 'import matplotlib' 2>/dev/null || pip_in matplotlib ||
    echo "$TEST: no matplotlib ($(tail -1 "$T/pip.log")): pcdm.plot and pcdm.compare not tested"
# the package from this tree (no build isolation: the build's requirements are installed above)
t0=$SECONDS
if pip_in --no-build-isolation --no-deps --force-reinstall .; then
    ok "pip install . ($((SECONDS - t0)) s)"
else
    fatal "pip install .: $(grep -i -m3 error "$T/pip.log")"
fi
ver=$(sed -n 's/^#define PCDM_VERSION_[A-Z]* *\([0-9]*\).*/\1/p' include/pcdm.h | paste -sd.)
got=$(cd "$T" && "$py" -c 'import pcdm; print(pcdm.__version__)')
[ "$got" = "$ver" ] && ok "pcdm.__version__ $got is include/pcdm.h's" ||
    fail "pcdm.__version__ is '$got', include/pcdm.h says $ver"
# from outside the tree, so that `import pcdm` is the installed package
root=$PWD
if (cd "$T" && "$py" -m pytest -q -p no:cacheprovider -s "$root/python/tests" >"$T/pytest.log" 2>&1); then
    ok "pytest: $(tail -1 "$T/pytest.log")"
else
    fail "pytest: $(grep -E '^(FAILED|ERROR)' "$T/pytest.log" | head -20)$(tail -1 "$T/pytest.log")"
fi
grep -E '^(Steiner|RSS|size|[0-9]+ calls)' "$T/pytest.log"
# pcdm.parallel (built where MPI and METIS are): mpi4py from PyPI when missing, then
# python/tests/par_check.py at 2 and 3 ranks
if (cd "$T" && "$py" -c 'import pcdm._par') 2>/dev/null; then
    "$py" -c 'import mpi4py' 2>/dev/null || pip_in mpi4py || fatal "pip install mpi4py: $(tail -3 "$T/pip.log")"
    for np in 2 3; do
        if (cd "$T" && TIMEOUT=300 mpi_run "$np" "$py" "$root/python/tests/par_check.py" >"$T/par.log" 2>&1); then
            ok "pcdm.parallel at $np ranks: $(grep '^par_check' "$T/par.log")"
        else
            fail "pcdm.parallel at $np ranks: $(tail -5 "$T/par.log")"
        fi
    done
elif command -v mpicc >/dev/null 2>&1; then
    fail "mpicc is here but the package was built without pcdm._par: $(grep -m1 'without pcdm.parallel' "$T/pip.log")"
else
    echo "$TEST: no MPI: pcdm.parallel not built, not tested"
fi
finish
