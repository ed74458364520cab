#!/usr/bin/env bash
# Runs tests of the sanitized build (build/sanitize, -DDEMBRIDGE_SANITIZE=ON) with the sanitizers'
# run-time options; used by './dembridge sanitize' and by the ctest entries sanitize.unit and
# sanitize.inprocess of the ordinary build.
#   tests/sanitize/run_layer.sh <sanitized build dir> <ctest -R regex> [more ctest arguments]
# ASan stops a process at its first error, UBSan too (halt_on_error=1; the code is also compiled with
# -fno-sanitize-recover=undefined), LSan fails a process at exit. Reports go to files (log_path), not
# only to the failing process: a child whose exit status a test ignores (an lmp run expected to stop
# on an ERROR, a rank under mpiexec) still fails the layer. The in-process Python entries add
# LD_PRELOAD and their own leak setting (tests/sanitize/CMakeLists.txt).
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
dir="$(cd "$1" && pwd)"; regex="$2"; shift 2
reports="$(mktemp -d "$dir/sanitizer-reports.XXXXXX")"
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1:detect_odr_violation=2:log_path=$reports/asan"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:log_path=$reports/ubsan"
export LSAN_OPTIONS="suppressions=$here/lsan.supp:print_suppressions=0"
ctest --test-dir "$dir" --output-on-failure --no-tests=error -j "${DEMBRIDGE_JOBS:-2}" -R "$regex" "$@"
status=$?
found=$(find "$reports" -type f | sort)
if [ -n "$found" ]; then
  for f in $found; do echo "== sanitizer report $f"; cat "$f"; done
  echo "sanitizer layer: $(echo "$found" | wc -l) report(s) above (kept in $reports)"
  exit 1
fi
rmdir "$reports"
exit $status
