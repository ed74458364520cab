#!/bin/sh
# Run before the plugin is linked, on its object files: every reference to a LAMMPS symbol (LAMMPS_NS) is
# made weak. A plugin built for another LAMMPS version then still loads when one of those symbols is absent
# from the host's liblammps (the dynamic loader would refuse it, and LAMMPS's 'plugin load' only warns), and
# its entry point refuses the version with an ERROR naming both before anything of it runs.
# Symbols the host has resolve as before. Idempotent: an object with no strong LAMMPS reference left is not touched.
#   weaken_lammps_references.sh OBJCOPY NM object.o...
set -eu
objcopy="$1"; nm="$2"; shift 2
for o in "$@"; do
  syms="$("$nm" --undefined-only "$o" | awk '$1 == "U" && $2 ~ /9LAMMPS_NS/ { print $2 }')"
  [ -n "$syms" ] || continue
  list="$o.weaken"
  printf '%s\n' "$syms" >"$list"
  "$objcopy" --weaken-symbols="$list" "$o"
  rm -f "$list"
done
