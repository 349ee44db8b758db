#!/usr/bin/env python3
"""The numpy pipeline a user would write for `massid identify`, as an anchor.

    bench/numpy_identify.py ROBOT.urdf DATA.csv [--params PARAMS.json] [--json]

np.loadtxt of the data CSV; forward kinematics from the URDF (xml.etree),
vectorised over the rows; the stacked regressor of the standard mass
parameters (m, mx, my, mz of every link: F = sum m_l g, M = sum (m_l p_l +
R_l h_l) x g in the sensor frame, the URDF's root link); np.linalg.lstsq on it,
weighted per axis like massid (sigma per axis re-estimated from the residuals,
4 solves). Prints rows/s and the total mass.

With --params (the file written by `massid identify` on the same data) it
evaluates every base parameter's `terms` on the numpy solution (a minimum-norm
solution of the same least squares: identifiable combinations agree) and
prints the largest difference relative to the parameter's std; exit status 1
when a base parameter differs by more than 1e-3 of its std or the total mass
by more than 1e-9 relative (round-off of the two solvers is far below both).

Needs numpy (Debian python3-numpy); only the root sensor link, joint columns
in rad or JOINT_deg, gx,gy,gz columns.
"""
import argparse
import json
import math
import sys
import time
import xml.etree.ElementTree as ET

import numpy as np


def rpy_matrix(r, p, y):
    # URDF: R = Rz(yaw) Ry(pitch) Rx(roll).
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def floats(text, default):
    return [float(v) for v in text.split()] if text else default


def load_urdf(path):
    """Links in tree order (parents first) and, per non-root link, its joint."""
    robot = ET.parse(path).getroot()
    links = [l.get("name") for l in robot.findall("link")]
    joints = {}
    for j in robot.findall("joint"):
        origin = j.find("origin")
        axis = j.find("axis")
        joints[j.find("child").get("link")] = {
            "name": j.get("name"),
            "type": j.get("type"),
            "parent": j.find("parent").get("link"),
            "xyz": np.array(floats(origin.get("xyz") if origin is not None else None, [0, 0, 0])),
            "R": rpy_matrix(*floats(origin.get("rpy") if origin is not None else None, [0, 0, 0])),
            "axis": np.array(floats(axis.get("xyz") if axis is not None else None, [1, 0, 0])),
        }
    roots = [l for l in links if l not in joints]
    if len(roots) != 1:
        sys.exit(f"{path}: expected one root link, found {roots}")
    order, todo = [roots[0]], [roots[0]]
    while todo:
        parent = todo.pop(0)
        for child, j in joints.items():
            if j["parent"] == parent:
                order.append(child)
                todo.append(child)
    return order, joints


def read_data(path, joints):
    """np.loadtxt of the CSV; q [N x joints] in rad, g and w [N x 3], [N x 6]."""
    with open(path, encoding="utf-8-sig") as f:
        skip = 0
        for line in f:
            skip += 1
            if line.strip() and not line.lstrip().startswith("#"):
                header = [c.strip() for c in line.split(",")]
                break
    data = np.loadtxt(path, delimiter=",", comments="#", skiprows=skip, ndmin=2,
                      encoding="utf-8-sig")
    col = {name: i for i, name in enumerate(header)}
    q = {}
    for j in joints.values():
        if j["type"] == "fixed":
            continue
        if j["name"] in col:
            q[j["name"]] = data[:, col[j["name"]]]
        else:
            q[j["name"]] = np.radians(data[:, col[j["name"] + "_deg"]])
    g = data[:, [col[k] for k in ("gx", "gy", "gz")]]
    w = data[:, [col[k] for k in ("fx", "fy", "fz", "mx", "my", "mz")]]
    return q, g, w


def axis_rotation(axis, angle):
    """Rodrigues, vectorised: [N x 3 x 3] rotations by angle[i] about the unit axis."""
    a = axis / np.linalg.norm(axis)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    s, c = np.sin(angle)[:, None, None], np.cos(angle)[:, None, None]
    return np.eye(3) + s * K + (1 - c) * (K @ K)


