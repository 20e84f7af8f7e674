#!/usr/bin/python3
"""Cost against sheet size, from a `clothsim bench --scale --csv` file.

Log-log, one line per lane: CPU seconds per simulated second against the particle count,
with the least-squares exponent p of cost ~ particles^p in the legend (1 is linear cost).
Runs that did not reach the duration are drawn hollow and left out of the fit.

    /usr/bin/python3 tools/plot_scale.py --csv scale.csv --out scale.png
"""
import math
from collections import OrderedDict

import plot_common as pc


def exponent(points):
    """Least-squares slope of log cost against log particles; nan with fewer than two."""
    pts = [(math.log(n), math.log(c)) for n, c in points if c > 0]
    if len(pts) < 2:
        return float("nan")
    mx = sum(x for x, _ in pts) / len(pts)
    my = sum(y for _, y in pts) / len(pts)
    sxx = sum((x - mx) ** 2 for x, _ in pts)
    return sum((x - mx) * (y - my) for x, y in pts) / sxx if sxx > 0 else float("nan")


def main():
    ap = pc.study_parser(__doc__, "scale")
    args = ap.parse_args()
    rows = pc.read_rows(args.csv)
    pc.require(rows, args.csv, ["lane", "particles", "cpu_per_sim_second", "finished"])
    by_lane = OrderedDict()
    for r in rows:
        by_lane.setdefault(r["lane"], []).append(r)
    fig, ax = pc.plt.subplots(figsize=(8, 5.5))
    for lane, rs in by_lane.items():
        xs = [pc.number(r["particles"]) for r in rs]
        ys = [pc.number(r["cpu_per_sim_second"]) for r in rs]
        done = [r["finished"] == "1" for r in rs]
        p = exponent([(x, y) for x, y, d in zip(xs, ys, done) if d])
        line, = ax.plot(xs, ys, marker="o", label=f"{lane}: p = {p:.2f}" if math.isfinite(p) else lane)
        hollow = [(x, y) for x, y, d in zip(xs, ys, done) if not d]
        if hollow:
            ax.scatter([x for x, _ in hollow], [y for _, y in hollow], s=80, facecolors="none",
                       edgecolors=line.get_color(), zorder=3)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("particles")
    ax.set_ylabel("CPU s per simulated s")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="best", title="cost ~ particles^p")
    ax.set_title(("scale: " + args.title) if args.title else "scale", fontsize=10)
    fig.tight_layout()
    pc.save(fig, args.out)


if __name__ == "__main__":
    main()
