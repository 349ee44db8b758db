#!/usr/bin/env bash
# Identification in motion, end to end, on the UR5-like arm of examples/ur_like
# (docs/motion.md walks through the same commands):
#   1. the arm on a base sensor: an exciting trajectory (design --dynamic), the
#      wrench it produces with sensor noise and offset (simulate --dynamic), the
#      dynamic base parameters (identify --dynamic --offset), compared with the
#      URDF's truth, then predicted along ANOTHER trajectory (predict);
#   2. the same log with positions only (the _vel/_acc columns dropped):
#      identify derives velocities and accelerations with its zero-phase filter;
#   3. the tool on a wrist sensor (--sensor wrist_3_link): the log holds the
#      arm's six joints and the wrist wrench, no gravity columns.
#
# Usage: examples/motion/run.sh [OUTDIR]     (default: a new temporary directory)
#   MASSID=path/to/massid picks the binary (default: massid on PATH, else
#   build/release/massid, build/dev/massid or build/massid of this checkout).
# 20 s of trajectory at 500 Hz per log: a few seconds in a Release build.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
URDF="$ROOT/examples/ur_like/ur_like.urdf"

M=${MASSID:-}
if [[ -z "$M" ]]; then
  if command -v massid >/dev/null 2>&1; then
    M=massid
  else
    for b in build/release/massid build/dev/massid build/massid; do
      if [[ -x "$ROOT/$b" ]]; then M="$ROOT/$b"; break; fi
    done
  fi
fi
if [[ "$M" == */* ]]; then  # a path: make it absolute (the script changes directory)
  M="$(cd "$(dirname "$M")" && pwd)/$(basename "$M")"
fi
if [[ -z "$M" ]]; then
  echo "run.sh: no massid binary: build it (cmake --build BUILD --target massid) or set MASSID" >&2
  exit 2
fi
OUT=${1:-$(mktemp -d "${TMPDIR:-/tmp}/massid-motion.XXXXXX")}
mkdir -p "$OUT"
cd "$OUT"

DESIGN=(--duration 20 --rate 500 --noise-force 0.1 --noise-moment 0.01)
NOISE=(--noise-force 0.1 --noise-moment 0.01)
OFFSET=1.5,-0.8,2.0,0.12,-0.05,0.03

# drop_columns REGEX IN.csv OUT.csv: every column whose name matches REGEX goes.
drop_columns() {
  awk -F, -v OFS=, -v re="$1" '
    NR == 1 { n = 0; for (i = 1; i <= NF; i++) if ($i !~ re) keep[++n] = i }
    { s = $(keep[1]); for (j = 2; j <= n; j++) s = s OFS $(keep[j]); print s }' "$2" >"$3"
}

echo "== 1. UR5-like arm on a base sensor: output in $OUT"
echo "-- massid model --dynamic: what a level platform with an unknown sensor offset can determine"
"$M" model "$URDF" --dynamic --gravity-model level --offset | grep -E "^(standard|motion|base) "

echo
echo "-- massid design --dynamic: 20 s at 500 Hz, Fourier series, at rest at both ends"
"$M" design "$URDF" --dynamic --offset -o traj.csv "${DESIGN[@]}" --seed 1 |
  grep -vE "^  (p[0-9]|offset_)"

echo
echo "-- massid simulate --dynamic: noise 0.1 N / 0.01 N m, offset $OFFSET"
"$M" simulate "$URDF" traj.csv -o log.csv --dynamic "${NOISE[@]}" --sensor-offset "$OFFSET" --seed 3

echo
echo "-- massid identify --dynamic --offset (base parameters p1..p40 in params.json)"
"$M" identify "$URDF" log.csv --dynamic --offset -o params.json | grep -vE "^  p[0-9]"
python3 "$HERE/compare_truth.py" "$URDF" params.json | tail -n 1

echo
echo "-- massid predict along another trajectory (design --seed 2), its own noise"
"$M" design "$URDF" --dynamic -o traj2.csv "${DESIGN[@]}" --seed 2 >/dev/null
"$M" simulate "$URDF" traj2.csv -o log2.csv --dynamic "${NOISE[@]}" --sensor-offset "$OFFSET" \
  --seed 4 >/dev/null
"$M" predict "$URDF" params.json log2.csv -o predicted2.csv

echo
echo "== 2. The same log from positions only (no _vel/_acc columns)"
drop_columns '_(vel|acc)$' log.csv log_q.csv
drop_columns '_(vel|acc)$' log2.csv log2_q.csv
"$M" identify "$URDF" log_q.csv --dynamic --offset -o params_q.json | grep -vE "^  p[0-9]"
python3 "$HERE/compare_truth.py" "$URDF" params_q.json | tail -n 1
"$M" predict "$URDF" params_q.json log2_q.csv -o predicted2_q.csv

echo
echo "== 3. The tool on a wrist sensor (--sensor wrist_3_link)"
# The arm's joints give the sensor frame's orientation and motion; gravity
# comes from --root-gravity (default 0,0,-9.80665 in the URDF root frame), so
# the trajectory's gx,gy,gz (the base sensor's frame) must go.
drop_columns '^g[xyz]$' traj.csv traj_wrist.csv
drop_columns '^g[xyz]$' traj2.csv traj2_wrist.csv
"$M" simulate "$URDF" traj_wrist.csv -o log_wrist.csv --dynamic --sensor wrist_3_link \
  "${NOISE[@]}" --offset 0.3,-0.2,0.5,0.01,-0.02,0.005 --seed 5
"$M" identify "$URDF" log_wrist.csv --dynamic --sensor wrist_3_link --offset -o params_wrist.json
python3 "$HERE/compare_truth.py" "$URDF" params_wrist.json | tail -n 1
"$M" simulate "$URDF" traj2_wrist.csv -o log2_wrist.csv --dynamic --sensor wrist_3_link \
  "${NOISE[@]}" --offset 0.3,-0.2,0.5,0.01,-0.02,0.005 --seed 6 >/dev/null
"$M" predict "$URDF" params_wrist.json log2_wrist.csv -o predicted2_wrist.csv
