#!/usr/bin/env bash
# make test-asan: builds every package's gtest binary with AddressSanitizer and
# UndefinedBehaviorSanitizer (-fno-sanitize-recover=undefined: any UB aborts the test) in a build
# tree of its own (catkin_ws/build_asan, catkin_ws/devel_asan; the normal build is untouched),
# runs them, and prints the failed cases and "N passed, N failed" (exit 0 only if all passed).
# Leak checking is off: Debian's OpenCV and yaml-cpp keep static allocations that LeakSanitizer
# would report from every binary.
set -uo pipefail
ws="$1"; jobs="${2:-2}"
export PATH=/usr/bin:/bin:$PATH PYTHONNOUSERSITE=1
unset PYTHONPATH PYTHONHOME
sanitize="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
# shellcheck disable=SC1091
source "$(dirname "$0")/gtest_targets.sh"
log="$ws/asan_build.log"
if ! catkin_make -C "$ws" --build "$ws/build_asan" -DCATKIN_DEVEL_PREFIX="$ws/devel_asan" -j"$jobs" \
    -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=ON \
    -DCMAKE_CXX_FLAGS="$sanitize" -DCMAKE_C_FLAGS="$sanitize" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" \
    "${gtest_targets[@]}" > "$log" 2>&1; then
  tail -n 40 "$log"; echo "sanitizer build failed (log: $log)"; echo "0 passed, 1 failed"; exit 1
fi
# The tests find packages (rospack) and data through the sanitized workspace's environment.
set +u
# shellcheck disable=SC1091
source "$ws/devel_asan/setup.bash"
set -u
results="$ws/build_asan/asan_results"
rm -rf "$results"; mkdir -p "$results"
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=0:halt_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
status=0
# A sanitizer abort leaves no XML: it counts as one failed case.
run_gtests "$ws/devel_asan/lib" "$results" "sanitizer or test failure; " "-A12" \
  'ERROR: AddressSanitizer|runtime error|FAILED  \]' sanitizer || status=1
summary="$(/usr/bin/python3 "$(dirname "$0")/test_summary.py" "$results")"
echo "$summary"
[[ $status -eq 0 ]]
