#!/usr/bin/env bash
# Runs every test: core gtests, ROS bridge gtests and rostests of the nodelets.
# Installs missing packages and builds first (both idempotent). Exits non-zero on any failure.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
"${ICGM_ROOT}/launch_scripts/setup.sh"
"${ICGM_ROOT}/launch_scripts/build.sh"
"${ICGM_ROOT}/launch_scripts/build.sh" tests
icgm_source_ws
cd "${ICGM_WS}/build"
results="${ICGM_WS}/build/test_results"
rm -rf "${results}"
icgm_log "running tests"
# run_tests never fails by itself; the verdict comes from the result files below. A test binary
# that crashes leaves no result file, which catkin_test_results reports as a missing result.
# The gtests share no files and run two at a time. Each rostest starts its own ROS master; those
# whose replay waits for the pipeline run two at a time too, those paced by the wall clock (a
# bag or a device played in real time) one after another with nothing else running
# (test/ros/tests.cmake, icgm_add_rostest's LANE).
make run_tests_icgm_slam_gtest -j2 > run_tests.log 2>&1 || true
make icgm_run_rostests_parallel -j2 >> run_tests.log 2>&1 || true
make icgm_run_rostests_alone run_tests_icgm_slam_roslaunch-check -j1 >> run_tests.log 2>&1 || true
grep -E "^\[ *(RUN|OK|FAILED|PASSED|SKIPPED) *\]|FAILURE|process has died|Exception" run_tests.log \
  | grep -v -E "^\[ *(RUN|OK) *\]" || true
summary=$(catkin_test_results --all "${results}" 2>&1) && status=0 || status=$?
echo "${summary}" | grep -v -E "^Skipping" | tail -n 25
line=$(echo "${summary}" | grep -E "^Summary:" | tail -1)
tests=$(echo "${line}" | sed -E 's/.*Summary: ([0-9]+) tests.*/\1/')
errors=$(echo "${line}" | sed -E 's/.* ([0-9]+) errors.*/\1/')
failures=$(echo "${line}" | sed -E 's/.* ([0-9]+) failures.*/\1/')
skipped=$(echo "${line}" | sed -E 's/.* ([0-9]+) skipped.*/\1/')
if [ -z "${line}" ]; then
  icgm_log "no test results found"
  exit 1
fi
failed=$((errors + failures))
passed=$((tests - failed - skipped))
echo "${passed} passed, ${failed} failed, ${skipped} skipped"
if [ "${status}" -ne 0 ] || [ "${failed}" -ne 0 ] || [ "${tests}" -eq 0 ]; then
  /usr/bin/python3 "${ICGM_ROOT}/launch_scripts/test_failures.py" "${results}" || true
  icgm_log "TESTS FAILED (log: ${ICGM_WS}/build/run_tests.log)"
  exit 1
fi
icgm_log "all tests passed"
