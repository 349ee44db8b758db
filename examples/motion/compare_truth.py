#!/usr/bin/env python3
"""Compare identified dynamic base parameters with the URDF's own inertials.

    python3 compare_truth.py ROBOT.urdf PARAMS.json

For data simulated from ROBOT.urdf (massid simulate --dynamic) the URDF is the
truth: every base parameter's `terms` evaluated on the URDF's ten standard
parameters per link give the value noise-free data would identify. Prints, per
base parameter, the identified value, the truth, the reported std and the
error in units of the std; then the spread of those normalised errors (about
1 when the reported standard deviations are honest).

Standard parameters, as massid defines them: m, mx, my, mz (mass times the
centre of mass in the link frame) and ixx, ixy, ixz, iyy, iyz, izz, the inertia
tensor about the LINK ORIGIN in the link frame,
I_O = R I_C R^T + m (|c|^2 1 - c c^T), with R the <inertial> origin's rpy.
Standard library only.
"""
import json
import math
import sys
import xml.etree.ElementTree as ET


def rpy_matrix(r, p, y):
    """URDF rpy: R = Rz(y) Ry(p) Rx(r)."""
    cr, sr, cp, sp, cy, sy = (math.cos(r), math.sin(r), math.cos(p), math.sin(p),
                              math.cos(y), math.sin(y))
    return [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr]]


def numbers(text, default):
    return [float(v) for v in text.split()] if text else default


def standard_parameters(urdf_path):
    """{link: {"m": ..., "mx": ..., ..., "izz": ...}} from the URDF's inertials."""
    out = {}
    for link in ET.parse(urdf_path).getroot().iter("link"):
        p = dict.fromkeys(["m", "mx", "my", "mz", "ixx", "ixy", "ixz", "iyy", "iyz", "izz"], 0.0)
        inertial = link.find("inertial")
        if inertial is not None:
            origin = inertial.find("origin")
            c = numbers(origin.get("xyz") if origin is not None else None, [0.0, 0.0, 0.0])
            rpy = numbers(origin.get("rpy") if origin is not None else None, [0.0, 0.0, 0.0])
            m = float(inertial.find("mass").get("value"))
            e = inertial.find("inertia")
            g = lambda k: float(e.get(k, "0")) if e is not None else 0.0
            ic = [[g("ixx"), g("ixy"), g("ixz")],
                  [g("ixy"), g("iyy"), g("iyz")],
                  [g("ixz"), g("iyz"), g("izz")]]
            R = rpy_matrix(*rpy)
            # R I_C R^T, then the parallel-axis term about the link origin.
            ri = [[sum(R[i][k] * ic[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
            io = [[sum(ri[i][k] * R[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
            c2 = sum(v * v for v in c)
            for i in range(3):
                for j in range(3):
                    io[i][j] += m * ((c2 if i == j else 0.0) - c[i] * c[j])
            p.update(m=m, mx=m * c[0], my=m * c[1], mz=m * c[2],
                     ixx=io[0][0], ixy=io[0][1], ixz=io[0][2],
                     iyy=io[1][1], iyz=io[1][2], izz=io[2][2])
        out[link.get("name")] = p
    return out


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    truth = standard_parameters(sys.argv[1])
    with open(sys.argv[2]) as f:
        params = json.load(f)
    print(f"{'name':<5} {'identified':>12} {'URDF truth':>12} {'std':>9} {'error/std':>9}  unit")
    z = []
    for p in params["base_parameters"]:
        true = sum(t["coef"] * truth[t["link"]][t["param"]] for t in p["terms"])
        err = (p["value"] - true) / p["std"] if p["std"] > 0 else float("nan")
        z.append(err)
        print(f"{p['name']:<5} {p['value']:>12.6g} {true:>12.6g} {p['std']:>9.2g} {err:>9.2f}  {p['unit']}")
    rms = math.sqrt(sum(v * v for v in z) / len(z))
    worst = max(z, key=abs)
    print(f"{len(z)} base parameters: RMS of error/std {rms:.2f}, largest |error/std| {abs(worst):.2f}"
          " (honest std: RMS near 1, largest below about 3.5)")


if __name__ == "__main__":
    main()
