#!/bin/sh
# Runs the LAMMPS of the own-LAMMPS layer (build_layer.sh) under Debian's Open MPI:
#   run_own_lammps.sh <layer dir> <ranks> lmp-arguments...
# Its lmp finds liblammps through LD_LIBRARY_PATH (an install without RPATH, as 'cmake --install' leaves it).
set -eu
dir="$1"; ranks="$2"; shift 2
root=""; [ "$(id -u)" = 0 ] && root="--allow-run-as-root"  # CI runs as root
LD_LIBRARY_PATH="$dir/prefix/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" OMP_NUM_THREADS=1 \
  exec mpirun.openmpi $root --oversubscribe -x LD_LIBRARY_PATH -x OMP_NUM_THREADS -np "$ranks" "$dir/prefix/bin/lmp" "$@"
