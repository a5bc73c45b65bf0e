#!/bin/sh
# Installs the build's dependencies from Debian packages when they are missing; silent otherwise.
# Needs: mpicc/mpirun (Open MPI), Check (pkg-config check), METIS 5 (libmetis-dev); with FUZZ=1
# also clang-14 and libFuzzer (libclang-rt-14-dev).
set -e
missing=""
command -v mpicc >/dev/null 2>&1 || missing="$missing openmpi-bin libopenmpi-dev"
command -v mpirun >/dev/null 2>&1 || missing="$missing openmpi-bin"
command -v pkg-config >/dev/null 2>&1 || missing="$missing pkg-config"
pkg-config --exists check 2>/dev/null || missing="$missing check"
command -v make >/dev/null 2>&1 || missing="$missing make"
[ -e /usr/include/metis.h ] || missing="$missing libmetis-dev"
# The Python package (tests/t_python.sh): the headers to build it and venv to install it.
if command -v python3 >/dev/null 2>&1; then
    python3 -c 'import ensurepip, venv' 2>/dev/null || missing="$missing python3-venv"
    [ -e "$(python3 -c 'import sysconfig; print(sysconfig.get_paths()["include"])')/Python.h" ] ||
        missing="$missing python3-dev"
fi
if [ "${FUZZ:-}" = 1 ]; then # make fuzz: clang with libFuzzer and the sanitizer runtimes
    command -v clang-14 >/dev/null 2>&1 || missing="$missing clang-14"
    [ -e /usr/lib/llvm-14/lib/clang/14.0.0/lib/linux/libclang_rt.fuzzer-x86_64.a ] ||
        ls /usr/lib/llvm-14/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1 ||
        missing="$missing libclang-rt-14-dev"
fi
# Optional (tests/t_readers.sh skips without them): the PyPI triangle and meshio readers.  A
# failure to install them is not an error.
if command -v python3 >/dev/null 2>&1 && ! python3 -c 'import triangle, meshio' 2>/dev/null; then
    echo "deps: installing the Python readers triangle and meshio (optional)"
    timeout 300 python3 -m pip install --quiet triangle meshio >/dev/null 2>&1 ||
        echo "deps: could not install triangle/meshio; tests/t_readers.sh will skip"
fi
[ -z "$missing" ] && exit 0
echo "deps: installing$missing"
if [ "$(id -u)" -eq 0 ]; then SUDO=""; else SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# shellcheck disable=SC2086
$SUDO apt-get install -y -qq --no-install-recommends $missing gcc libc6-dev >/dev/null
echo "deps: done"
