#!/usr/bin/env python3
"""The whole workflow in Python, without Jupyter: design -> simulate -> identify
-> predict -> report, on the PUMA 260 of the paper.

The "robot" measured here is puma260_as_built.urdf (a gripper and cables that
the nominal URDF lacks); massid identifies it with the nominal URDF's
kinematics, as a lab would, and the report shows the fit.

    PYTHONPATH=build/test/python /usr/bin/python3 examples/python_workflow.py [OUT_DIR]

(after `cmake --install`, no PYTHONPATH is needed). Writes OUT_DIR/plan.csv,
data.csv, params.json and report.html (default OUT_DIR: massid_workflow).
"""

import pathlib
import sys

import numpy as np

import massid

HERE = pathlib.Path(__file__).resolve().parent
URDF = HERE / "puma260" / "puma260.urdf"  # the kinematics we know
AS_BUILT = HERE / "puma260" / "puma260_as_built.urdf"  # stands in for the real robot
HOLDOUT = HERE / "puma260" / "holdout.csv"  # 200 poses the fit never saw
AXES = ("fx", "fy", "fz", "mx", "my", "mz")


def main(out: pathlib.Path) -> int:
    out.mkdir(parents=True, exist_ok=True)

    # 1. Design: 30 static poses, the platform tilting up to 25 deg (4 shared
    #    tilts). In the PUMA's sensor frame gravity is +z when level.
    plan = massid.design(URDF, 30, tilt_max_deg=25, level_gravity=(0.0, 0.0, 9.80665), seed=1)
    plan.save(out / "plan.csv")
    print(f"design: {len(plan)} poses, condition number {plan.condition_number:.3g} (eq. 36)")

    # 2. Measure (here: simulate the robot as built), 20 samples per pose with
    #    sensor noise and an unknown offset.
    offset = [0.3, -0.2, 0.5, 0.02, -0.01, 0.03]
    data = massid.simulate(AS_BUILT, plan, noise_force=0.05, noise_moment=0.005, sensor_offset=offset,
                           repeat=20, seed=7)
    with open(out / "data.csv", "w") as f:  # a log as a data logger would write it
        f.write(",".join(data) + "\n")
        for row in zip(*data.values()):
            f.write(",".join(repr(float(v)) for v in row) + "\n")

    # 3. Identify the base parameters and the offsets from the log.
    fit = massid.identify(URDF, out / "data.csv", offset=True)
    fit.save(out / "params.json")
    print(f"identify: total mass {fit.total_mass:.4f} +- {fit.total_mass_std:.4f} kg "
          f"(nominal URDF {massid.load_model(URDF).nominal_total_mass:.4f} kg)")
    for p in fit.base_parameters:
        print(f"  {p.name:>3} = {p.value:9.5f} +- {p.std:.5f} {p.unit:5} {p.expression}")

    # 4. Predict the gravity wrench at the held-out poses (the mechanism's own,
    #    without the sensor offset, as massid predict's fx_pred); the as-built
    #    robot's noise-free wrench is the truth.
    holdout = massid.read_csv(HOLDOUT)
    predicted = massid.predict(URDF, fit, holdout)
    truth = massid.simulate(AS_BUILT, holdout)
    true_w = np.column_stack([truth[a] for a in AXES])
    rms = np.sqrt(((true_w - predicted) ** 2).mean(axis=0))
    span = np.ptp(true_w, axis=0)
    print("predict: RMS error at 200 held-out poses, % of each axis' range:")
    print("  " + "  ".join(f"{a} {100 * e / s:.3f} %" for a, e, s in zip(AXES, rms, span)))

    # 5. Report: one self-contained HTML file.
    massid.report.write_identify_report(out / "report.html", fit)
    print(f"wrote {out / 'report.html'}")
    worst = float(np.max(100 * rms / span))
    return 0 if worst < 1.0 else 1  # the paper's target: 1 % of each axis' range


if __name__ == "__main__":
    sys.exit(main(pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "massid_workflow")))
