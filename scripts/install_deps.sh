#!/usr/bin/env bash
# Installs pgba's build and test dependencies from Debian's package registry (idempotent).
set -euo pipefail
PKGS=(build-essential cmake ninja-build pkg-config
      libeigen3-dev libceres-dev libsuitesparse-dev libopengv-dev libopencv-dev
      nlohmann-json3-dev libcli11-dev libtbb-dev libsqlite3-dev libexif-dev libgtest-dev
      libjs-three  # three.js, which report.html inlines for its 3D view (modules/report/CMakeLists.txt)
      chromium)  # chromium: the test that renders report.html headless (tests/apps/report_html_browser_test.cc)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PKGS[@]} packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO=sudo
echo "install_deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
