#!/usr/bin/env bash
# Builds icgm_slam in a catkin workspace (default <repo>/.ws, not committed), Release, with tests.
# Incremental: a second run only rebuilds what changed. Exports compile_commands.json to the repo.
# Shows make's percentage, the elapsed time and the file being compiled at most every
# ICGM_PROGRESS_S seconds (default 5; a first build takes about 12 minutes on 2 cores); the full
# output goes to <ws>/build/make.log, and on failure the errors are printed from it.
# ICGM_CMAKE_ARGS adds arguments to the first configure (e.g. a compiler launcher such as ccache).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
ICGM_PROGRESS_S="${ICGM_PROGRESS_S:-5}"

# Reads make's output on stdin and reports progress on stderr: one line per report, or one
# line updated in place on a terminal. Also reports while a long compile prints nothing.
icgm_progress() {
  local start=${SECONDS} last=${SECONDS} pct="  0" what="" buf="" chunk="" line="" status=0
  local tty=0
  [ -t 2 ] && tty=1
  report() {
    local elapsed=$((SECONDS - start))
    local text
    text=$(printf '[icgm] %s%% %3dm%02ds %s' "${pct}" $((elapsed / 60)) $((elapsed % 60)) "${what}")
    if [ "${tty}" -eq 1 ]; then printf '\r\033[K%s' "${text:0:$(( $(tput cols 2>/dev/null || echo 100) - 1 ))}" >&2
    else printf '%s\n' "${text}" >&2; fi
    last=${SECONDS}
  }
  while :; do
    if IFS= read -r -t "${ICGM_PROGRESS_S}" chunk; then
      status=0
      line="${buf}${chunk}"
      buf=""
    else
      status=$?
      if [ "${status}" -gt 128 ]; then  # timed out: nothing printed for a while
        buf+="${chunk}"
        report
        continue
      fi
      line="${buf}${chunk}"
      [ -z "${line}" ] && break
      buf=""
    fi
    if [[ "${line}" =~ ^\[\ *([0-9]+)%\]\ (.*)$ ]]; then
      pct=$(printf '%3d' "${BASH_REMATCH[1]}")
      what="${BASH_REMATCH[2]}"
      # "Building CXX object .../src/core/map/map_store.cpp.o" -> "building map_store.cpp"
      if [[ "${what}" =~ ^Building\ [A-Z]+\ object\ .*/([^/]+)\.o$ ]]; then
        what="building ${BASH_REMATCH[1]}"
      elif [[ "${what}" =~ ^Linking\ .*\ ([^ ]*/)?([^/ ]+)$ ]]; then
        what="linking ${BASH_REMATCH[2]}"
      fi
    fi
    if [ $((SECONDS - last)) -ge "${ICGM_PROGRESS_S}" ]; then report; fi
    [ "${status}" -ne 0 ] && break
  done
  cat > /dev/null  # never close the pipe on make
  if [ "${tty}" -eq 1 ]; then printf "\r\033[K" >&2; elif [ "${last}" -ne "${SECONDS}" ]; then report; fi
  return 0
}

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
    -DCATKIN_ENABLE_TESTING=ON -DCMAKE_EXPORT_COMPILE_COMMANDS=ON ${ICGM_CMAKE_ARGS:-} > cmake.log 2>&1 \
    || { cat cmake.log; exit 1; }
fi
icgm_log "building (${ICGM_JOBS} jobs${*:+, $*}; full log: ${ICGM_WS}/build/make.log)"
build_start=${SECONDS}
if ! make -j"${ICGM_JOBS}" "$@" 2>&1 | tee make.log | icgm_progress; then
  grep -E -B2 -A8 "error:|Error [0-9]|undefined reference" make.log | head -80
  icgm_log "build failed after $(( (SECONDS - build_start) / 60 ))m$(( (SECONDS - build_start) % 60 ))s (full log: ${ICGM_WS}/build/make.log)"
  exit 1
fi
grep -c "warning:" make.log | xargs -I{} echo "[icgm] {} compiler warnings (see ${ICGM_WS}/build/make.log)" >&2 || true
ln -sf "${ICGM_WS}/build/compile_commands.json" "${ICGM_ROOT}/compile_commands.json"
icgm_log "build ok in $(( (SECONDS - build_start) / 60 ))m$(( (SECONDS - build_start) % 60 ))s"
