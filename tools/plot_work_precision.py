#!/usr/bin/python3
"""The work-precision diagram of a `clothsim bench --csv` file.

Two panels, error (log) against cost (log): time and force evaluations. Time is the CPU
time of the thread that made the run by default (--time cpu): on an idle machine it is the
run's wall time, and it stays so when other processes share the cores, which the wall
clock (--time wall) does not. One line per integrator through the runs that
finished, labelled with their step (labels placed clear of each other); an adaptive lane
(bs3, dopri5, rkf78: column tolerance set) is a dashed line through its tolerances, each point
labelled with its tolerance, as DiffEqDevTools draws fixed-step and adaptive methods on one
plot; runs that
diverged are marked with a cross along the top edge at their cost, labelled with their step; runs with implicit steps that did not converge (column
unconverged_steps, when present) are drawn hollow and circled in red: their error is not
backward Euler's; runs that read WRONG (column wrong, when present: energy made with no work
done, or strain past its bound) carry a red square: finite, but not this scene's motion. The dotted line is the reference's own resolution (how much halving its
step moved it): errors near it are not measured, only bounded.

    /usr/bin/python3 tools/plot_work_precision.py --csv bench.csv --out wp.png
"""
import math
from collections import OrderedDict

import plot_common as pc


def unconverged(row):
    """True when the run had implicit steps above their Newton tolerance."""
    return pc.number(row.get("unconverged_steps") or "0") > 0


def tolerance(row):
    """An adaptive run's tolerance (column tolerance, when present), else 0."""
    return pc.number(row.get("tolerance") or "0")


def step_text(row):
    """What a point is labelled with: its step, or an adaptive run's tolerance."""
    tol = tolerance(row)
    return f"tol {tol:.0e}" if tol > 0 else f"{pc.number(row['dt']):.3g}"


def wrong(row):
    """True when the run read WRONG (core/diagnostics.h)."""
    return (row.get("wrong") or "0") == "1"


def main():
    ap = pc.study_parser(__doc__, "bench")
    ap.add_argument("--time", choices=["wall", "cpu"], default="cpu",
                    help="cost axis of the left panel: CPU time of the run (default) or its wall time")
    args = ap.parse_args()

    rows = pc.read_rows(args.csv)
    pc.require(rows, args.csv, ["integrator", "dt", "force_evals", "wall_seconds", "cpu_seconds",
                                "rms_error", "diverged"])
    runs = OrderedDict()
    for r in rows:
        runs.setdefault(r["integrator"], []).append(r)

    time_key = "wall_seconds" if args.time == "wall" else "cpu_seconds"
    time_label = "wall time of the run (s)" if args.time == "wall" else \
        "time of the run (s, CPU time of its thread)"
    errors = [pc.number(r["rms_error"]) for r in rows]
    finite = [e for e in errors if e > 0 and math.isfinite(e)]
    top = max(finite) * 3 if finite else 1.0  # where diverged runs are marked
    bottom = min(finite) / 3 if finite else 1e-3
    ref = [pc.number(r.get("reference_change")) for r in rows]
    ref = [x for x in ref if x > 0 and math.isfinite(x)]

    fig, axes = pc.plt.subplots(1, 2, figsize=(12, 5.2), sharey=True)
    panels = [(axes[0], time_key, time_label), (axes[1], "force_evals", "force evaluations")]
    step_labels = {ax: [] for ax in axes}  # (x, y, step, colour): placed once the limits are known
    # bench --vary: lanes "rk4 (ks = 2e4)", coloured by their integrator, one line style per value.
    values = list(OrderedDict.fromkeys(n.partition(" (")[2] for n in runs if " (" in n))
    dashes = ["-", "--", ":", "-."]
    for ax, key, label in panels:
        for name, rs in runs.items():
            base, _, value = name.partition(" (")
            color, marker = pc.style(base)
            adaptive = any(tolerance(r) > 0 for r in rs)
            line = dashes[values.index(value) % len(dashes)] if value else ("--" if adaptive else "-")
            title = pc.lane_label(base) + (" (" + value if value else "") + (" by tolerance" if adaptive else "")
            ok = sorted((r for r in rs if r["diverged"] == "0" and pc.number(r["rms_error"]) > 0),
                        key=lambda r: tolerance(r) if adaptive else pc.number(r["dt"]))
            xs = [max(pc.number(r[key]), 1e-6) for r in ok]
            ys = [pc.number(r["rms_error"]) for r in ok]
            ax.plot(xs, ys, color=color, marker=marker, linestyle=line, label=title)
            step_labels[ax].extend((x, y, step_text(r), color) for r, x, y in zip(ok, xs, ys))
            missed = [(x, y) for r, x, y in zip(ok, xs, ys) if unconverged(r)]
            if missed:  # hollow: the line's filled marker painted over in white, then circled
                ax.scatter([x for x, _ in missed], [y for _, y in missed], marker=marker, s=40,
                           facecolors="white", edgecolors=color, linewidths=1.2, zorder=3)
                ax.scatter([x for x, _ in missed], [y for _, y in missed], s=140, facecolors="none",
                           edgecolors="red", linewidths=1.5, zorder=4)
            made_up = [(x, y) for r, x, y in zip(ok, xs, ys) if wrong(r)]
            if made_up:
                ax.scatter([x for x, _ in made_up], [y for _, y in made_up], marker="s", s=150,
                           facecolors="none", edgecolors="red", linewidths=1.5, zorder=4)
            bad = [r for r in rs if r["diverged"] == "1"]
            if bad:
                bx = [max(pc.number(r[key]), 1e-6) for r in bad]
                ax.scatter(bx, [top] * len(bad), marker="x", color=color, s=50, zorder=3)
                step_labels[ax].extend((x, top, step_text(r), color) for r, x in zip(bad, bx))
        if ref:
            ax.axhline(max(ref), color="gray", linestyle=":", linewidth=1)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(label)
        ax.grid(True, which="both", alpha=0.3)
    over_time = any((r.get("error_measure") or "end") == "time" for r in rows)
    axes[0].set_ylabel("RMS error (m), " + ("largest over the sample times" if over_time else "at T"))
    axes[0].set_ylim(min(bottom, min(ref) / 3) if ref else bottom, top * 3)
    handles, labels = axes[0].get_legend_handles_labels()
    handles.append(pc.plt.Line2D([], [], color="black", marker="x", linestyle="None"))
    labels.append("diverged (at its cost)")
    if any(unconverged(r) for r in rows):
        handles.append(pc.plt.Line2D([], [], marker="o", markerfacecolor="none", markeredgecolor="red",
                                     linestyle="None", markersize=10))
        labels.append("not converged (implicit steps above tolerance)")
    if any(wrong(r) for r in rows):
        handles.append(pc.plt.Line2D([], [], marker="s", markerfacecolor="none", markeredgecolor="red",
                                     linestyle="None", markersize=10))
        labels.append("wrong (energy made or over-stretched)")
    if ref:
        handles.append(pc.plt.Line2D([], [], color="gray", linestyle=":"))
        labels.append("reference resolution")
    axes[1].legend(handles, labels, fontsize=8, loc="lower left")
    fig.suptitle(("work precision: " + args.title) if args.title else "work precision")
    fig.text(0.5, 0.005, "points labelled with their step dt (s) or an adaptive lane's tolerance, crosses too; "
             "lower left is better",
             ha="center", fontsize=8)
    fig.tight_layout(rect=(0, 0.02, 1, 0.96))
    for ax in axes:
        pc.place_labels(ax, step_labels[ax])
    pc.save(fig, args.out)


if __name__ == "__main__":
    main()
