#!/usr/bin/env bash
# The on-demand long run of the MBDyn protocol fuzzer (libFuzzer, ASan + UBSan): N executions (default
# 10^7) at low priority (nice DEMBRIDGE_FUZZ_NICE, default 10), split over DEMBRIDGE_FUZZ_WORKERS processes (default 1) with distinct seeds that
# share one corpus. Prints the figures doc/mbdyn_protocol_library.md reports.
#   coupling/fuzz/long_run.sh <fuzzer binary> [executions]
set -euo pipefail
fuzzer="$1"
runs="${2:-10000000}"
workers="${DEMBRIDGE_FUZZ_WORKERS:-1}"
work="${DEMBRIDGE_FUZZ_DIR:-$(dirname "$fuzzer")/long_run}"
mkdir -p "$work/corpus"
per=$(( (runs + workers - 1) / workers ))
start=$(date +%s)
pids=()
for w in $(seq 1 "$workers"); do
  nice -n "${DEMBRIDGE_FUZZ_NICE:-10}" "$fuzzer" -seed="$w" -runs="$per" -max_len=512 -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -reload=1 "$work/corpus" > "$work/worker_$w.log" 2>&1 &
  pids+=($!)
done
status=0
for p in "${pids[@]}"; do wait "$p" || status=1; done
end=$(date +%s)
total=0
for w in $(seq 1 "$workers"); do
  n=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/worker_$w.log")
  total=$(( total + ${n:-0} ))
  grep -E '^(stat::|Done|==[0-9]+==ERROR|SUMMARY)' "$work/worker_$w.log" | sed "s/^/worker $w: /"
done
cov=$(grep -ho 'cov: [0-9]*' "$work"/worker_*.log | awk '{print $2}' | sort -n | tail -1)
ft=$(grep -ho 'ft: [0-9]*' "$work"/worker_*.log | awk '{print $2}' | sort -n | tail -1)
secs=$((end - start))
echo "fuzz long run: $total executions in $secs s ($(( total / (secs > 0 ? secs : 1) )) exec/s) by $workers worker(s)," \
     "max coverage ${cov:-?} edges / ${ft:-?} features, corpus $(ls "$work/corpus" | wc -l) inputs," \
     "status $([ $status = 0 ] && echo clean || echo FAILED)"
exit $status
