#!/usr/bin/env python3
"""The numpy Kalman filter a user would write for the tracker, as an anchor.

    bench/numpy_tracker.py ROWS.json [--passes 3] [--json]

ROWS.json and ROWS.bin come from massid_tracker_rows (bench/tracker_rows.cpp;
scripts/bench.sh runs both): the rows of the tracker tests' 40 s wrist log
(20 000 rows at 500 Hz), each the LINK regressor Y (6 x 10) and the measured
wrench less the mechanism's prediction z (6), formed by massid as its tracker
forms them. This script times only the filter's update over the same 16
unknowns (the payload's 10 parameters, the sensor's 6 offsets), per row, in
plain numpy:

    P[offsets] += walk * dt               (the offsets' random walk)
    H = [Y | I6]
    PHt = P @ H.T
    S = H @ PHt + R
    K = np.linalg.solve(S, PHt.T).T
    x = x + K @ (z - H @ x)
    P = P - K @ PHt.T;  P = (P + P.T) / 2

(the rows' H built beforehand, outside the timed loop). That is massid's
tracker as a plain Kalman filter (lag 0, no gate); massid's figure
(massid_ns_per_row in ROWS.json) is its whole update as `compensate --track`
runs it: the mechanism's prediction, the regressor, the gate's chi^2 of the
new row, the lagged commit, the refits and the projection, i.e. more work;
less the time that forms the rows (massid_row_forming_ns_per_row, timed
apart), it is massid's filter from the same given rows, a second ratio. The
anchor checks that its final state and covariance equal the plain massid
filter's (x_final, P_final) to 1e-6 of their std; exit status 1 otherwise.

Needs numpy only (Debian python3-numpy: /usr/bin/python3).
"""
import argparse
import json
import sys
import time

import numpy as np


def run(rows, x0, P0, R, walk):
    """The filter over every row; returns x, P."""
    t, H, z = rows
    x = x0.copy()
    P = P0.copy()
    off = np.arange(10, 16)
    for i in range(len(t)):
        if i > 0:
            P[off, off] += walk * (t[i] - t[i - 1])
        Hi = H[i]
        PHt = P @ Hi.T
        S = Hi @ PHt + R
        K = np.linalg.solve(S, PHt.T).T
        x = x + K @ (z[i] - Hi @ x)
        P = P - K @ PHt.T
        P = (P + P.T) / 2
    return x, P


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("rows", help="massid_tracker_rows's OUT.json (OUT.bin beside it)")
    ap.add_argument("--passes", type=int, default=3, help="timed passes, best taken (default 3)")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    with open(a.rows) as f:
        meta = json.load(f)
    n, width = meta["rows"], meta["row_doubles"]
    data = np.fromfile(a.rows[:-len(".json")] + ".bin", dtype="<f8").reshape(n, width)
    t = data[:, 0]
    Y = data[:, 1:61].reshape(n, 6, 10)
    z = data[:, 61:67]
    H = np.concatenate((Y, np.broadcast_to(np.eye(6), (n, 6, 6))), axis=2)
    x0 = np.array(meta["x0"])
    P0 = np.array(meta["P0"]).reshape(16, 16, order="F")
    R = np.diag(meta["noise_var"])
    walk = np.array(meta["walk_var"])

    best = float("inf")
    for _ in range(a.passes):
        t0 = time.perf_counter()
        x, P = run((t, H, z), x0, P0, R, walk)
        best = min(best, time.perf_counter() - t0)
    ns = best / n * 1e9

    xm = np.array(meta["x_final"])
    Pm = np.array(meta["P_final"]).reshape(16, 16, order="F")
    sd = np.sqrt(np.diag(Pm))
    dx = float(np.max(np.abs(x - xm) / sd))
    dP = float(np.max(np.abs(P - Pm) / np.outer(sd, sd)))
    filt = meta["massid_ns_per_row"] - meta["massid_row_forming_ns_per_row"]
    out = {
        "rows": n,
        "numpy_ns_per_row": ns,
        "massid_ns_per_row": meta["massid_ns_per_row"],
        "massid_plain_ns_per_row": meta["massid_plain_ns_per_row"],
        "ratio": ns / meta["massid_ns_per_row"],
        "ratio_plain": ns / meta["massid_plain_ns_per_row"],
        "massid_filter_ns_per_row": filt,
        "ratio_filter": ns / filt,
        "state_diff_std": dx,
        "covariance_diff": dP,
        "numpy": np.__version__,
    }
    if a.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"numpy Kalman filter (numpy {np.__version__}), the same {n} rows, 16 unknowns: "
              f"{ns / 1e3:.1f} us per row (best of {a.passes})")
        print(f"massid Tracker::update: {out['massid_ns_per_row']:.0f} ns per row, whole "
              f"(ratio {out['ratio']:.0f}x); as the plain filter "
              f"{out['massid_plain_ns_per_row']:.0f} ns ({out['ratio_plain']:.0f}x); less forming "
              f"the rows, from the same rows as numpy: {filt:.0f} ns ({out['ratio_filter']:.0f}x)")
        print(f"against massid's plain filter: state within {dx:.2g} std, covariance within "
              f"{dP:.2g} (relative to the std products)")
    return 0 if dx < 1e-6 and dP < 1e-6 else 1


if __name__ == "__main__":
    sys.exit(main())
