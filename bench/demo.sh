#!/usr/bin/env bash
# make demo: ./pcdm on 4 ranks on the default domain (data/lake.poly, a lake with two islands),
# writing the mesh (Triangle format), a VTK file for ParaView and an SVG picture coloured by rank.
set -euo pipefail
cd "$(dirname "$0")/.."
out=out/demo
mkdir -p "$out"
if [ "$(id -u)" -eq 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
np=${NP:-4}
area=${AREA:-0.00003} # about 120K triangles
cmd=(mpirun --oversubscribe -np "$np" ./pcdm -q 30 -a "$area" -o "$out/lake" --vtk "$out/lake.pvtu"
     --svg "$out/lake.svg" --stats data/lake.poly)
echo "demo: ${cmd[*]}"
timeout 300 "${cmd[@]}"
./meshcheck data/lake.poly "$out/lake" -q 30 -a "$area"
echo "demo: wrote $out/lake.node $out/lake.ele $out/lake.poly (Triangle format),"
echo "      $out/lake.pvtu + one lake_R.vtu piece per rank (open the .pvtu in ParaView) and $out/lake.svg (open in a browser)"
