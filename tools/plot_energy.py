#!/usr/bin/python3
"""Energy over time of several `clothsim run --metrics` files, one line per run.

Each file is one run, a lane: an integrator at a step. Its label is the integrator and step
the file's scene,integrator,dt columns name (and the scene when the files come from several),
unless --labels gives them; files without those columns are labelled by their names. Lines
are drawn by lane: the integrator's colour (the same in every figure), and a line style per
step within it, so two implicit Euler runs at 1/60 s and 1/240 s are told apart. The legend
sits outside the axes, beside them, so no label covers a curve. The column plotted is total_energy by default
(kinetic + spring + gravity, J); --column picks another (kinetic, spring_potential, ...),
and --relative plots E(t) - E(0), which shows drift when the energies are large. Each lane's
change over the run, lowest and highest E(t) - E(0) are printed, one line per lane.

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


def run_labels(paths, runs):
    """'rk4, dt = 0.0001 s' from each file's columns (with the scene when they differ)."""
    if not all(runs[i] and "integrator" in runs[i][0] and "dt" in runs[i][0] for i in range(len(runs))):
        return [os.path.splitext(os.path.basename(p))[0] for p in paths]  # older files: by name
    scenes = {rows[0].get("scene", "") for rows in runs}
    labels = []
    for rows in runs:
        r = rows[0]
        label = f"{r['integrator']}, dt = {pc.number(r['dt']):g} s"
        labels.append(f"{r.get('scene', '')}: {label}" if len(scenes) > 1 else label)
    return labels


def lane_styles(runs, labels):
    """(colour, line style) per run: the integrator's colour, a style per step within it."""
    styles = ["-", "--", ":", "-."]
    steps = {}  # integrator -> its steps, in the order met
    out = []
    for rows, label in zip(runs, labels):
        r = rows[0] if rows else {}
        integrator = r.get("integrator", label)
        step = (r.get("scene", ""), r.get("dt", label))
        seen = steps.setdefault(integrator, [])
        if step not in seen:
            seen.append(step)
        color = pc.style(integrator)[0] if integrator in pc.STYLE or integrator.startswith(pc.FIXED_POINT) else None
        out.append((color, styles[seen.index(step) % len(styles)]))
    return out


def plot(runs, labels, column="total_energy", relative=False, log=False, title="", paths=None):
    """The figure: one line per run, drawn by lane; returns (fig, ax)."""
    fig, ax = pc.plt.subplots(figsize=(10, 5))
    for path, label, rows, (color, dash) in zip(paths or labels, labels, runs, lane_styles(runs, labels)):
        pc.require(rows, path, ["t", column])
        t = [pc.number(r["t"]) for r in rows]
        y = [pc.number(r[column]) for r in rows]
        if relative:
            y = [v - y[0] for v in y]
        line, = ax.plot(t, y, label=label, color=color, linestyle=dash, linewidth=1.6)
        if any(not math.isfinite(v) for v in y):
            ax.annotate("non-finite", (t[-1], 0), color=line.get_color(), fontsize=8)
    unit = UNITS.get(column, "J")
    name = column.replace("_", " ")
    ylabel = (f"{name} - its initial value" if relative else name) + (f" ({unit})" if unit else "")
    ax.set_xlabel("simulated time t (s)")
    ax.set_ylabel(ylabel)
    if log:
        ax.set_yscale("log")
    ax.margins(x=0.01, y=0.06)  # curves off the frame, so a tick label never sits on one
    ax.grid(True, alpha=0.3)
    # Beside the axes, not over them: a report figure's curves stay whole.
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, title="lane")
    ax.set_title(title or f"{name} over time")
    fig.tight_layout()
    return fig, ax


def summary(runs, labels, column="total_energy"):
    """One line per lane, the figures a report quotes: its change over the run and extremes."""
    unit = UNITS.get(column, "J")
    out = []
    for label, rows in zip(labels, runs):
        y = [pc.number(r[column]) for r in rows]
        d = [v - y[0] for v in y]
        t_end = pc.number(rows[-1]["t"])
        out.append(f"{label}: {column} at t = {t_end:g} s minus at 0: {d[-1]:.4g} {unit}; "
                   f"lowest {min(d):.4g} {unit}, highest {max(d):.4g} {unit}")
    return out


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

    runs = [pc.read_rows(p) for p in args.csv]
    labels = [s for s in args.labels.split(",")] if args.labels else run_labels(args.csv, runs)
    if len(labels) != len(args.csv):
        pc.fail(f"--labels: {len(labels)} labels for {len(args.csv)} files")
    fig, _ = plot(runs, labels, args.column, args.relative, args.log, args.title, args.csv)
    pc.save(fig, args.out)
    for line in summary(runs, labels, args.column):
        print(line)


if __name__ == "__main__":
    main()
