#!/usr/bin/env bash
# The PUMA 260 of the paper, end to end: installs what is missing, builds in
# Release, simulates the paper's experiment (30 poses, level and 25 deg about y)
# with force/torque sensor noise, identifies the base parameters (with an HTML
# report), compares them
# with the paper's, predicts the gravity wrench at 200 held-out poses, and flies
# the space emulator in simulation with parameters identified from the robot as built.
# Last, identification in motion (docs/motion.md): the UR5-like arm moving on its
# base sensor, the same from positions only, and a tool on a wrist sensor
# (examples/motion/run.sh, 20 s of trajectory at 500 Hz per log).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh
BUILD=${BUILD_DIR:-build/release}
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DMASSID_TESTS=OFF \
  -DMASSID_PYTHON=ON -DPython_EXECUTABLE=/usr/bin/python3 >/dev/null
cmake --build "$BUILD" -j "$(nproc)" --target massid _massid >/dev/null
M="$BUILD/massid"
EX=examples/puma260
OUT=${DEMO_OUT:-$BUILD/demo}
mkdir -p "$OUT"

echo "== massid model: which mass parameters can a base sensor see? (paper eq. 28)"
"$M" model $EX/puma260.urdf

echo
echo "== massid simulate: the paper's plan, sensor noise 0.05 N and 0.005 N m"
"$M" simulate $EX/puma260.urdf $EX/plan.csv -o "$OUT/data.csv" \
  --noise-force 0.05 --noise-moment 0.005 --seed 1

echo
echo "== massid identify (and an HTML report: plots of the fit, the parameters, the plan)"
"$M" identify $EX/puma260.urdf "$OUT/data.csv" -o "$OUT/params.json" --report "$OUT/report.html"

echo
echo "== identified against the paper's values (section V)"
python3 $EX/compare_paper.py "$OUT/params.json"

echo
echo "== massid predict at 200 held-out poses (tilts up to 25 deg in any direction),"
echo "   against the URDF's noise-free truth; the paper reached 1 % (Mz 10 %) of each axis' range"
"$M" simulate $EX/puma260.urdf $EX/holdout.csv -o "$OUT/holdout.csv" >/dev/null
"$M" predict $EX/puma260.urdf "$OUT/params.json" "$OUT/holdout.csv" -o "$OUT/predicted.csv"

echo
echo "== the space emulator: the PUMA as built (a gripper and cables its URDF lacks),"
echo "   measured 1 s per pose at 1 kHz, identified, then flown on a 50 kg spacecraft for 10 s"
"$M" simulate $EX/puma260_as_built.urdf $EX/plan.csv -o "$OUT/lab.csv" \
  --noise-force 0.05 --noise-moment 0.005 --repeat 1000 --seed 7
"$M" identify $EX/puma260.urdf "$OUT/lab.csv" -o "$OUT/lab_params.json" | grep "total mass"
"$M" emulate $EX/puma260.urdf "$OUT/lab_params.json" --plant $EX/puma260_as_built.urdf \
  -o "$OUT/trace.csv" --summary "$OUT/summary.json" --gravity 0,0,9.80665

echo
echo "== identification in motion: the UR5-like arm's inertias from its base wrench while it moves"
echo "   (design --dynamic, simulate --dynamic, identify --dynamic, predict on another trajectory),"
echo "   the same from positions only, and a tool on a wrist sensor (docs/motion.md)"
MASSID="$M" examples/motion/run.sh "$OUT/motion"
