#!/usr/bin/env python3
"""Writes a synthetic motion log for a URDF (dynamic identification, timing).

    bench/make_dynamic_log.py ROBOT.urdf OUT.csv [--rows N | --duration S] [--rate HZ]
        [--sensor LINK] [--noise-force N] [--noise-moment NM] [--seed S]
        [--no-derivatives] [--fmt %.17g]

Every movable joint below the sensor link follows a finite Fourier series
(--harmonics of --base-frequency, random coefficients from --seed, amplitude
--amplitude rad inside the joint limits; prismatic joints 0.4 of their range):

    q(t) = q0 + sum_k a_k/(k w) sin(k w t) - b_k/(k w) cos(k w t)

with analytic velocities and accelerations. Gravity is constant in the sensor
frame (--gravity, default 0,0,-9.80665), the sensor at rest. The wrench is
the one the measured bodies (sensor link and subtree) exert on the sensor,
from the URDF's inertials by Newton-Euler in the link frames
(f = m a + alpha x h + omega x (omega x h), n = I alpha + omega x (I omega)
+ h x a, I about the link origin; w = -sum [R f; R n + p x R f]), plus
Gaussian noise (--noise-force, --noise-moment, standard deviations).

Columns: t, one per joint (positions, rad or m), JOINT_vel, JOINT_acc (not
with --no-derivatives), gx,gy,gz, fx,fy,fz,mx,my,mz. Written in chunks of
10^5 rows with np.savetxt (10^7 rows are feasible: a few GB with %.17g;
--fmt %.9g halves it, but then the round-off level is 1e-9, not 1e-16).

Kinematics and URDF reading are shared with bench/numpy_identify_dynamic.py;
the wrench here is computed directly (3x3 inertia matrices), not from that
script's regressor columns. Needs numpy (/usr/bin/python3).
"""
import argparse
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from numpy_identify_dynamic import link_motion, load_urdf, movable  # noqa: E402

CHUNK = 100000


def trajectories(joints, a, rng):
    """Per movable joint: (q0, a_k, b_k) of its Fourier series."""
    w = 2 * math.pi * a.base_frequency
    k = np.arange(1, a.harmonics + 1)
    out = {}
    for j in movable(joints):
        lo, hi = j["lower"], j["upper"]
        limited = j["type"] != "continuous" and math.isfinite(lo) and math.isfinite(hi) and hi > lo
        if j["type"] == "prismatic":
            amp = 0.4 * (hi - lo) if limited else 0.1
            q0 = 0.5 * (lo + hi) if limited else 0.0
        else:
            amp = min(a.amplitude, 0.45 * (hi - lo)) if limited else a.amplitude
            mid = 0.5 * (lo + hi) if limited else 0.0
            room = 0.5 * (hi - lo) - amp if limited else math.pi
            q0 = mid + rng.uniform(-1, 1) * min(max(room, 0.0), math.pi)
        ca, cb = rng.uniform(-1, 1, a.harmonics), rng.uniform(-1, 1, a.harmonics)
        bound = ((np.abs(ca) + np.abs(cb)) / (k * w)).sum()  # max |q - q0|
        out[j["name"]] = (q0, ca * amp / bound, cb * amp / bound)
    return out


def evaluate(traj, t, base_frequency):
    """q, qd, qdd per joint at times t."""
    w = 2 * math.pi * base_frequency
    q, qd, qdd = {}, {}, {}
    for name, (q0, ca, cb) in traj.items():
        k = np.arange(1, len(ca) + 1)
        s, c = np.sin(np.outer(t, k * w)), np.cos(np.outer(t, k * w))
        q[name] = q0 + s @ (ca / (k * w)) - c @ (cb / (k * w))
        qd[name] = c @ ca + s @ cb
        qdd[name] = (-s @ (ca * k * w)) + c @ (cb * k * w)
    return q, qd, qdd


