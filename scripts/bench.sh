#!/usr/bin/env bash
# Builds massid in Release, runs the Google Benchmark suite (bench/) with the
# KDL and MuJoCo anchors in the same binary, and prints one table of figures
# and ratios (bench/summarize.py). Extra arguments go to massid_bench, e.g.
# --benchmark_filter=Predict. The raw JSON is kept in $BUILD/bench.json.
# Last, `massid identify` against the numpy pipeline (bench/numpy_identify.py)
# on one 300 000-row log (86 MB, about 30 s for numpy), and `massid identify
# --dynamic` against bench/numpy_identify_dynamic.py on a 100 000-row motion
# log, skipped when no python3 has numpy. Then the tracker's update per row
# (massid_tracker_rows, bench/tracker_rows.cpp) against a numpy Kalman filter
# on the same rows (bench/numpy_tracker.py).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh
BUILD=${BUILD_DIR:-build/release}
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DMASSID_TESTS=OFF -DMASSID_BENCH=ON >/dev/null
cmake --build "$BUILD" -j "$(nproc)" --target massid_bench massid massid_tracker_rows >/dev/null
"$BUILD/bench/massid_bench" --benchmark_format=json --benchmark_out="$BUILD/bench.json" \
  --benchmark_out_format=json "$@" >/dev/null
python3 bench/summarize.py "$BUILD/bench.json"
echo
"$BUILD/massid" bench examples/ur_like/ur_like.urdf

echo
PY=""
for p in python3 /usr/bin/python3; do
  if "$p" -c "import numpy" 2>/dev/null; then
    PY=$p
    break
  fi
done
if [ -z "$PY" ]; then
  echo "numpy pipeline: skipped (no python3 with numpy; Debian python3-numpy)"
  exit 0
fi
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
URDF=examples/ur_like/ur_like.urdf
ROWS=300000  # long enough that `massid identify` streams it rather than load it whole
"$PY" bench/make_log.py "$URDF" examples/ur_like/plan.csv "$ROWS" "$TMP/log.csv" \
  --massid "$BUILD/massid"
t0=$(date +%s.%N)
"$BUILD/massid" identify "$URDF" "$TMP/log.csv" -o "$TMP/params.json" >/dev/null
t1=$(date +%s.%N)
echo "identify from CSV, $ROWS rows of ur_like, end to end:"
awk -v n="$ROWS" -v a="$t0" -v b="$t1" \
  'BEGIN { printf "  massid identify  %10.3g rows/s\n", n / (b - a) }'
"$PY" bench/numpy_identify.py "$URDF" "$TMP/log.csv" --params "$TMP/params.json" | sed 's/^/  /'

# Identification in motion: `massid identify --dynamic` (streamed from the CSV,
# streaming.hpp) against the numpy pipeline (bench/numpy_identify_dynamic.py)
# on one 100 000-row log of ur_like, both end to end; the anchor also checks
# that its solution matches massid's params file. Two logs: the velocities
# given (52 MB, about 30-70 s for numpy), and positions only (massid derives
# the velocities and accelerations by its zero-phase filter in the stream; the
# anchor filters with np.convolve and fits every filtered row, its default).
DROWS=100000
dynamic_pair() {  # NAME "what" [make_dynamic_log.py options]
  local name=$1 what=$2
  shift 2
  "$PY" bench/make_dynamic_log.py "$URDF" "$TMP/$name.csv" --rows "$DROWS" \
    --noise-force 0.1 --noise-moment 0.01 "$@" 2>/dev/null
  local t0 t1
  t0=$(date +%s.%N)
  "$BUILD/massid" identify --dynamic "$URDF" "$TMP/$name.csv" -o "$TMP/$name.json" >/dev/null
  t1=$(date +%s.%N)
  echo
  echo "identify --dynamic from CSV, $DROWS rows of ur_like ($what), end to end:"
  awk -v n="$DROWS" -v a="$t0" -v b="$t1" \
    'BEGIN { printf "  massid identify --dynamic  %10.3g rows/s\n", n / (b - a) }'
  "$PY" bench/numpy_identify_dynamic.py "$URDF" "$TMP/$name.csv" --params "$TMP/$name.json" |
    sed 's/^/  /'
}
dynamic_pair dynamic "velocities given"
dynamic_pair positions "positions only" --no-derivatives

# The tracker (issue 28): Tracker::update per row on the tracked wrist log
# (10 + 6 unknowns), whole, against the numpy Kalman filter a user would write,
# timed on the same rows (formed by massid and saved); the anchor checks that
# it ends where massid's plain filter does.
echo
echo "tracker update per row, 20 000 rows of the tracked wrist log:"
"$BUILD/bench/massid_tracker_rows" "$TMP/tracker" | sed 's/^/  /'
"$PY" bench/numpy_tracker.py "$TMP/tracker.json" | sed 's/^/  /'
