#!/usr/bin/env bash
# Builds massid in Release, runs the Google Benchmark suite (bench/) with the
# KDL and MuJoCo anchors in the same binary, and prints one table of figures
# and ratios (bench/summarize.py). Extra arguments go to massid_bench, e.g.
# --benchmark_filter=Predict. The raw JSON is kept in $BUILD/bench.json.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh
BUILD=${BUILD_DIR:-build/release}
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DMASSID_TESTS=OFF -DMASSID_BENCH=ON >/dev/null
cmake --build "$BUILD" -j "$(nproc)" --target massid_bench massid >/dev/null
"$BUILD/bench/massid_bench" --benchmark_format=json --benchmark_out="$BUILD/bench.json" \
  --benchmark_out_format=json "$@" >/dev/null
python3 bench/summarize.py "$BUILD/bench.json"
echo
"$BUILD/massid" bench examples/ur_like/ur_like.urdf
