#!/usr/bin/python3
"""The convergence figure of a `clothsim converge --csv` file.

Two panels, RMS distance from the converged backward-Euler step (log) against iterations
(log) and against the step's CPU time (log): one line per method, the mean over the states.
An iteration count at which any state's step read WRONG (column wrong, when present: energy
made with no work done, or strain past its bound) carries a red square.

    /usr/bin/python3 tools/plot_convergence.py --csv converge.csv --out converge.png
"""
from collections import OrderedDict, defaultdict

import plot_common as pc


def main():
    ap = pc.study_parser(__doc__, "converge")
    args = ap.parse_args()

    rows = pc.read_rows(args.csv)
    pc.require(rows, args.csv, ["method", "iterations", "rms_distance", "cpu_seconds"])
    sums = OrderedDict()
    for r in rows:
        per = sums.setdefault(r["method"], defaultdict(lambda: [0.0, 0.0, 0, False]))
        cell = per[int(r["iterations"])]
        cell[0] += pc.number(r["rms_distance"])
        cell[1] += pc.number(r["cpu_seconds"])
        cell[2] += 1
        cell[3] = cell[3] or bool(r.get("wrong"))

    plt = pc.plt
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 5))
    for method, per in sums.items():
        its = sorted(per)
        rms = [max(per[i][0] / per[i][2], 1e-16) for i in its]
        cpu = [max(per[i][1] / per[i][2], 1e-7) for i in its]
        left.loglog(its, rms, marker=".", label=method)
        right.loglog(cpu, rms, marker=".", label=method)
        bad = [k for k, i in enumerate(its) if per[i][3]]
        for ax, xs in ((left, its), (right, cpu)):
            if bad:
                ax.scatter([xs[k] for k in bad], [rms[k] for k in bad], marker="s", s=60, facecolors="none",
                           edgecolors="red", linewidths=1.2, zorder=4)
    if any(cell[3] for per in sums.values() for cell in per.values()):
        for ax in (left, right):
            ax.scatter([], [], marker="s", facecolors="none", edgecolors="red", label="wrong (energy made or over-stretched)")
    for ax, xlabel in ((left, "iterations per step"), (right, "CPU per step (s)")):
        ax.set_xlabel(xlabel)
        ax.set_ylabel("RMS distance from backward Euler (m)")
        ax.axhline(1e-2, color="grey", linestyle=":", linewidth=0.8)
        ax.axhline(1e-3, color="grey", linestyle=":", linewidth=0.8)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    pc.save(fig, args.out)  # the CLI passes a descriptor (/dev/fd/3): the format is named there


if __name__ == "__main__":
    main()
