#!/usr/bin/env bash
# Builds icgm_slam in a catkin workspace (default <repo>/.ws, not committed), Release, with tests.
# Incremental: a second run only rebuilds what changed. Exports compile_commands.json to the repo.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
mkdir -p "${ICGM_WS}/src"
[ -e "${ICGM_WS}/src/icgm_slam" ] || ln -s "${ICGM_ROOT}" "${ICGM_WS}/src/icgm_slam"
[ -e "${ICGM_WS}/src/CMakeLists.txt" ] || ln -s /usr/share/catkin/cmake/toplevel.cmake "${ICGM_WS}/src/CMakeLists.txt"
mkdir -p "${ICGM_WS}/build"
cd "${ICGM_WS}/build"
if [ ! -f Makefile ]; then
  icgm_log "configuring workspace ${ICGM_WS}"
  cmake "${ICGM_WS}/src" \
    -DCMAKE_BUILD_TYPE=Release \
    -DCATKIN_DEVEL_PREFIX="${ICGM_WS}/devel" \
    -DCMAKE_INSTALL_PREFIX="${ICGM_WS}/install" \
    -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 \
    -DCATKIN_ENABLE_TESTING=ON -DCMAKE_EXPORT_COMPILE_COMMANDS=ON > cmake.log 2>&1 \
    || { cat cmake.log; exit 1; }
fi
icgm_log "building (${ICGM_JOBS} jobs)"
if ! make -j"${ICGM_JOBS}" "$@" > make.log 2>&1; then
  grep -E -B2 -A8 "error:|Error [0-9]|undefined reference" make.log | head -80
  icgm_log "build failed (full log: ${ICGM_WS}/build/make.log)"
  exit 1
fi
grep -c "warning:" make.log | xargs -I{} echo "[icgm] {} compiler warnings (see ${ICGM_WS}/build/make.log)" >&2 || true
ln -sf "${ICGM_WS}/build/compile_commands.json" "${ICGM_ROOT}/compile_commands.json"
icgm_log "build ok"
