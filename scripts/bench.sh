#!/usr/bin/env bash
# Builds massid in Release and runs the Google Benchmark suite (bench/).
# Extra arguments go to massid_bench, e.g. --benchmark_filter=Predict.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh
BUILD=${BUILD_DIR:-build/release}
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DMASSID_TESTS=OFF -DMASSID_BENCH=ON >/dev/null
cmake --build "$BUILD" -j "$(nproc)" --target massid_bench >/dev/null
"$BUILD/bench/massid_bench" "$@"
