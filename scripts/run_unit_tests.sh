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
run_gtests "$ws/devel/lib" "$results" "" "-B2 -A8" 'Failure|FAILED  \]' crashed || status=1
summary="$(/usr/bin/python3 "$(dirname "$0")/test_summary.py" "$results")"
echo "$summary"
[[ $status -eq 0 ]]
