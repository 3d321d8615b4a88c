# Shared by the setup/build/test/demo scripts. Source it; do not run it.
# Finds the repo, keeps the system python first on PATH (catkin needs the Debian python3 with
# its ROS modules, not a user python) and defines the workspace location.
set -euo pipefail
ICGM_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
# The catkin workspace lives outside version control, next to the sources.
ICGM_WS="${ICGM_WS:-${ICGM_ROOT}/.ws}"
ICGM_OUT="${ICGM_OUT:-${ICGM_ROOT}/out}"
ICGM_JOBS="${ICGM_JOBS:-$(nproc)}"
export ROS_HOME="${ROS_HOME:-${ICGM_WS}/ros_home}"
export ROS_LOG_DIR="${ROS_LOG_DIR:-${ROS_HOME}/log}"

icgm_log() { printf '\033[1;34m[icgm]\033[0m %s\n' "$*" >&2; }

icgm_source_ws() {
  # setup.bash reads unset variables; relax -u while sourcing.
  set +u
  # shellcheck disable=SC1091
  source "${ICGM_WS}/devel/setup.bash"
  set -u
}
