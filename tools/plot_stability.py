#!/usr/bin/python3
"""Largest stable step against a swept parameter, from a `clothsim stability --csv` file.

Log-log, one line per integrator through the bracketed limits. A method stable at the
largest step tried is drawn as an open triangle pointing up at that step (its limit is
above); one unstable at every step tried, as an open triangle pointing down at the
smallest (its limit, if any, is below). A limit set by implicit steps that did not converge
(column failure = not_converged) rather than by divergence is drawn hollow and circled in
red. Runs at one step per frame (column frame_steps) are drawn at their step, labelled by
lane: a filled square converged at every step (for the course's fixed point, which solves
nothing, a filled plus: ran to the end), a hollow one circled in red had steps that did not,
a cross diverged. Two lanes with limits in common are both shown: the second dashed, hollow
and labelled "the same limits as" the first (to the bisection's 2 %), "at N of M values" when
only some are. The legend sits beside the axes. The black dashed line is the springs' Gershgorin estimate
2 / w_max, the grey dotted one 2 / max(w_max, c_max) with the dampers counted.

    /usr/bin/python3 tools/plot_stability.py --csv stability.csv --out stability.png
"""
import math
import re
from collections import OrderedDict

import plot_common as pc

UNITS = {"stiffness": "N/m", "damping": "N s/m", "particle_mass": "kg", "air_drag": "N s/m", "mass": "kg",
         "ks": "N/m", "kd": "N s/m"}  # ks, kd: the aliases of scene/param_keys.h


def unit_of(param):
    return UNITS.get(param.rsplit(".", 1)[-1], "")


# One frame step's result in frame_steps: "1/60 s: ok, 12 steps converged",
# "1/30 s: 3 of 6 steps not converged", "1/30 s: diverged at t = 0.1 s", "0.003 s: ...".
FRAME_STEP = re.compile(r"^\s*(?:1/([0-9.]+)|([0-9.eE+-]+)) s: (ok|diverged|stopped|\d+ of \d+ steps not converged)")


def frame_steps(text):
    """[(dt, 'ok' | 'not_converged' | 'diverged')] from a frame_steps cell; stopped runs left out."""
    out = []
    for item in (text or "").split(";"):
        m = FRAME_STEP.match(item)
        if not m or m.group(3) == "stopped":
            continue
        dt = 1.0 / float(m.group(1)) if m.group(1) else float(m.group(2))
        result = m.group(3)
        out.append((dt, "not_converged" if result.endswith("not converged") else result))
    return out


def coinciding(drawn, xs, ys):
    """(name, count): the earlier lane sharing the most of these limits, the same to the
    bisection's 2 % (its precision) at the same value, and how many; (None, 0) if none does."""
    best, count = None, 0
    for dxs, dys, name in drawn:
        at = dict(zip(dxs, dys))
        n = sum(1 for x, y in zip(xs, ys) if x in at and abs(y - at[x]) <= 0.02 * abs(at[x]))
        if n > count:
            best, count = name, n
    return best, count