def regressor(order, joints, q, g):
    """A [6N x 4L]: rows fx..mz of sample 0, then sample 1, ...; columns m, mx, my, mz per link."""
    n = g.shape[0]
    L = len(order)
    R = {order[0]: np.broadcast_to(np.eye(3), (n, 3, 3))}
    p = {order[0]: np.zeros((n, 3))}
    A = np.zeros((n, 6, 4 * L))
    for i, link in enumerate(order):
        if i > 0:
            j = joints[link]
            Rp, pp = R[j["parent"]], p[j["parent"]]
            M = Rp @ j["R"]
            pos = pp + Rp @ j["xyz"]
            if j["type"] in ("revolute", "continuous"):
                M = M @ axis_rotation(j["axis"], q[j["name"]])
            elif j["type"] == "prismatic":
                pos = pos + (M @ j["axis"]) * q[j["name"]][:, None]
            R[link], p[link] = M, pos
        A[:, 0:3, 4 * i] = g  # force: m_l g
        A[:, 3:6, 4 * i] = np.cross(p[link], g)  # moment: m_l p_l x g
        for k in range(3):  # moment: (R_l e_k) x g for h_l,k = m_l c_l,k
            A[:, 3:6, 4 * i + 1 + k] = np.cross(R[link][:, :, k], g)
    return A.reshape(6 * n, 4 * L)


def identify(A, y, iterations=4):
    """Per-axis weighted least squares, sigma re-estimated like massid's identify().

    Returns x, sigma and the seconds of the first (unweighted) solve."""
    n = A.shape[0] // 6
    p = np.linalg.matrix_rank(A[: min(A.shape[0], 6000)])
    sigma = np.ones(6)
    first = None
    for _ in range(iterations):
        t0 = time.perf_counter()
        wts = np.tile(1.0 / sigma, n)
        x = np.linalg.lstsq(A * wts[:, None], y * wts, rcond=None)[0]
        first = first or time.perf_counter() - t0
        r = (y - A @ x).reshape(n, 6)
        sigma = np.sqrt((r * r).sum(axis=0) / max(1.0, n - p / 6.0))
    return x, sigma, first


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("urdf")
    ap.add_argument("data")
    ap.add_argument("--params", help="massid identify's params file on the same data")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()

    t0 = time.perf_counter()
    order, joints = load_urdf(a.urdf)
    q, g, w = read_data(a.data, joints)
    t_read = time.perf_counter()
    A = regressor(order, joints, q, g)
    t_reg = time.perf_counter()
    x, sigma, first_solve = identify(A, w.reshape(-1))
    t1 = time.perf_counter()
    rows = g.shape[0]
    std = {(link, name): x[4 * i + k] for i, link in enumerate(order)
           for k, name in enumerate(("m", "mx", "my", "mz"))}
    total_mass = sum(std[(link, "m")] for link in order)
    out = {"rows": rows, "seconds": t1 - t0, "rows_per_s": rows / (t1 - t0),
           "rows_per_s_one_solve": rows / (t_reg - t0 + first_solve),
           "loadtxt_s": t_read - t0, "regressor_s": t_reg - t_read, "lstsq_s": t1 - t_reg,
           "total_mass": total_mass, "sigma": sigma.tolist()}
    ok = True
    if a.params:
        with open(a.params) as f:
            params = json.load(f)
        worst = abs(total_mass - params["total_mass"]) / max(1e-300, abs(params["total_mass"]))
        worst_std = 0.0
        for bp in params["base_parameters"]:
            value = sum(t["coef"] * std[(t["link"], t["param"])] for t in bp["terms"])
            worst_std = max(worst_std, abs(value - bp["value"]) / bp["std"])
        out["total_mass_rel_diff"] = worst
        out["base_parameters_max_diff_in_std"] = worst_std
        ok = worst_std < 1e-3 and worst < 1e-9
    if a.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"numpy pipeline: {rows} rows in {out['seconds']:.3g} s, {out['rows_per_s']:.3g} rows/s "
              f"(loadtxt {out['loadtxt_s']:.3g} s, regressor {out['regressor_s']:.3g} s, "
              f"lstsq x4 {out['lstsq_s']:.3g} s; with one lstsq "
              f"{out['rows_per_s_one_solve']:.3g} rows/s); total mass {total_mass:.6g} kg")
        if a.params:
            print(f"against {a.params}: total mass differs by {out['total_mass_rel_diff']:.2g} "
                  f"relative, base parameters by at most {out['base_parameters_max_diff_in_std']:.2g} std")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
