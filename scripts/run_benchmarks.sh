#!/usr/bin/env bash
# Runs the project's Google Benchmark binaries (renderer, decoder, local map and path checks) on one
# core and writes their JSON and console output to bench_results/. Speed is measured here, never
# asserted in tests.
#   make bench            (after make build)
set -uo pipefail
ws="$1"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$root/bench_results"
mkdir -p "$out"
status=0
# taskset pins each run to one core when it is available (the floors are for one core).
pin=()
command -v taskset >/dev/null && pin=(taskset -c 0)
bins=(sl_sim/sl_sim_benchmark sl_evaluation/sl_decoder_benchmark sl_obstacle/sl_obstacle_benchmark
      sl_navigation/sl_navigation_benchmark)
k=0
for bin in "${bins[@]}"; do
  k=$((k + 1))
  exe="$ws/devel/lib/$bin"
  name="$(basename "$bin")"
  if [[ ! -x "$exe" ]]; then
    echo "run_benchmarks: $exe not built (is libbenchmark-dev installed?)" >&2
    status=1
    continue
  fi
  # Progress: each binary takes up to a minute; Google Benchmark prints a line per benchmark.
  echo "== $name (binary $k of ${#bins[@]}, 10 repetitions of each benchmark)"
  if ! "${pin[@]}" "$exe" --benchmark_repetitions=10 --benchmark_report_aggregates_only=true \
      --benchmark_out="$out/$name.json" --benchmark_out_format=json | tee "$out/$name.txt"; then
    echo "run_benchmarks: $name failed" >&2
    status=1
  fi
done
echo "results in $out/"
exit $status
