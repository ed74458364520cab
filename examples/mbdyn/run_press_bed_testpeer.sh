#!/usr/bin/env bash
# Case a without MBDyn: the test peer plays press_bed.mbd (plate of 0.5 kg thrown down at 0.5 m/s
# under gravity, trapezoidal rule, 2000 steps of 1e-4 s); then plot_press_bed.py.
#   BUILD=/path/to/build ./run_press_bed_testpeer.sh
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
rm -f mbdyn.sock
"$TESTPEER" --path mbdyn.sock --nodes 1 --orientation none --coupling loose \
    --steps 2000 --dt 1e-4 --mass 0.5 --gravity 0,0,-9.81 --x0 0,0,0.08 --v0 0,0,-0.5 \
    --accept-timeout 120 --io-timeout 120 --trajectory press_bed_mbdyn.txt &
PEER=$!
"$LMP" -in in.press_bed "${PLUGIN[@]}" -var sock mbdyn.sock \
    -log press_bed.log -nocite
wait $PEER
"$PYTHON" plot_press_bed.py press_bed_mbdyn.txt press_bed_lammps.txt press_bed.png
