#!/usr/bin/env bash
# Live pipeline vs offline front end: replays a bag through the nodelets on simulated time at
# several rates (test/ros/live_offline.test with check:=false) and prints, per rate, the frames
# that got a relative pose, the ATE of the fused odometry next to the offline front end's on the
# same bag, and the nodelet manager's CPU per frame next to the offline front end's, then where
# the frames went stage by stage (received, skipped by the backpressure, extracted, paired with
# depth, dropped, processed, relative poses).
#   bash launch_scripts/benchmark_live.sh [BAG] [RATES...] [--repeat N] [name:=value...]
# name:=value arguments go to live_offline.test, e.g. max_frames_in_flight:=0 (no backpressure).
# paced_offline:=true also feeds the offline front end at the replay's pace (frames no sooner than
# their bag time over the rate, as the nodelets get them) and prints the ratio to that as well.
# --repeat N (default 1) plays every rate N times, the rates in turn, and ends with the median of
# the CPU ratios per rate: one run's ratio moves by +-15% with the machine's load, because the
# offline front end's own CPU per frame does.
# Defaults: rosbags/crowded.bag (rendered with icgm_sim if missing), rates 1 2 4 8. Expects a
# build with tests (icgm_build tests, or launch_scripts/build.sh tests).
#   bash launch_scripts/benchmark_live.sh --driver [FRAMES] [RATES...] [--repeat N]
# The robot's configuration instead: the OpenNI2 driver nodelet in the pipeline's manager on the
# virtual device playing the first FRAMES (default 300) of ../shared/data/tum_fr1_xyz at each
# rate (default 1), so the images reach the nodelets without serialization (test/ros/
# openni2_tum.test with cpu_report:=true); the manager's CPU per fused pose, the virtual
# device's decoding thread left out, against the offline front end on the same frames.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
icgm_source_ws
BIN="${ICGM_WS}/devel/lib/icgm_slam"
if [ "${1:-}" = "--driver" ]; then
  shift
  FRAMES=300
  if [[ "${1:-}" =~ ^[1-9][0-9]*$ ]]; then FRAMES="$1"; shift; fi
  TUM_DIR="$(realpath -m "${ICGM_ROOT}/../shared/data/tum_fr1_xyz")"
  [ -s "${TUM_DIR}/rgb.txt" ] || { icgm_log "no TUM fr1/xyz at ${TUM_DIR}"; exit 1; }
  DRIVER_RATES=()
  DRIVER_REPEAT=1
  DRIVER_ARGS=()
  while [ $# -gt 0 ]; do
    case "$1" in
      --repeat) DRIVER_REPEAT="${2:-}"; shift 2 ;;
      *:=*) DRIVER_ARGS+=("$1"); shift ;;
      *) [[ "$1" =~ ^[0-9]+([.][0-9]+)?$ ]] || { icgm_log "not a rate: $1"; exit 2; }
         DRIVER_RATES+=("$1"); shift ;;
    esac
  done
  [[ "${DRIVER_REPEAT}" =~ ^[1-9][0-9]*$ ]] || { icgm_log "--repeat needs a count >= 1"; exit 2; }
  [ ${#DRIVER_RATES[@]} -gt 0 ] || DRIVER_RATES=(1)
  REPORT="$(mktemp /tmp/icgm_driver_benchmark.XXXXXX)"
  for ((run = 1; run <= DRIVER_REPEAT; ++run)); do
    for rate in "${DRIVER_RATES[@]}"; do
      icgm_log "driver in the manager, rate ${rate} (run ${run} of ${DRIVER_REPEAT})"
      rostest icgm_slam openni2_tum.test tum_dir:="${TUM_DIR}" frames:="${FRAMES}" \
        rate:="${rate}" offline_tool:="${BIN}/icgm_slam_offline" cpu_report:=true \
        report:="${REPORT}" ${DRIVER_ARGS[@]+"${DRIVER_ARGS[@]}"} > /dev/null 2>&1 ||
        icgm_log "rate ${rate}: rostest failed"
    done
  done
  cat "${REPORT}"
  rm -f "${REPORT}"
  exit 0
fi
BAG="${1:-${ICGM_ROOT}/rosbags/crowded.bag}"
BAG="$(realpath -m "${BAG}")"  # the test node runs in another directory
shift || true
RATES=()
ARGS=()
REPEAT=1
while [ $# -gt 0 ]; do
  case "$1" in
    --repeat)
      REPEAT="${2:-}"
      [[ "${REPEAT}" =~ ^[1-9][0-9]*$ ]] || { icgm_log "--repeat needs a count >= 1"; exit 2; }
      shift 2 ;;
    *:=*) ARGS+=("$1"); shift ;;
    *)
      [[ "$1" =~ ^[0-9]+([.][0-9]+)?$ ]] || { icgm_log "not a rate: $1"; exit 2; }
      RATES+=("$1"); shift ;;
  esac
done
[ ${#RATES[@]} -gt 0 ] || RATES=(1 2 4 8)
if [ ! -s "${BAG}" ]; then
  icgm_log "rendering ${BAG}"
  mkdir -p "$(dirname "${BAG}")"
  "${BIN}/icgm_sim" --config "${ICGM_ROOT}/config/sim/crowded.yaml" --out "${BAG}"
fi
[ -x "${BIN}/icgm_rostests" ] || { icgm_log "build the tests first (icgm_build tests)"; exit 1; }
REPORT="$(mktemp /tmp/icgm_live_benchmark.XXXXXX)"
for ((run = 1; run <= REPEAT; ++run)); do
  for rate in "${RATES[@]}"; do
    icgm_log "rate ${rate} (run ${run} of ${REPEAT})"
    rostest icgm_slam live_offline.test bag:="${BAG}" rate:="${rate}" check:=false \
      report:="${REPORT}" ${ARGS[@]+"${ARGS[@]}"} > /dev/null 2>&1 || icgm_log "rate ${rate}: rostest failed"
  done
done
cat "${REPORT}"
if [ "${REPEAT}" -gt 1 ]; then
  # "rate R: ... offline front end X ms (A.AAx), offline with reading the bag Y ms (B.BBx)"
  awk '/^rate [0-9.]+: / {
         r = $2; sub(":", "", r); n = 0
         for (i = 1; i <= NF; ++i) if ($i ~ /^\([0-9.]+x\),?$/) { v = $i; gsub(/[(),x]/, "", v); x[++n] = v }
         if (n == 2) { k = ++count[r]; alone[r, k] = x[1]; read[r, k] = x[2] }
       }
       /^rate [0-9.]+ paced: / {
         r = $2; v = $(NF - 1); gsub(/x/, "", v); k = ++pcount[r]; paced[r, k] = v
       }
       function median(a, r, k,   i, j, t, v) {
         for (i = 1; i <= k; ++i) v[i] = a[r, i]
         for (i = 2; i <= k; ++i) for (j = i; j > 1 && v[j] < v[j - 1]; --j) { t = v[j]; v[j] = v[j - 1]; v[j - 1] = t }
         return k % 2 ? v[(k + 1) / 2] : (v[k / 2] + v[k / 2 + 1]) / 2
       }
       END {
         for (r in count) printf "rate %s: median CPU ratio over %d runs: %.2fx the offline front end, %.2fx with reading the bag\n", r, count[r], median(alone, r, count[r]), median(read, r, count[r])
         for (r in pcount) printf "rate %s: median CPU ratio over %d runs: %.2fx the offline front end fed at the replay'"'"'s pace\n", r, pcount[r], median(paced, r, pcount[r])
       }' "${REPORT}" | sort -t' ' -k2 -n
fi
rm -f "${REPORT}"
