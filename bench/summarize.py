#!/usr/bin/env python3
"""One table of massid's benchmark figures and the anchors' ratios.

Reads Google Benchmark's JSON (massid_bench --benchmark_format=json) and
prints: the gravity wrench by massid's predictor against KDL and MuJoCo on the
same robots, the full wrench in motion against KDL's recursive Newton-Euler,
then every other benchmark with its counters. Standard library only.
"""
import json
import sys


def ns(b):
    scale = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}[b.get("time_unit", "ns")]
    return b["real_time"] * scale


def main(path):
    with open(path) as f:
        data = json.load(f)
    ctx = data.get("context", {})
    print(f"massid_bench on {ctx.get('host_name', '?')}, {ctx.get('num_cpus', '?')} cpus "
          f"at {ctx.get('mhz_per_cpu', '?')} MHz, {ctx.get('date', '')}")
    runs = {b["name"]: b for b in data["benchmarks"] if b.get("run_type", "iteration") == "iteration"}

    robots = {"0": "puma260", "1": "ur_like"}
    print("\ngravity wrench at the base, per call (lower is better; ratio = anchor / massid)")
    print(f"  {'robot':<10} {'massid':>10} {'KDL FK':>16} {'KDL RNE':>16} {'MuJoCo':>16}")
    for idx, robot in robots.items():
        mine = runs.get(f"BM_Predict/{idx}")
        if not mine:
            continue
        cells = [f"{ns(mine):8.0f} ns"]
        for anchor in ("BM_KdlFkWrench", "BM_KdlRneWrench", "BM_MujocoWrench"):
            b = runs.get(f"{anchor}/{idx}")
            cells.append(f"{ns(b):7.0f} ns {ns(b) / ns(mine):5.1f}x" if b else "-")
        print(f"  {robot:<10} {cells[0]:>10} {cells[1]:>16} {cells[2]:>16} {cells[3]:>16}")

    print("\nfull wrench in motion (weight and motion), per call (ratio = anchor / massid)")
    print(f"  {'robot':<10} {'massid':>10} {'KDL RNE':>16}")
    for idx, robot in robots.items():
        mine = runs.get(f"BM_PredictMotionAnchor/{idx}")
        b = runs.get(f"BM_KdlRneMotionWrench/{idx}")
        if not mine:
            continue
        cell = f"{ns(b):7.0f} ns {ns(b) / ns(mine):5.1f}x" if b else "-"
        print(f"  {robot:<10} {ns(mine):8.0f} ns {cell:>16}")

    print("\ntracker update per sample, 10 + 6 unknowns (BM_TrackerUpdate; target <= 1 us)")
    print(f"  {'sensor':<8} {'rest':>10} {'motion':>10} {'40 s log':>10}")
    for sensor in ("wrist", "base"):
        cells = [runs.get(f"BM_TrackerUpdate/{sensor}_{kind}") for kind in ("rest", "motion", "log")]
        if any(cells):
            print(f"  {sensor:<8} " + " ".join(f"{ns(b):7.0f} ns" if b else f"{'-':>10}"
                                                  for b in cells))

    print("\nall benchmarks")
    for name, b in runs.items():
        counters = {k: v for k, v in b.items()
                    if k not in ("name", "family_index", "per_family_instance_index", "run_name",
                                 "run_type", "repetitions", "repetition_index", "threads",
                                 "iterations", "real_time", "cpu_time", "time_unit", "label",
                                 "error_occurred", "error_message", "aggregate_name")}
        extra = "  ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                          for k, v in counters.items())
        if b.get("error_occurred"):
            extra = "ERROR: " + b.get("error_message", "")
        t = ns(b)
        shown = f"{t / 1e6:10.3f} ms" if t >= 1e6 else f"{t / 1e3:10.3f} us" if t >= 1e4 else f"{t:10.1f} ns"
        print(f"  {name:<40} {shown} {b.get('label', ''):<10} {extra}")


if __name__ == "__main__":
    main(sys.argv[1])
