#!/usr/bin/env python3
"""Print identified PUMA 260 base parameters next to the paper's (section V).

The paper's values are the example URDF's truth, so error/std should look
like draws from a unit normal distribution.

Usage: compare_paper.py PARAMS.json

The paper's p1..p9 (eq. 28) are written here as combinations of the URDF's
standard parameters (m, mx, my, mz per link; geometry of eq. 19, X = Y = 0,
Z = -0.036, l1 = 0.330, l2x = 0.198, l2y = -0.019; the sensor link's first
moments join the base's). Each is matched to the massid base parameter that
equals it up to sign and a multiple of the total mass. Standard library only.
"""
import json
import sys

Z, L1, L2X, L2Y = -0.036, 0.330, 0.198, -0.019
MOVING = ["base", "link1", "link2", "link3"]
PAPER = {  # name: (reported value, {(link, param): coef})
    "p1": (0.158, {("link3", "mx"): 1}),
    "p2": (0.010, {("link3", "my"): 1}),
    "p3": (0.382, {("link2", "mx"): 1, ("link3", "m"): L2X}),
    "p4": (-0.015, {("link2", "my"): 1, ("link3", "m"): L2Y}),
    "p5": (0.437, {("link1", "my"): -1, ("link2", "mz"): 1, ("link3", "mz"): 1}),
    "p6": (0.008, {("link1", "mx"): 1}),
    "p7": (-0.050, {("sensor", "mx"): 1, ("base", "my"): -1}),
    "p8": (0.275, {("sensor", "my"): 1, ("base", "mx"): -1}),
    "p9": (-2.445, {("sensor", "mz"): 1, ("base", "mz"): -1, ("link1", "mz"): -1,
                    **{(l, "m"): Z for l in MOVING},
                    ("link2", "m"): Z - L1, ("link3", "m"): Z - L1}),
    "M_t": (10.6, {(l, "m"): 1 for l in ["sensor"] + MOVING}),
}
KEYS = sorted({k for _, t in PAPER.values() for k in t} | {(l, p) for l in ["sensor"] + MOVING
                                                          for p in ("m", "mx", "my", "mz")})


def vec(terms):
    v = [0.0] * len(KEYS)
    for k, c in terms.items():
        v[KEYS.index(k)] += c
    return v


def match(paper_v, ours_v, mass_v):
    """Sign s and multiple a with ours = s (paper + a M), or None."""
    for s in (1.0, -1.0):
        d = [s * o - p for o, p in zip(ours_v, paper_v)]
        # d must be a multiple of the mass vector
        a = sum(x * m for x, m in zip(d, mass_v)) / sum(m * m for m in mass_v)
        if max(abs(x - a * m) for x, m in zip(d, mass_v)) < 1e-9:
            return s, a
    return None


def main():
    params = json.load(open(sys.argv[1]))
    mass_v = vec(PAPER["M_t"][1])
    total = params["total_mass"]
    print(f"{'paper':<6} {'paper value':>12} {'identified':>12} {'std':>10} {'error/std':>9}"
          "  massid parameter")
    for name, (value, terms) in PAPER.items():
        for bp in params["base_parameters"]:
            ours = vec({(t["link"], t["param"]): t["coef"] for t in bp["terms"]})
            m = match(vec(terms), ours, mass_v)
            if m:
                s, a = m
                ident = s * bp["value"] - a * total
                z = (ident - value) / bp["std"]
                print(f"{name:<6} {value:>12.4f} {ident:>12.4f} {bp['std']:>10.2g} {z:>9.2f}  "
                      f"{'-' if s < 0 else ''}{bp['name']} = {bp['expression']}")
                break
        else:
            print(f"{name:<6} {value:>12.4f} {'(no match)':>12}")
            sys.exit(1)


if __name__ == "__main__":
    main()
