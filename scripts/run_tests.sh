#!/usr/bin/env bash
# Builds and runs every test of the workspace (gtest, rostest), then prints the verdict of
# catkin_test_results and one closing line "N passed, N failed". Exit status 0 only if all passed.
set -uo pipefail
ws="$1"; jobs="${2:-2}"
export PATH=/usr/bin:/bin:$PATH PYTHONNOUSERSITE=1
unset PYTHONPATH PYTHONHOME
# shellcheck disable=SC1091
set +u
source "$ws/devel/setup.bash"
set -u
results="$ws/build/test_results"
rm -rf "$results"
log="$ws/test.log"
# Test binaries build in parallel; the tests themselves run one at a time (rostests share ports).
if ! catkin_make -C "$ws" -j"$jobs" tests > "$log" 2>&1; then
  tail -n 60 "$log"; echo "test build failed (log: $log)"; echo "0 passed, 1 failed"; exit 1
fi
catkin_make -C "$ws" -j1 run_tests >> "$log" 2>&1
# catkin_test_results gives the verdict (and lists failing files); the case counts come from the XML.
catkin_test_results --all "$results" > "$ws/test_results.txt" 2>&1
status=$?
grep -E -v '^(Skipping|Summary)|: [0-9]+ tests(, 0 errors, 0 failures.*)?$' "$ws/test_results.txt" || true
# Every test group must have run: a result file missing from the expected set (a package whose
# tests did not build, Aravis missing, a rostest that never started) counts as a failure.
expected="$(dirname "$0")/../test/expected_results.txt"
missing=0
if [[ -f "$expected" ]]; then
  while read -r name; do
    [[ -z "$name" || "$name" == \#* ]] && continue
    if [[ ! -s "$results/$name" ]]; then
      echo "MISSING $name (expected by test/expected_results.txt)"
      missing=$((missing + 1))
    fi
  done < "$expected"
fi
# A rostest that left no results says why only in the run's log (a node that died, a time limit).
if [[ $status -ne 0 || $missing -ne 0 ]]; then
  grep -E 'process has died|terminate called|what\(\):|Segmentation fault|Aborted|time limit|timed out|\[ *FAILED *\]' \
    "$log" | sort | uniq -c | sort -rn | head -n 40 || true
fi
summary="$(/usr/bin/python3 "$(dirname "$0")/test_summary.py" "$results" --missing "$missing")"
summary_status=$?
echo "$summary"
[[ $status -eq 0 && $summary_status -eq 0 ]]
