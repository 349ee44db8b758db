#!/usr/bin/env python3
"""Write holdout.csv: 200 random poses of puma260.urdf, not used for
identification, to check predictions "throughout the workspace" (paper, sec. V).

Joint angles uniform over the plan's ranges; platform tilt uniform in direction
and up to 25 deg from level (gravity +z when level in the PUMA sensor frame).
Standard library only; fixed seed, so reruns rewrite the same file.
"""
import math
import os
import random

HERE = os.path.dirname(os.path.abspath(__file__))
G = 9.80665
RANGES_DEG = [("joint1", -160.0, 160.0), ("joint2", -200.0, 20.0), ("joint3", -45.0, 225.0)]


def main():
    rng = random.Random(2602)
    lines = ["# 200 held-out poses for puma260.urdf (make_holdout.py, seed 2602);",
             "# tilt up to 25 deg in any direction. Joints in rad.",
             "joint1,joint2,joint3,gx,gy,gz,tilt_x_deg,tilt_y_deg"]
    for _ in range(200):
        q = [math.radians(lo + (hi - lo) * rng.random()) for _, lo, hi in RANGES_DEG]
        tx = math.radians(rng.uniform(-25.0, 25.0))
        ty = math.radians(rng.uniform(-25.0, 25.0))
        # keep the tilt within a 25 deg cone
        while math.degrees(math.acos(math.cos(tx) * math.cos(ty))) > 25.0:
            tx = math.radians(rng.uniform(-25.0, 25.0))
            ty = math.radians(rng.uniform(-25.0, 25.0))
        # platform rotation R = Rx(tx) Ry(ty); gravity in the sensor frame R^T (0, 0, G)
        g = [-G * math.cos(tx) * math.sin(ty),
             G * math.sin(tx),
             G * math.cos(tx) * math.cos(ty)]
        row = q + g + [math.degrees(tx), math.degrees(ty)]
        lines.append(",".join(repr(v) for v in row))
    with open(os.path.join(HERE, "holdout.csv"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
