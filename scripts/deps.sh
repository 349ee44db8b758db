#!/usr/bin/env bash
# Installs the Debian packages massid needs to build and test, skipping those
# already present. Safe to run repeatedly; needs root (or sudo) for apt-get.
set -euo pipefail
pkgs=(build-essential cmake libeigen3-dev liburdfdom-dev libtinyxml2-dev nlohmann-json3-dev
      libcli11-dev libfast-float-dev libfmt-dev libceres-dev libgtest-dev libbenchmark-dev
      libmujoco-dev libqhull-dev libgl-dev liborocos-kdl-dev python3-numpy
      clang libclang-rt-14-dev  # clang + its sanitizer and libFuzzer runtimes: scripts/test.sh
      pybind11-dev python3-dev python3-matplotlib  # the Python package and --report
      python3-pytest chromium)  # its tests: pytest, and the report in headless Chromium
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "Installing: ${missing[*]}"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
