#!/usr/bin/env python3
"""Writes a long data log for timing `massid identify` (streaming).

    bench/make_log.py ROBOT.urdf PLAN.csv ROWS OUT.csv [--massid build/massid]

Random poses drawn inside the ranges of PLAN's columns (gravity rows taken from
PLAN, so |g| stays right), simulated by `massid simulate` with sensor noise, a
few samples per pose (--repeat) as a logger would record them. Logs of more
than 10^6 rows repeat the data rows of a 10^6-row log (simulate holds its
output in memory), which is enough for timing and memory measurements.
"""
import argparse
import math
import os
import random
import shutil
import subprocess
import tempfile


def read_plan(path):
    header, rows = None, []
    with open(path) as f:
        for line in f:
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            cells = [c.strip() for c in s.split(",")]
            if header is None:
                header = cells
            else:
                rows.append([float(c) for c in cells])
    return header, rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("urdf")
    ap.add_argument("plan")
    ap.add_argument("rows", type=int)
    ap.add_argument("out")
    ap.add_argument("--massid", default="build/massid")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()

    header, rows = read_plan(a.plan)
    g = [header.index(n) for n in ("gx", "gy", "gz")]
    lo = [min(r[c] for r in rows) for c in range(len(header))]
    hi = [max(r[c] for r in rows) for c in range(len(header))]
    rng = random.Random(a.seed)
    base_rows = min(a.rows, 1000000)
    poses = min(base_rows, 5000)
    repeat = math.ceil(base_rows / poses)
    tmp = tempfile.mkdtemp()
    try:
        plan = os.path.join(tmp, "plan.csv")
        with open(plan, "w") as f:
            f.write(",".join(header) + "\n")
            for _ in range(poses):
                grow = rng.choice(rows)
                cells = [grow[c] if c in g else rng.uniform(lo[c], hi[c]) for c in range(len(header))]
                f.write(",".join(repr(x) for x in cells) + "\n")
        data = os.path.join(tmp, "data.csv")
        subprocess.run([a.massid, "simulate", a.urdf, plan, "-o", data, "--repeat", str(repeat),
                        "--noise-force", "0.05", "--noise-moment", "0.005", "--seed", str(a.seed)],
                       check=True, stdout=subprocess.DEVNULL)
        with open(data) as f:
            head = f.readline()
            body = f.readlines()[:base_rows]
        with open(a.out, "w") as out:
            out.write(head)
            left = a.rows
            while left > 0:
                chunk = body[:left]
                out.writelines(chunk)
                left -= len(chunk)
    finally:
        shutil.rmtree(tmp)


if __name__ == "__main__":
    main()
