#!/usr/bin/python3
"""Substeps against iterations at equal cost, from a `clothsim bench --budget N --csv` file.

Two panels against the substeps s a frame (log), k = N / s iterations each: the largest particle
distance from the reference over the frames (log), and the largest spring strain (l - l0) / l0
(log). One line per solver through the splits that finished; a split that diverged is a cross
along the top edge at its s; one that reads WRONG (energy made with no work done, or strain past
its bound) carries a red square; an error the reference cannot resolve (unresolved: under 10x
its own) is drawn hollow on that bound, the dotted line. The strain panel's dotted line is the
reference's own largest strain. Macklin et al. 2019's
claim reads as the lines falling to the right: more, smaller steps, fewer iterations each.

    /usr/bin/python3 tools/plot_budget.py --csv budget.csv --out budget.png
"""
import math
from collections import OrderedDict

import plot_common as pc  # matplotlib (Agg) and its ticker, loaded by pyplot

# The iterative solvers' colours (plot_common.STYLE has the seed's five).
SOLVER_STYLE = {
    "xpbd": ("tab:cyan", "o"),
    "vbd": ("tab:olive", "s"),
    "projective_dynamics": ("tab:pink", "D"),
    "implicit_euler": ("tab:purple", "v"),
}


def style(name):
    return SOLVER_STYLE.get(name.partition(":")[0], pc.style(name))


def main():
    ap = pc.study_parser(__doc__, "bench --budget")
    args = ap.parse_args()
    rows = pc.read_rows(args.csv)
    pc.require(rows, args.csv, ["solver", "budget", "substeps", "iterations", "max_error", "max_strain",
                                "diverged", "wrong", "unresolved", "reference_error"])
    solvers = OrderedDict()
    for r in rows:
        solvers.setdefault(r["solver"], []).append(r)
    budget = rows[0]["budget"]
    # Errors under 10x the reference's own are unresolved (bench's margin): that bound is drawn.
    ref = 10 * max((pc.number(r["reference_error"]) for r in rows), default=math.nan)
    ref_strain = max((pc.number(r.get("reference_max_strain")) for r in rows), default=math.nan)

    fig, axes = pc.plt.subplots(1, 2, figsize=(12, 5.2))
    panels = [(axes[0], "max_error", "largest distance from the reference over the frames (m)"),
              (axes[1], "max_strain", "largest strain (l - l0) / l0 over the run")]
    for ax, key, label in panels:
        values = [pc.number(r[key]) for r in rows if r["diverged"] == "0"]
        finite = [v for v in values if v > 0 and math.isfinite(v)]
        if key == "max_error" and ref > 0 and any(r["unresolved"] == "1" for r in rows):
            finite.append(ref)  # drawn at it
        top = max(finite) * 1.5 if finite else 1.0  # where diverged splits are marked
        bottom = min(finite) / 1.5 if finite else 1e-3
        for name, rs in solvers.items():
            color, marker = style(name)
            ok = sorted((r for r in rs if r["diverged"] == "0"), key=lambda r: pc.number(r["substeps"]))
            xs = [pc.number(r["substeps"]) for r in ok]
            ys = []
            for r in ok:
                y = pc.number(r[key])
                if key == "max_error" and r["unresolved"] == "1":
                    y = ref  # no number: at most the reference's resolution
                ys.append(y)
            ax.plot(xs, ys, color=color, marker=marker, label=name)
            hollow = [(x, y) for r, x, y in zip(ok, xs, ys) if key == "max_error" and r["unresolved"] == "1"]
            if hollow:
                ax.scatter([x for x, _ in hollow], [y for _, y in hollow], marker=marker, s=40,
                           facecolors="white", edgecolors=color, zorder=3)
            wrong = [(x, y) for r, x, y in zip(ok, xs, ys) if r["wrong"] == "1"]
            if wrong:
                ax.scatter([x for x, _ in wrong], [y for _, y in wrong], marker="s", s=150,
                           facecolors="none", edgecolors="red", linewidths=1.5, zorder=4)
            bad = [pc.number(r["substeps"]) for r in rs if r["diverged"] == "1"]
            if bad:
                ax.scatter(bad, [top] * len(bad), marker="x", color=color, s=50, zorder=3)
        # The reference's resolution (errors under it are not measured), and its own largest strain.
        line = ref if key == "max_error" else ref_strain
        if line > 0 and line >= bottom:
            ax.axhline(line, color="gray", linestyle=":", linewidth=1,
                       label="10x the reference's error (unresolved under it)" if key == "max_error"
                       else "reference's strain")
            bottom = min(bottom, line / 1.5)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_ylim(bottom, top * 1.3)
        # A narrow range (strains 0.26 .. 0.29) has no decade tick: label the minor ones too.
        ax.yaxis.set_minor_formatter(pc.matplotlib.ticker.FormatStrFormatter("%.3g"))
        ax.tick_params(axis="y", which="minor", labelsize=7)
        ax.set_xlabel(f"substeps s a frame (k = {budget} / s iterations each)")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
        ticks = sorted({pc.number(r["substeps"]) for r in rows})
        ax.set_xticks(ticks)
        ax.set_xticklabels([f"{int(s)}x{int(int(budget) / s)}" for s in ticks], fontsize=7, rotation=30)
        ax.xaxis.set_minor_locator(pc.matplotlib.ticker.NullLocator())
    handles, labels = axes[0].get_legend_handles_labels()
    if any(r["diverged"] == "1" for r in rows):
        handles.append(pc.plt.Line2D([], [], color="black", marker="x", linestyle="None"))
        labels.append("diverged")
    if any(r["wrong"] == "1" for r in rows):
        handles.append(pc.plt.Line2D([], [], marker="s", markerfacecolor="none", markeredgecolor="red",
                                     linestyle="None", markersize=10))
        labels.append("wrong (energy made or over-stretched)")
    axes[0].legend(handles, labels, fontsize=8, loc="best")
    axes[1].legend(fontsize=8, loc="best")
    fig.suptitle(("substeps x iterations = " + budget + ": " + args.title) if args.title
                 else "substeps x iterations = " + budget, fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    pc.save(fig, args.out)


if __name__ == "__main__":
    main()