def wrench(order, kin, theta):
    """[N x 6] wrench the bodies exert on the sensor (sensor frame, moment about its origin)."""
    n = kin[order[0]]["a"].shape[0]
    w = np.zeros((n, 6))
    for link in order:
        p = theta[link]
        m, h = p[0], p[1:4]
        I = np.array([[p[4], p[5], p[6]], [p[5], p[7], p[8]], [p[6], p[8], p[9]]])
        k = kin[link]
        om, al, acc = k["w"], k["dw"], k["a"]
        f = m * acc + np.cross(al, h) + np.cross(om, np.cross(om, h))
        nn = al @ I + np.cross(om, om @ I) + np.cross(h, acc)  # I symmetric: I v = v @ I
        Rf = np.einsum("nij,nj->ni", k["R"], f)
        Rn = np.einsum("nij,nj->ni", k["R"], nn)
        w[:, 0:3] -= Rf
        w[:, 3:6] -= Rn + np.cross(k["p"], Rf)
    return w


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("urdf")
    ap.add_argument("out")
    ap.add_argument("--rows", type=int, help="rows (default: duration x rate)")
    ap.add_argument("--duration", type=float, default=30.0, help="seconds (default 30)")
    ap.add_argument("--rate", type=float, default=1000.0, help="Hz (default 1000)")
    ap.add_argument("--sensor", help="sensor link (default: the URDF root)")
    ap.add_argument("--harmonics", type=int, default=5)
    ap.add_argument("--base-frequency", type=float, default=0.1, help="Hz (default 0.1)")
    ap.add_argument("--amplitude", type=float, default=1.0, help="rad (default 1)")
    ap.add_argument("--gravity", default="0,0,-9.80665", help="gx,gy,gz in the sensor frame")
    ap.add_argument("--noise-force", type=float, default=0.0, help="N (std)")
    ap.add_argument("--noise-moment", type=float, default=0.0, help="N m (std)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--no-derivatives", action="store_true", help="omit the _vel and _acc columns")
    ap.add_argument("--fmt", default="%.17g")
    a = ap.parse_args()

    t0 = time.perf_counter()
    order, joints, theta = load_urdf(a.urdf, a.sensor)
    rng = np.random.default_rng(a.seed)
    traj = trajectories(joints, a, rng)
    names = list(traj)
    rows = a.rows if a.rows is not None else int(round(a.duration * a.rate))
    g = np.array([float(v) for v in a.gravity.split(",")])
    header = ["t"] + names
    if not a.no_derivatives:
        header += [n + "_vel" for n in names] + [n + "_acc" for n in names]
    header += ["gx", "gy", "gz", "fx", "fy", "fz", "mx", "my", "mz"]
    with open(a.out, "w") as f:
        f.write(f"# make_dynamic_log.py {os.path.basename(a.urdf)}: {rows} rows at {a.rate:g} Hz, "
                f"{a.harmonics} harmonics of {a.base_frequency:g} Hz, seed {a.seed}, noise "
                f"{a.noise_force:g} N / {a.noise_moment:g} N m\n")
        f.write(",".join(header) + "\n")
        for start in range(0, rows, CHUNK):
            t = np.arange(start, min(rows, start + CHUNK)) / a.rate
            q, qd, qdd = evaluate(traj, t, a.base_frequency)
            gg = np.broadcast_to(g, (len(t), 3))
            w = wrench(order, link_motion(order, joints, q, qd, qdd, gg), theta)
            if a.noise_force > 0:
                w[:, 0:3] += rng.normal(0.0, a.noise_force, (len(t), 3))
            if a.noise_moment > 0:
                w[:, 3:6] += rng.normal(0.0, a.noise_moment, (len(t), 3))
            cols = [t] + [q[n] for n in names]
            if not a.no_derivatives:
                cols += [qd[n] for n in names] + [qdd[n] for n in names]
            np.savetxt(f, np.column_stack(cols + [gg, w]), fmt=a.fmt, delimiter=",")
    print(f"{a.out}: {rows} rows, {len(header)} columns in {time.perf_counter() - t0:.3g} s",
          file=sys.stderr)


if __name__ == "__main__":
    main()
