#!/usr/bin/env python3
"""The simulated wrist logs of docs/tracking.md's worked example.

The UR5-like arm of tests/data/ur_wrist_ft.urdf with a force/torque sensor on
its flange and a gripper below it (finger held at 0.02 m), at 500 Hz:

  free.csv     20 s of motion with the gripper alone, constant offsets: the
               log the gripper is identified from (massid identify --dynamic);
  tracked.csv  40 s: the arm moves in three windows (3-9 s, 12-22 s, 26-34 s)
               and rests between them; an object (0.8 kg) is grasped at rest
               at 10 s and put down at rest at 24 s; the sensor's offsets
               drift by 0.3 N (0.01 N m) over the 40 s; a 9.7 N contact
               pushes on the gripper's tip from 16 s to 18 s, during motion.

Noise 0.05 N and 0.003 N m per axis (normal, fixed seed). The wrenches come
from `massid simulate` (the project's simulator), which this script runs:

  - the arm's motion with and without the object: simulate --dynamic on the
    URDF and on a copy with the object as an extra link fixed to the gripper
    (object.urdf, written here), spliced at the grasp and the release;
  - the contact: a force fixed in the world, F, at a point P on the gripper
    is the weight of a 1 kg point mass at P under a "gravity" F / (1 kg):
    simulate (static) on a copy with that point mass (contact.urdf) less
    simulate on the URDF, both with --root-gravity F, gives it in the sensor
    frame at every row, turning with the tool;
  - the drift and the noise are added here.

tracked.csv carries the truth in columns that `massid compensate --track`
passes through and its report plots (docs/report.md, "Report of a tracked
log"): true_payload_m, true_payload_cx..cz (empty while nothing is held),
true_payload_ixx..izz (the object's inertia about its centre of mass, the
gripper's axes), true_offset_fx..mz and true_fx_comp..true_mz_comp (the
contact's wrench, which *_comp should equal).

Usage: make_logs.py [--massid PATH] [--out DIR]   (numpy; seconds)
"""

import argparse
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
URDF = os.path.join(HERE, "..", "..", "tests", "data", "ur_wrist_ft.urdf")
JOINTS = ("shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint",
          "wrist_2_joint", "wrist_3_joint")
RATE, DURATION = 500.0, 40.0
MOTION = ((3.0, 9.0), (12.0, 22.0), (26.0, 34.0))  # the arm rests outside these windows
GRASP, RELEASE = 10.0, 24.0                         # at rest
CONTACT = (16.0, 18.0)                              # in motion; 50 ms ramps
OBJECT_MASS = 0.8
OBJECT_COM = (0.01, -0.005, 0.15)                   # gripper frame, m
OBJECT_INERTIA = (2.0e-3, 1.5e-3, 1.0e-3)           # principal, about the com, gripper axes
CONTACT_FORCE = (6.0, 3.0, -7.0)                    # world, N
CONTACT_POINT = (0.0, 0.0, 0.17)                    # gripper frame, m
OFFSET0 = np.array([1.5, -0.8, 2.0, 0.05, -0.03, 0.02])
DRIFT = np.array([0.3, -0.3, 0.3, 0.01, -0.01, 0.01])  # over the 40 s
NOISE = np.array([0.05, 0.05, 0.05, 0.003, 0.003, 0.003])
SIMULATE = ["--sensor", "ft_sensor", "--fixed", "finger_joint=0.02"]


def envelope(t, windows, ramp=0.3):
    """1 inside the motion windows, 0 at rest, raised-cosine ramps; and its two derivatives."""
    w, w1, w2 = np.zeros_like(t), np.zeros_like(t), np.zeros_like(t)
    k = np.pi / ramp
    for a, b in windows:
        inside = (t >= a) & (t <= b)
        u = np.minimum(t - a, b - t)
        sign = np.where(t - a < b - t, 1.0, -1.0)
        full = inside & (u >= ramp)
        edge = inside & (u < ramp)
        w[full] = 1.0
        w[edge] = np.sin(0.5 * k * u[edge]) ** 2
        w1[edge] = sign[edge] * 0.5 * k * np.sin(k * u[edge])
        w2[edge] = 0.5 * k * k * np.cos(k * u[edge])
    return w, w1, w2


def trajectory(t, windows, seed):
    """q, qd, qdd [n x 6]: a rest pose plus the envelope times three sines per joint."""
    rng = np.random.default_rng(seed)
    q0 = np.array([0.3, -1.3, 1.4, -1.2, -1.4, 0.4])
    w, w1, w2 = envelope(t, windows)
    q = np.tile(q0, (t.size, 1))
    qd, qdd = np.zeros_like(q), np.zeros_like(q)
    for j in range(6):
        for h in range(3):
            amp = (0.15 if j < 3 else 0.45) * (0.5 + rng.uniform()) / (h + 1)
            f = 1.5 + 2.5 * rng.uniform() + h
            phase = 2 * np.pi * rng.uniform()
            g = amp * np.sin(f * t + phase)
            g1 = amp * f * np.cos(f * t + phase)
            g2 = -amp * f * f * np.sin(f * t + phase)
            q[:, j] += w * g
            qd[:, j] += w1 * g + w * g1
            qdd[:, j] += w2 * g + 2 * w1 * g1 + w * g2
    return q, qd, qdd


def write_csv(path, columns):
    """Columns (arrays of one length) as a CSV; NaN as an empty field."""
    names = list(columns)
    data = np.column_stack([np.asarray(columns[k], dtype=float) + 0.0 for k in names])  # no -0
    row = ",".join(["%.15g"] * len(names)) + "\n"  # 15 digits: exact enough, readable
    with open(path, "w") as f:
        f.write(",".join(names) + "\n")
        f.writelines((row % tuple(r)).replace("nan", "") for r in data.tolist())


