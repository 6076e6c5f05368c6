#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang (AddressSanitizer + UndefinedBehaviorSanitizer)
# and runs each for FUZZ_SECONDS on a copy of its seed corpus (fuzz/corpus/<target>/). Prints one
# line per target (runs, coverage, new corpus entries) and a verdict; exits 1 when a target found a
# crash, a hang (one input over 10 s), an out-of-memory (2 GB) or a leak, printing the reproducer
# (or when a run failed without one), 2 when the build fails. The last line is "N passed, N failed"
# with one case per target (CI adds it to the tests' count).
#   scripts/run_fuzz.sh [target ...]   (default: every target; `make fuzz` runs this)
# Environment: FUZZ_SECONDS (30 per target), FUZZ_JOBS (2, build jobs),
#   FUZZ_BUILD_DIR (catkin_ws/build_fuzz, git-ignored; runs in <build dir>/run/<target>/).
# Reproduce a finding: <build dir>/fuzz_<target> <reproducer>. Add it to fuzz/corpus/<target>/
# once fixed, with a gtest of the owning package.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${FUZZ_SECONDS:-30}"
jobs="${FUZZ_JOBS:-2}"
build="${FUZZ_BUILD_DIR:-$root/catkin_ws/build_fuzz}"
all=(oi_parsers sim_robot rig_parser scene_parser decoder_image decoder_rig cloud_conversion)
targets=("$@")
[[ $# -gt 0 ]] || targets=("${all[@]}")
for t in "${targets[@]}"; do
  [[ -d "$root/fuzz/corpus/$t" ]] || { echo "run_fuzz: unknown target '$t' (${all[*]})" >&2; exit 2; }
done
if ! command -v clang++ > /dev/null; then
  echo "run_fuzz: clang++ not found; \`make deps\` installs clang (scripts/debian_packages.txt)" >&2
  exit 2
fi

start=$(date +%s)
mkdir -p "$build"
if ! { cmake -S "$root/fuzz" -B "$build" -DCMAKE_CXX_COMPILER=clang++ &&
       cmake --build "$build" -j "$jobs" --target "${targets[@]/#/fuzz_}"; } > "$build/build.log" 2>&1; then
  tail -n 40 "$build/build.log"
  echo "run_fuzz: build failed (full log: $build/build.log)"
  echo "0 passed, 1 failed"
  exit 2
fi
echo "fuzz: built ${#targets[@]} target(s) in $(( $(date +%s) - start )) s (log: $build/build.log); ${seconds} s each"

export UBSAN_OPTIONS="print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
failed=()
for t in "${targets[@]}"; do
  dir="$build/run/$t"
  rm -rf "$dir"
  mkdir -p "$dir/corpus" "$dir/artifacts"
  cp "$root/fuzz/corpus/$t/"* "$dir/corpus/"
  seeds=$(ls "$dir/corpus" | wc -l)
  dict=()
  case "$t" in
    rig_parser | decoder_rig) dict=(-dict="$root/fuzz/dicts/rig.dict") ;;
    scene_parser) dict=(-dict="$root/fuzz/dicts/scene.dict") ;;
  esac
  # The outer timeout only guards against a hang outside libFuzzer's own per-input -timeout.
  timeout --signal=KILL $((seconds + 300)) "$build/fuzz_$t" -max_total_time="$seconds" -timeout=10 \
    -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$dir/artifacts/" "${dict[@]}" "$dir/corpus" \
    > "$dir/fuzz.log" 2>&1
  rc=$?
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$dir/fuzz.log" | tail -n 1)
  cov=$(grep -oE 'cov: [0-9]+ ft: [0-9]+' "$dir/fuzz.log" | tail -n 1)
  corpus=$(( $(ls "$dir/corpus" | wc -l) - seeds ))
  reproducer=$(ls "$dir/artifacts/" 2> /dev/null | grep -E '^(crash|timeout|oom|leak)-' | head -n 1)
  summary="${runs:-?} runs, ${cov:-cov: ?}, +$corpus corpus"
  if [[ -n "$reproducer" ]]; then
    failed+=("$t")
    why=$(grep -m 1 -E 'FUZZ_CHECK failed|^SUMMARY:|ERROR: libFuzzer|runtime error:' "$dir/fuzz.log")
    echo "fuzz $t: ${reproducer%%-*} after $summary: $why"
    echo "  reproducer: $dir/artifacts/$reproducer"
    echo "  rerun:      $build/fuzz_$t $dir/artifacts/$reproducer   (log: $dir/fuzz.log)"
  elif [[ $rc -ne 0 ]]; then
    failed+=("$t")
    echo "fuzz $t: exited with $rc and no reproducer after $summary (log: $dir/fuzz.log)"
    tail -n 5 "$dir/fuzz.log" | sed 's/^/  /'
  else
    echo "fuzz $t: ok, $summary"
  fi
done

total=$(( $(date +%s) - start ))
if [[ ${#failed[@]} -gt 0 ]]; then
  echo "fuzz: FAILED in ${#failed[@]} of ${#targets[@]} target(s): ${failed[*]} (${total} s)"
  echo "$(( ${#targets[@]} - ${#failed[@]} )) passed, ${#failed[@]} failed"
  exit 1
fi
echo "fuzz: no crash, hang, out-of-memory or leak in ${#targets[@]} target(s), ${seconds} s each (${total} s)"
echo "${#targets[@]} passed, 0 failed"
