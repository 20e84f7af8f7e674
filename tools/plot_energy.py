#!/usr/bin/python3
"""Energy over time of several `clothsim run --metrics` files, one line per run.

Each file is one run (typically one integrator); its label is the file's name without
the extension unless --labels gives them. The column plotted is total_energy by default
(kinetic + spring + gravity, J); --column picks another (kinetic, spring_potential, ...),
and --relative plots E(t) - E(0), which shows drift when the energies are large.

    for i in explicit_euler symplectic_euler rk4 implicit_euler; do
      build/clothsim run scenes/spring.yaml --integrator $i --dt 0.01 --duration 10 \
          --set cloth.springs.structural.damping=0 --metrics /tmp/$i.csv
    done
    /usr/bin/python3 tools/plot_energy.py /tmp/*.csv --out energy.png
"""
import argparse
import math
import os

import plot_common as pc

UNITS = {"max_strain": "", "contacts": "", "force_evals": "", "newton_iterations": "", "cg_iterations": "",
         "residual": ""}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", nargs="+", help="metrics CSVs written by clothsim run --metrics")
    ap.add_argument("--out", required=True, help="PNG to write")
    ap.add_argument("--labels", default="", help="comma-separated labels, one per file (default: file names)")
    ap.add_argument("--column", default="total_energy", help="column to plot (default total_energy)")
    ap.add_argument("--relative", action="store_true", help="plot the change from the first row")
    ap.add_argument("--log", action="store_true", help="logarithmic y axis (values must be > 0)")
    ap.add_argument("--title", default="", help="figure title")
    args = ap.parse_args()

    labels = [s for s in args.labels.split(",")] if args.labels else \
        [os.path.splitext(os.path.basename(p))[0] for p in args.csv]
    if len(labels) != len(args.csv):
        pc.fail(f"--labels: {len(labels)} labels for {len(args.csv)} files")

    fig, ax = pc.plt.subplots(figsize=(9, 5))
    for path, label in zip(args.csv, labels):
        rows = pc.read_rows(path)
        pc.require(rows, path, ["t", args.column])
        t = [pc.number(r["t"]) for r in rows]
        y = [pc.number(r[args.column]) for r in rows]
        if args.relative:
            y = [v - y[0] for v in y]
        color, _ = pc.style(label)
        line, = ax.plot(t, y, label=label, color=color if label in pc.STYLE else None)
        if any(not math.isfinite(v) for v in y):
            ax.annotate("non-finite", (t[-1], 0), color=line.get_color(), fontsize=8)
    unit = UNITS.get(args.column, "J")
    name = args.column.replace("_", " ")
    ylabel = (f"{name} - its initial value" if args.relative else name) + (f" ({unit})" if unit else "")
    ax.set_xlabel("simulated time t (s)")
    ax.set_ylabel(ylabel)
    if args.log:
        ax.set_yscale("log")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(args.title or f"{name} over time")
    fig.tight_layout()
    pc.save(fig, args.out)


if __name__ == "__main__":
    main()
