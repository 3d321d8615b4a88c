#!/usr/bin/env bash
# Installs the Debian packages icgm_slam needs, only those missing (idempotent, fast when done).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
mapfile -t wanted < <(grep -v '^#' "${ICGM_ROOT}/launch_scripts/debian_packages.txt" | tr ' ' '\n' | sed '/^$/d')
missing=()
for p in "${wanted[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  icgm_log "all ${#wanted[@]} Debian packages present"
  exit 0
fi
icgm_log "installing ${#missing[@]} Debian packages: ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
icgm_log "packages installed"