def read_wrench(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return data[:, [header.index(a) for a in ("fx", "fy", "fz", "mx", "my", "mz")]]


def with_link(urdf_text, name, xyz, mass, inertia):
    """The URDF with a link NAME fixed to the gripper: a body at xyz (gripper frame)."""
    link = (f'<joint name="{name}_joint" type="fixed"><parent link="gripper"/><child link="{name}"/>'
            f'<origin xyz="0 0 0" rpy="0 0 0"/></joint>\n'
            f'<link name="{name}"><inertial><origin xyz="{xyz[0]} {xyz[1]} {xyz[2]}" rpy="0 0 0"/>'
            f'<mass value="{mass}"/><inertia ixx="{inertia[0]}" ixy="0" ixz="0" iyy="{inertia[1]}" '
            f'iyz="0" izz="{inertia[2]}"/></inertial></link>\n</robot>')
    at = urdf_text.rfind("</robot>")
    return urdf_text[:at] + link + urdf_text[at + len("</robot>"):]


def simulate(massid, urdf, plan, out, *extra):
    subprocess.run([massid, "simulate", urdf, plan, "-o", out, *SIMULATE, *extra], check=True,
                   stdout=subprocess.DEVNULL)
    return read_wrench(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--massid", default="massid", help="the massid program (default: on PATH)")
    ap.add_argument("--out", default=".", help="directory for the logs (default: here)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    work = lambda name: os.path.join(a.out, name)  # noqa: E731
    with open(URDF) as f:
        urdf_text = f.read()
    with open(work("object.urdf"), "w") as f:
        f.write(with_link(urdf_text, "object", OBJECT_COM, OBJECT_MASS, OBJECT_INERTIA))
    with open(work("contact.urdf"), "w") as f:
        f.write(with_link(urdf_text, "contact_point", CONTACT_POINT, 1.0, (0.0, 0.0, 0.0)))
    rng = np.random.default_rng(2026)

    def joints(t, windows, seed):
        q, qd, qdd = trajectory(t, windows, seed)
        cols = {"t": t}
        for j, name in enumerate(JOINTS):
            cols[name] = q[:, j]
        for j, name in enumerate(JOINTS):
            cols[name + "_vel"] = qd[:, j]
        for j, name in enumerate(JOINTS):
            cols[name + "_acc"] = qdd[:, j]
        return cols

    # free.csv: the gripper alone, moving all along, constant offsets.
    t = np.arange(int(20 * RATE)) / RATE
    cols = joints(t, ((0.5, 19.5),), seed=11)
    write_csv(work("free_traj.csv"), cols)
    w = simulate(a.massid, URDF, work("free_traj.csv"), work("free_sim.csv"), "--dynamic")
    w += OFFSET0 + rng.normal(size=w.shape) * NOISE
    for k, axis in enumerate(("fx", "fy", "fz", "mx", "my", "mz")):
        cols[axis] = w[:, k]
    write_csv(work("free.csv"), cols)

    # tracked.csv
    t = np.arange(int(DURATION * RATE)) / RATE
    cols = joints(t, MOTION, seed=12)
    write_csv(work("traj.csv"), cols)
    plain = simulate(a.massid, URDF, work("traj.csv"), work("plain_sim.csv"), "--dynamic")
    held = simulate(a.massid, work("object.urdf"), work("traj.csv"), work("held_sim.csv"), "--dynamic")
    g = ",".join(repr(x) for x in CONTACT_FORCE)  # F / (1 kg)
    contact = (simulate(a.massid, work("contact.urdf"), work("traj.csv"), work("c1.csv"), "--root-gravity", g)
               - simulate(a.massid, URDF, work("traj.csv"), work("c0.csv"), "--root-gravity", g))
    holding = (t >= GRASP) & (t < RELEASE)
    a0, a1 = CONTACT
    scale = np.clip(np.minimum((t - a0) / 0.05, (a1 - t) / 0.05), 0.0, 1.0) * ((t >= a0) & (t < a1))
    offset = OFFSET0 + np.outer(t / DURATION, DRIFT)
    contact *= scale[:, None]
    w = np.where(holding[:, None], held, plain) + offset + contact + rng.normal(size=plain.shape) * NOISE
    for k, axis in enumerate(("fx", "fy", "fz", "mx", "my", "mz")):
        cols[axis] = w[:, k]
    nan = np.full(t.size, np.nan)
    cols["true_payload_m"] = np.where(holding, OBJECT_MASS, 0.0)
    for k, c in enumerate("xyz"):
        cols["true_payload_c" + c] = np.where(holding, OBJECT_COM[k], nan)
    inertia = {"ixx": OBJECT_INERTIA[0], "ixy": 0.0, "ixz": 0.0, "iyy": OBJECT_INERTIA[1], "iyz": 0.0,
               "izz": OBJECT_INERTIA[2]}
    for name, v in inertia.items():
        cols["true_payload_" + name] = np.where(holding, v, nan)
    for k, axis in enumerate(("fx", "fy", "fz", "mx", "my", "mz")):
        cols["true_offset_" + axis] = offset[:, k]
    for k, axis in enumerate(("fx", "fy", "fz", "mx", "my", "mz")):
        cols[f"true_{axis}_comp"] = contact[:, k]
    write_csv(work("tracked.csv"), cols)
    for name in ("free_traj.csv", "free_sim.csv", "traj.csv", "plain_sim.csv", "held_sim.csv", "c1.csv",
                 "c0.csv"):
        os.remove(work(name))
    print(f"wrote {work('free.csv')} ({int(20 * RATE)} rows) and {work('tracked.csv')} "
          f"({t.size} rows; grasp at {GRASP:g} s, release at {RELEASE:g} s, contact "
          f"{a0:g}-{a1:g} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
