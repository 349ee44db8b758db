#!/usr/bin/env bash
# Installs a built massid tree into a staging directory (DESTDIR) and builds
# tests/consumer against it: in C++ and in C, with CMake (find_package(massid))
# and with pkg-config; every program must predict a noise-free PUMA 260 log that the
# installed CLI simulated and identified. Run by ctest (consumer_installed).
#
#   check_installed.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
prefix=/opt/massid
DESTDIR="$stage" cmake --install "$build" --prefix "$prefix" >/dev/null
root="$stage$prefix"
[ -f "$root/include/massid/core/predictor.hpp" ] || { echo "headers not installed"; exit 1; }
for private in json_text.hpp atomic_file.hpp identify_file.hpp; do
  [ ! -e "$root/include/massid/$private" ] || { echo "private header installed: $private"; exit 1; }
done
# No installed header may include a private dependency.
if grep -rlE '#include <(nlohmann|fmt|urdf|ceres|CLI|fast_float|mujoco)' "$root/include"; then
  echo "an installed header includes a private dependency"; exit 1
fi

ex="$src/examples/puma260"
"$root/bin/massid" simulate "$ex/puma260.urdf" "$ex/plan.csv" -o "$stage/data.csv" >/dev/null
"$root/bin/massid" identify "$ex/puma260.urdf" "$stage/data.csv" -o "$stage/params.json" >/dev/null

echo "== CMake: find_package(massid)"
cmake -S "$src/tests/consumer" -B "$stage/cmake-build" -DCMAKE_PREFIX_PATH="$root" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$stage/cmake-build" -j 2 >/dev/null
"$stage/cmake-build/consumer" "$ex/puma260.urdf" "$stage/params.json" "$stage/data.csv"
"$stage/cmake-build/consumer_c" "$ex/puma260.urdf" "$stage/params.json" "$stage/data.csv"

echo "== pkg-config massid"
pcdir=$(dirname "$(find "$root" -name massid.pc | head -1)")
export PKG_CONFIG_PATH="$pcdir"
version=$(sed -n 's/^#define MASSID_VERSION "\(.*\)"/\1/p' "$root/include/massid/version.hpp")
[ "$(pkg-config --modversion massid)" = "$version" ] || { echo "pkg-config version differs"; exit 1; }
# shellcheck disable=SC2046
g++ -O1 -o "$stage/consumer_pc" "$src/tests/consumer/consumer.cpp" \
  $(pkg-config --cflags massid) $(pkg-config --static --libs massid)
"$stage/consumer_pc" "$ex/puma260.urdf" "$stage/params.json" "$stage/data.csv"

echo "== pkg-config massid-c"
[ "$(pkg-config --modversion massid-c)" = "$version" ] || { echo "massid-c version differs"; exit 1; }
# shellcheck disable=SC2046
gcc -std=c99 -O1 -o "$stage/consumer_c_pc" "$src/tests/consumer/consumer.c" \
  $(pkg-config --cflags massid-c) $(pkg-config --libs massid-c) -lm
LD_LIBRARY_PATH="$(pkg-config --variable=libdir massid-c)" \
  "$stage/consumer_c_pc" "$ex/puma260.urdf" "$stage/params.json" "$stage/data.csv"
