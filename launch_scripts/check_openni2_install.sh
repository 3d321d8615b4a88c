#!/usr/bin/env bash
# Checks the OpenNI2 drivers folder of the catkin install space: installs the icgm_openni2
# component (lib/icgm_openni2 with the libOpenNI2 link, the system drivers' links, the virtual
# device driver, the Kinect v1 driver when built, and OpenNI.ini; icgm_openni2_benchmark and the
# ROS bridge library it links) into the workspace's install prefix,
# then runs the installed icgm_openni2_benchmark on the virtual device and checks that OpenNI2
# loaded its library and the virtual driver from the install space (not from the devel space).
# Needs a built workspace (launch_scripts/build.sh icgm_virtual_device icgm_openni2_benchmark).
# Exits 0 when every check passes.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
set -euo pipefail
build="${ICGM_WS}/build"
prefix="$(sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p' "${build}/CMakeCache.txt")"
dir="${prefix}/lib/icgm_openni2"
failed=0
check() {  # check "what" command...
  local what="$1"; shift
  if "$@"; then echo "ok:   ${what}"; else echo "FAIL: ${what}"; failed=1; fi
}

cmake -DCOMPONENT=icgm_openni2 -P "${build}/icgm_slam/cmake_install.cmake" > /dev/null
check "libOpenNI2 link in ${dir}" test -e "${dir}/libOpenNI2.so.0"
check "virtual device driver installed" test -f "${dir}/OpenNI2/Drivers/libicgm_virtual_device.so.0"
check "system drivers linked" test -e "${dir}/OpenNI2/Drivers/libOniFile.so.0"
# The Kinect v1 driver is built only with libfreenect (libfreenect-dev).
if [ -e "${ICGM_WS}/devel/lib/icgm_openni2/OpenNI2/Drivers/libicgm_freenect_device.so.0" ]; then
  check "Kinect v1 (libfreenect) driver installed" test -f "${dir}/OpenNI2/Drivers/libicgm_freenect_device.so.0"
fi
check "OpenNI.ini repository is the installed drivers folder" \
  grep -qx "Repository=${dir}/OpenNI2/Drivers" "${dir}/OpenNI.ini"
bin="$(find "${prefix}/lib" -name icgm_openni2_benchmark -type f | head -1)"
check "icgm_openni2_benchmark installed" test -x "${bin}"
check "installed run path holds ${dir}" \
  bash -c "readelf -d '${bin}' | grep -E 'R(UN)?PATH' | grep -q '${dir}'"

# The installed program on the virtual device (a simulated scenario, looped), with the loader's
# record of the libraries it initialised (the links resolve to the system files they name).
log="$(mktemp)"
uri="icgm-virtual://sim?scenario=${ICGM_ROOT}/config/sim/static_short.yaml&loop=1"
export LD_LIBRARY_PATH="${prefix}/lib${LD_LIBRARY_PATH:+:${LD_LIBRARY_PATH}}"  # as the install space's setup.bash
if LD_DEBUG=libs "${bin}" --uri "${uri}" --frames 10 > "${log}" 2>&1; then ran=0; else ran=1; fi
check "installed benchmark ran on the virtual device" test "${ran}" -eq 0
check "libOpenNI2 loaded from the install space" grep -q "calling init: ${dir}/libOpenNI2.so.0" "${log}"
check "virtual driver loaded from the install space" \
  grep -q "calling init: ${dir}/OpenNI2/Drivers/libicgm_virtual_device.so.0" "${log}"
check "nothing loaded from the devel space's drivers folder" \
  bash -c "! grep -q 'calling init: ${ICGM_WS}/devel/lib/icgm_openni2' '${log}'"
grep "CPU per frame" "${log}" | tail -1 || true
rm -f "${log}"
exit "${failed}"
