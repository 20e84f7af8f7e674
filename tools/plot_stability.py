#!/usr/bin/python3
"""Largest stable step against a swept parameter, from a `clothsim stability --csv` file.

Log-log, one line per integrator through the bracketed limits. A method stable at the
largest step tried is drawn as an open triangle pointing up at that step (its limit is
above); one unstable at every step tried, as an open triangle pointing down at the
smallest (its limit, if any, is below). The black dashed line is the springs' Gershgorin
estimate 2 / w_max, the grey dotted one 2 / max(w_max, c_max) with the dampers counted.

    /usr/bin/python3 tools/plot_stability.py --csv stability.csv --out stability.png
"""
import argparse
import math
from collections import OrderedDict

import plot_common as pc

UNITS = {"stiffness": "N/m", "damping": "N s/m", "particle_mass": "kg", "air_drag": "N s/m", "mass": "kg"}


def unit_of(param):
    return UNITS.get(param.rsplit(".", 1)[-1], "")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--csv", required=True, help="output of clothsim stability --csv")
    ap.add_argument("--out", required=True, help="PNG to write")
    ap.add_argument("--title", default="", help="figure title")
    args = ap.parse_args()

    rows = pc.read_rows(args.csv)
    pc.require(rows, args.csv, ["param", "value", "integrator", "outcome", "stable_dt", "dt_springs",
                                "dt_with_damping", "min_dt", "max_dt"])
    param = rows[0]["param"]
    by_kind = OrderedDict()
    for r in rows:
        by_kind.setdefault(r["integrator"], []).append(r)

    fig, ax = pc.plt.subplots(figsize=(8, 5.5))
    for name, rs in by_kind.items():
        color, marker = pc.style(name)
        rs = sorted(rs, key=lambda r: pc.number(r["value"]))
        found = [r for r in rs if r["outcome"] == "bracketed"]
        if found:
            ax.plot([pc.number(r["value"]) for r in found], [pc.number(r["stable_dt"]) for r in found],
                    color=color, marker=marker, label=name)
        above = [r for r in rs if r["outcome"] == "stable_at_max"]
        if above:
            ax.scatter([pc.number(r["value"]) for r in above], [pc.number(r["max_dt"]) for r in above],
                       marker="^", s=80, facecolors="none", edgecolors=color, linewidths=1.5,
                       label=f"{name}: stable at the largest dt tried")
        below = [r for r in rs if r["outcome"] == "unstable_at_min"]
        if below:
            ax.scatter([pc.number(r["value"]) for r in below], [pc.number(r["min_dt"]) for r in below],
                       marker="v", s=80, facecolors="none", edgecolors=color, linewidths=1.5,
                       label=f"{name}: unstable at every dt tried")
    # A stable step whose run had implicit steps above tolerance: circled in red, apart.
    missed = [r for r in rows if pc.number(r.get("stable_unconverged_steps") or "0") > 0]
    if missed:
        ax.scatter([pc.number(r["value"]) for r in missed],
                   [pc.number(r["stable_dt"] if r["outcome"] == "bracketed" else r["max_dt"]) for r in missed],
                   s=220, facecolors="none", edgecolors="red", linewidths=1.5, zorder=4,
                   label="stable, but steps not converged")
    est = {}
    for r in rows:
        est[pc.number(r["value"])] = (pc.number(r["dt_springs"]), pc.number(r["dt_with_damping"]))
    xs = sorted(est)
    springs = [est[x][0] for x in xs]
    damped = [est[x][1] for x in xs]
    if all(math.isfinite(y) for y in springs):
        ax.plot(xs, springs, color="black", linestyle="--", linewidth=1, label="2 / w_max (springs, Gershgorin)")
    if damped != springs and all(math.isfinite(y) for y in damped):
        ax.plot(xs, damped, color="gray", linestyle=":", linewidth=1.5, label="2 / max(w_max, c_max) (with dampers)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    unit = unit_of(param)
    ax.set_xlabel(f"{param} ({unit})" if unit else param)
    ax.set_ylabel("largest stable step dt (s)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    T = pc.number(rows[0].get("duration"))
    sub = f"runs from 0 to T = {T:g} s" if math.isfinite(T) else ""
    ax.set_title((("stability: " + args.title) if args.title else "stability") + (f"\n{sub}" if sub else ""),
                 fontsize=10)
    fig.tight_layout()
    pc.save(fig, args.out)


if __name__ == "__main__":
    main()
