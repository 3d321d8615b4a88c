#!/usr/bin/env bash
# The main job, end to end on a new machine: installs missing Debian packages, builds, renders a
# crowded-cafeteria scenario with the simulator into a rosbag, runs the offline SLAM on it with
# and without ICGM, evaluates both against ground truth and draws plots into out/demo/; then
# builds a hybrid map over two laps of the 20 m x 20 m cafeteria (loop closure, eq. 6.2, with the
# pose-graph back end), scores its loop closures and exports its people-free cloud and occupancy
# grid; then the robot drives: a map taught on the crowded cafeteria, two closed-loop drives of
# 12 m through the crowd. With ../shared/data/tum_fr1_xyz present it also maps the real TUM
# fr1/xyz sequence (pose-graph back end as well).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
"${ICGM_ROOT}/launch_scripts/setup.sh"
"${ICGM_ROOT}/launch_scripts/build.sh"
icgm_source_ws
BIN="${ICGM_WS}/devel/lib/icgm_slam"
DEMO="${ICGM_OUT}/demo"
SCENARIO="${ICGM_SCENARIO:-crowded}"
BAG="${ICGM_ROOT}/rosbags/${SCENARIO}.bag"
mkdir -p "${DEMO}" "${ICGM_ROOT}/rosbags"

if [ ! -s "${BAG}" ] || [ "${ICGM_ROOT}/config/sim/${SCENARIO}.yaml" -nt "${BAG}" ] || [ "${BIN}/icgm_sim" -nt "${BAG}" ]; then
  icgm_log "rendering scenario '${SCENARIO}' -> ${BAG}"
  "${BIN}/icgm_sim" --config "${ICGM_ROOT}/config/sim/${SCENARIO}.yaml" --out "${BAG}"
fi
"${BIN}/icgm_bag_info" "${BAG}"

run_and_eval() {  # name, gt, offline args...
  local name="$1" gt="$2"; shift 2
  icgm_log "offline SLAM: ${name}"
  "${BIN}/icgm_slam_offline" "$@" --trajectory "${DEMO}/${name}.txt" | tee "${DEMO}/${name}.log"
  "${BIN}/icgm_eval_traj" --gt "${gt}" --est "${DEMO}/${name}.txt" --plot "${DEMO}/${name}.png" \
    | tee "${DEMO}/${name}.eval"
}

run_and_eval "${SCENARIO}_icgm" "${BAG%.bag}.gt.txt" --bag "${BAG}"
run_and_eval "${SCENARIO}_no_icgm" "${BAG%.bag}.gt.txt" --bag "${BAG}" --no-icgm
# The thesis's fusion (vision whenever registration succeeds): ICGM's effect without the
# project's vision/wheel consistency gate.
run_and_eval "${SCENARIO}_icgm_no_gate" "${BAG%.bag}.gt.txt" --bag "${BAG}" --no-wheel-gate
run_and_eval "${SCENARIO}_no_icgm_no_gate" "${BAG%.bag}.gt.txt" --bag "${BAG}" --no-icgm \
  --no-wheel-gate

icgm_log "hybrid map over two laps of the cafeteria (rendered in process)"
"${BIN}/icgm_slam_offline" --sim "${ICGM_ROOT}/config/sim/two_lap_loop.yaml" \
  --gt-out "${DEMO}/two_lap_gt.txt" --trajectory "${DEMO}/two_lap_map.txt" \
  --map "${DEMO}/two_lap.db" --pose-graph | tee "${DEMO}/two_lap_map.log"
"${BIN}/icgm_eval_traj" --gt "${DEMO}/two_lap_gt.txt" --est "${DEMO}/two_lap_map.txt" \
  --plot "${DEMO}/two_lap_map.png" | tee "${DEMO}/two_lap_map.eval"
"${BIN}/icgm_map_eval" --map "${DEMO}/two_lap.db" --gt "${DEMO}/two_lap_gt.txt" \
  | tee "${DEMO}/two_lap_loops.txt"

icgm_log "people-free cloud and occupancy grid of the two-lap map"
"${BIN}/icgm_map_export" "${DEMO}/two_lap.db" --ply "${DEMO}/two_lap.ply" \
  --grid "${DEMO}/two_lap_grid" | tee "${DEMO}/two_lap_export.log"

icgm_log "closed-loop navigation in the crowded cafeteria (teach run, then two 12 m drives)"
# Time limit 3.6 x 12 m / 0.6 m/s (the controller's top speed) = 72 s per drive.
"${BIN}/icgm_nav_benchmark" --runs 2 --timeout-factor 4.8 --out "${DEMO}/nav" \
  --config "${ICGM_ROOT}/config/sim/nav_cafeteria.yaml" --nav-config "${ICGM_ROOT}/config/navigation.yaml" \
  --slam-config "${ICGM_ROOT}/config" | tee "${DEMO}/nav.log"

TUM="${ICGM_ROOT}/../shared/data/tum_fr1_xyz"
if [ -d "${TUM}" ]; then
  run_and_eval "tum_fr1_xyz_map" "${TUM}/groundtruth.txt" --tum "${TUM}" \
    --camera "${ICGM_ROOT}/config/camera/tum_fr1.yaml" --map "${DEMO}/tum_fr1_xyz.db" --pose-graph
fi

# The real hand-held crowd (Bonn RGB-D Dynamic excerpt: no wheels, people filling the view) with
# the crowd profile, mapped with the hand-held crowd's map profile (loop links to the first
# keyframes, pose graph) with and without ICGM, and with the default configuration for comparison.
BONN="${ICGM_ROOT}/../shared/data/bonn_crowd_excerpt"
if [ -d "${BONN}" ]; then
  run_and_eval "bonn_crowd_profile" "${BONN}/groundtruth.txt" --tum "${BONN}" \
    --camera "${ICGM_ROOT}/config/camera/bonn_xtion.yaml" \
    --config "${ICGM_ROOT}/config/odometry_handheld_crowd.yaml"
  for icgm in "" "--no-icgm"; do
    run_and_eval "bonn_crowd_map${icgm:+_no_icgm}" "${BONN}/groundtruth.txt" --tum "${BONN}" \
      --camera "${ICGM_ROOT}/config/camera/bonn_xtion.yaml" \
      --config "${ICGM_ROOT}/config/odometry_handheld_crowd.yaml" ${icgm} \
      --map "${DEMO}/bonn_crowd${icgm:+_no_icgm}.db" \
      --map-config "${ICGM_ROOT}/config/map_handheld_crowd.yaml"
  done
  run_and_eval "bonn_crowd_default" "${BONN}/groundtruth.txt" --tum "${BONN}" \
    --camera "${ICGM_ROOT}/config/camera/bonn_xtion.yaml"
fi

icgm_log "summary (ATE RMSE after alignment):"
for f in "${DEMO}"/*.eval; do
  printf '  %-28s %s\n' "$(basename "${f%.eval}")" "$(grep -m1 -i "ate.*rmse" "$f" | sed 's/^ *//')"
done
grep -h "^navigation:" "${DEMO}/nav.log" | sed 's/^/  /' || true
icgm_log "plots and trajectories in ${DEMO}"
