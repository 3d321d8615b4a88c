#!/usr/bin/env bash
# Live pipeline vs offline front end: replays a bag through the nodelets on simulated time at
# several rates (test/ros/live_offline.test with check:=false) and prints, per rate, the frames
# that got a relative pose, the ATE of the fused odometry next to the offline front end's on the
# same bag, and the nodelet manager's CPU per frame next to the offline front end's, then where
# the frames went stage by stage (received, skipped by the backpressure, extracted, paired with
# depth, dropped, processed, relative poses).
#   bash launch_scripts/benchmark_live.sh [BAG] [RATES...] [name:=value...]
# name:=value arguments go to live_offline.test, e.g. max_frames_in_flight:=0 (no backpressure).
# Defaults: rosbags/crowded.bag (rendered with icgm_sim if missing), rates 1 2 4 8. Expects a
# build with tests (icgm_build tests, or launch_scripts/build.sh tests).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
icgm_source_ws
BIN="${ICGM_WS}/devel/lib/icgm_slam"
BAG="${1:-${ICGM_ROOT}/rosbags/crowded.bag}"
BAG="$(realpath -m "${BAG}")"  # the test node runs in another directory
shift || true
RATES=()
ARGS=()
for a in "$@"; do
  if [[ "${a}" == *:=* ]]; then ARGS+=("${a}"); else RATES+=("${a}"); fi
done
[ ${#RATES[@]} -gt 0 ] || RATES=(1 2 4 8)
if [ ! -s "${BAG}" ]; then
  icgm_log "rendering ${BAG}"
  mkdir -p "$(dirname "${BAG}")"
  "${BIN}/icgm_sim" --config "${ICGM_ROOT}/config/sim/crowded.yaml" --out "${BAG}"
fi
[ -x "${BIN}/icgm_rostests" ] || { icgm_log "build the tests first (icgm_build tests)"; exit 1; }
REPORT="$(mktemp /tmp/icgm_live_benchmark.XXXXXX)"
for rate in "${RATES[@]}"; do
  icgm_log "rate ${rate}"
  rostest icgm_slam live_offline.test bag:="${BAG}" rate:="${rate}" check:=false \
    report:="${REPORT}" ${ARGS[@]+"${ARGS[@]}"} > /dev/null 2>&1 || icgm_log "rate ${rate}: rostest failed"
done
cat "${REPORT}"
rm -f "${REPORT}"