def main():
    ap = pc.study_parser(__doc__, "stability")
    args = ap.parse_args()

    rows = pc.read_rows(args.csv)
    pc.require(rows, args.csv, ["param", "value", "integrator", "outcome", "stable_dt", "dt_springs",
                                "dt_with_damping", "min_dt", "max_dt"])
    param = rows[0]["param"]
    by_kind = OrderedDict()
    for r in rows:
        by_kind.setdefault(r["integrator"], []).append(r)

    fig, ax = pc.plt.subplots(figsize=(10, 5.5))
    drawn = []  # (xs, ys, name) of the lanes drawn, to find a later one lying on an earlier one
    for name, rs in by_kind.items():
        color, marker = pc.style(name)
        rs = sorted(rs, key=lambda r: pc.number(r["value"]))
        found = [r for r in rs if r["outcome"] == "bracketed"]
        if found:
            xs, ys = [pc.number(r["value"]) for r in found], [pc.number(r["stable_dt"]) for r in found]
            same, shared = coinciding(drawn, xs, ys)
            drawn.append((xs, ys, name))
            if same is None:
                ax.plot(xs, ys, color=color, marker=marker, label=pc.lane_label(name))
            else:  # limits in common would hide one line under the other: dashed, hollow, and said
                where = "" if shared == len(xs) else f" at {shared} of {len(xs)} values"
                ax.plot(xs, ys, color=color, marker=marker, markersize=11, markerfacecolor="none", linestyle="--",
                        label=f"{pc.lane_label(name)} (the same limits as {pc.lane_label(same)}{where})")
        above = [r for r in rs if r["outcome"] == "stable_at_max"]
        if above:
            ax.scatter([pc.number(r["value"]) for r in above], [pc.number(r["max_dt"]) for r in above],
                       marker="^", s=80, facecolors="none", edgecolors=color, linewidths=1.5,
                       label=f"{pc.lane_label(name)}: stable at the largest dt tried")
        below = [r for r in rs if r["outcome"] == "unstable_at_min"]
        if below:
            ax.scatter([pc.number(r["value"]) for r in below], [pc.number(r["min_dt"]) for r in below],
                       marker="v", s=80, facecolors="none", edgecolors=color, linewidths=1.5,
                       label=f"{pc.lane_label(name)}: unstable at every dt tried")
    # Marks drawn as two overlaid artists (a hollow marker, circled in red) get one legend
    # entry each, as the pair: (artists, label).
    paired = []
    # A limit set by the Newton solve (steps above tolerance just above it), not by divergence.
    solve = [r for r in rows if r.get("failure") == "not_converged" and r["outcome"] in ("bracketed", "unstable_at_min")]
    if solve:
        xs = [pc.number(r["value"]) for r in solve]
        ys = [pc.number(r["stable_dt"] if r["outcome"] == "bracketed" else r["min_dt"]) for r in solve]
        inner = ax.scatter(xs, ys, s=60, facecolors="white", edgecolors=[pc.style(r["integrator"])[0] for r in solve],
                           linewidths=1.2, zorder=4)
        ring = ax.scatter(xs, ys, s=220, facecolors="none", edgecolors="red", linewidths=1.5, zorder=4)
        paired.append(((inner, ring), "limit set by steps not converged (not by divergence)"))
    # One step per frame: each frame step's run at each value, by lane, so the course's fixed
    # point (no solve, nothing to converge) is never read as backward Euler's converged steps.
    frames = OrderedDict()
    for r in rows:
        for dt, result in frame_steps(r.get("frame_steps")):
            frames.setdefault((r["integrator"], result), []).append((pc.number(r["value"]), dt))
    frame_lanes = list(OrderedDict.fromkeys(name for name, _ in frames))
    for (name, result), pts in frames.items():
        color, marker = pc.style(name)
        # Two lanes' frame steps sit at the same (value, step): each later lane a little right.
        shift = 1.15 ** frame_lanes.index(name)
        pts = [(v * shift, dt) for v, dt in pts]
        solves = not name.startswith(pc.FIXED_POINT)
        words = {"ok": "converged" if solves else "ran to the end", "not_converged": "not converged",
                 "diverged": "diverged"}
        label = f"{pc.lane_label(name)} at one step per frame: {words[result]}"
        xs, ys = [v for v, _ in pts], [dt for _, dt in pts]
        fp = 's' if solves else 'P'  # the fixed point keeps its own marker shape
        if result == "ok":
            ax.scatter(xs, ys, marker=fp, s=30, color=color, zorder=3, label=label)
        elif result == "not_converged":
            inner = ax.scatter(xs, ys, marker=fp, s=30, facecolors="white", edgecolors=color, linewidths=1.2, zorder=3)
            ring = ax.scatter(xs, ys, s=150, facecolors="none", edgecolors="red", linewidths=1.5, zorder=4)
            paired.append(((inner, ring), label))
        else:
            ax.scatter(xs, ys, marker="x", s=50, color=color, zorder=3, label=label)
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
    ax.set_ylabel("largest stable step dt (s)" + (" / one step per frame" if frames else ""))
    ax.grid(True, which="both", alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    # Beside the axes, never over a marker.
    ax.legend(handles + [h for h, _ in paired], labels + [l for _, l in paired], fontsize=7, loc="upper left",
              bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    T = pc.number(rows[0].get("duration"))
    sub = f"runs from 0 to T = {T:.3g} s" if math.isfinite(T) else ""  # three figures, as every title
    ax.set_title((("stability: " + args.title) if args.title else "stability") + (f"\n{sub}" if sub else ""),
                 fontsize=10)
    fig.tight_layout()
    pc.save(fig, args.out)


if __name__ == "__main__":
    main()
