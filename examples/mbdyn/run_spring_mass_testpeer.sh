#!/usr/bin/env bash
# Case b without MBDyn: the test peer (coupling/testpeer) plays spring_mass.mbd (m = 2, trapezoidal
# rule, x0 = 0.1, 500 steps of 4 ms), then plot_spring_mass.py compares with the analytic solution.
#   BUILD=/path/to/build ./run_spring_mass_testpeer.sh [substeps]
set -euo pipefail
cd "$(dirname "$0")"
ROOT=$(cd ../.. && pwd)
BUILD=${BUILD:-$ROOT/build}
VENV=${DEMBRIDGE_VENV:-$ROOT/.venv}
# the source tree's build; else a pip install: its commands on PATH, the plugin loaded by lmp itself
if [ -x "$BUILD/coupling/mbdyn_testpeer" ]; then
  TESTPEER="$BUILD/coupling/mbdyn_testpeer" LMP="$VENV/bin/lmp" PYTHON="$VENV/bin/python"
  PLUGIN=(-var plugin "$BUILD/dembridgeplugin.so")
else
  TESTPEER=dembridge-mbdyn-testpeer LMP=lmp PYTHON=python PLUGIN=(-var load no)
fi
N=${1:-1}
rm -f mbdyn.sock
"$TESTPEER" --path mbdyn.sock --nodes 1 --orientation none --coupling loose \
    --steps 500 --dt 0.004 --mass 2 --x0 0.1,0,0 --v0 0,0,0 --trajectory spring_mass_mbdyn.txt &
PEER=$!
"$LMP" -in in.spring_mass "${PLUGIN[@]}" -var sock mbdyn.sock \
    -var substeps "$N" -log spring_mass.log -nocite
wait $PEER
"$PYTHON" plot_spring_mass.py spring_mass_mbdyn.txt spring_mass.png
