# The gtest binary of each package (one per package), and how make test-unit and make test-asan
# run them.
# shellcheck disable=SC2034
gtest_targets=(sl_rig_test sl_projector_test sl_camera_test sl_sim_test sl_decoder_test sl_calibration_test sl_evaluation_test
               sl_obstacle_test sl_navigation_test create_driver_test sl_bringup_test sl_testing_test)

# run_gtests LIB_DIR RESULTS WHAT CONTEXT PATTERN CASE: runs every binary of gtest_targets found under
# LIB_DIR, its XML and log in RESULTS. On a failure it prints "--- <target> (WHAT log: ...)" and the
# log's lines matching PATTERN (grep CONTEXT, e.g. "-A12"), and, when the binary left no XML (a crash
# or a sanitizer abort), writes one failed case named CASE. Returns 1 when any failed or is not built.
run_gtests() {
  local lib="$1" results="$2" what="$3" context="$4" pattern="$5" case_name="$6" status=0 t bin
  for t in "${gtest_targets[@]}"; do
    bin="$(find "$lib" -name "$t" -type f | head -n 1)"
    if [[ -z "$bin" ]]; then
      echo "FAILED $t: not built"; status=1; continue
    fi
    if ! "$bin" --gtest_output="xml:$results/$t.xml" > "$results/$t.log" 2>&1; then
      status=1
      echo "--- $t (${what}log: $results/$t.log)"
      # shellcheck disable=SC2086
      grep -E $context "$pattern" "$results/$t.log" | head -n 40
      [[ -s "$results/$t.xml" ]] || printf '<testsuites><testsuite><testcase classname="%s" name="%s"><failure message="no result"/></testcase></testsuite></testsuites>\n' "$t" "$case_name" > "$results/$t.xml"
    fi
  done
  return $status
}
