#!/usr/bin/env bash
# make test-unit: the edit-test loop. Builds and runs the gtest binary of each package (the
# ROS-free cores; no roscore, no rostest, no simulation), prints the failed cases and
# "N passed, N failed" (exit 0 only if all passed). make test runs these and everything else.
set -uo pipefail
ws="$1"; jobs="${2:-2}"
export PATH=/usr/bin:/bin:$PATH PYTHONNOUSERSITE=1
unset PYTHONPATH PYTHONHOME
# shellcheck disable=SC1091
source "$(dirname "$0")/gtest_targets.sh"
log="$ws/unit_build.log"
if ! catkin_make -C "$ws" -j"$jobs" "${gtest_targets[@]}" > "$log" 2>&1; then
  tail -n 40 "$log"; echo "unit test build failed (log: $log)"; echo "0 passed, 1 failed"; exit 1
fi
set +u
# shellcheck disable=SC1091
source "$ws/devel/setup.bash"
set -u
results="$ws/build/unit_results"
rm -rf "$results"; mkdir -p "$results"
status=0
for t in "${gtest_targets[@]}"; do
  bin="$(find "$ws/devel/lib" -name "$t" -type f | head -n 1)"
  if [[ -z "$bin" ]]; then
    echo "FAILED $t: not built"; status=1; continue
  fi
  if ! "$bin" --gtest_output="xml:$results/$t.xml" > "$results/$t.log" 2>&1; then
    status=1
    echo "--- $t (log: $results/$t.log)"
    grep -E -B2 -A8 'Failure|FAILED  \]' "$results/$t.log" | head -n 40
    [[ -s "$results/$t.xml" ]] || printf '<testsuites><testsuite><testcase classname="%s" name="crashed"><failure message="no result"/></testcase></testsuite></testsuites>\n' "$t" > "$results/$t.xml"
  fi
done
summary="$(/usr/bin/python3 "$(dirname "$0")/test_summary.py" "$results")"
echo "$summary"
[[ $status -eq 0 ]]
