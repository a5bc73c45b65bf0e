#!/bin/sh
# Installs the build's dependencies from Debian packages when they are missing; silent otherwise.
# Needs: mpicc/mpirun (Open MPI), Check (pkg-config check), METIS 5 (libmetis-dev).
set -e
missing=""
command -v mpicc >/dev/null 2>&1 || missing="$missing openmpi-bin libopenmpi-dev"
command -v mpirun >/dev/null 2>&1 || missing="$missing openmpi-bin"
command -v pkg-config >/dev/null 2>&1 || missing="$missing pkg-config"
pkg-config --exists check 2>/dev/null || missing="$missing check"
command -v make >/dev/null 2>&1 || missing="$missing make"
[ -e /usr/include/metis.h ] || missing="$missing libmetis-dev"
[ -z "$missing" ] && exit 0
echo "deps: installing$missing"
if [ "$(id -u)" -eq 0 ]; then SUDO=""; else SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# shellcheck disable=SC2086
$SUDO apt-get install -y -qq --no-install-recommends $missing gcc libc6-dev >/dev/null
echo "deps: done"
