"""Shared by the plot scripts: reading clothsim's CSVs and saving a figure headlessly.

Run with Debian's python (/usr/bin/python3) and python3-matplotlib; the Agg backend needs
no display, so the scripts work on a server.
"""
import argparse
import csv
import math
import os
import sys

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: E402  (after use())
except ImportError:  # pragma: no cover - depends on the machine
    sys.stderr.write("plot: matplotlib is missing (apt-get install python3-matplotlib; "
                     "run with /usr/bin/python3)\n")
    sys.exit(3)

# One colour and marker per integrator, the same in every figure.
STYLE = {
    "explicit_euler": ("tab:red", "o"),
    "symplectic_euler": ("tab:orange", "s"),
    "midpoint": ("tab:green", "D"),
    "rk4": ("tab:blue", "^"),
    "implicit_euler": ("tab:purple", "v"),
    # The newer families: each its own colour, so a work-precision plot of all reads apart.
    "velocity_verlet": ("gold", "<"),
    "yoshida4": ("olive", ">"),
    "implicit_midpoint": ("tab:pink", "d"),
    "newmark": ("tab:cyan", "p"),
    "generalized_alpha": ("darkslategray", "h"),
    "bdf2": ("tab:brown", "8"),
    "ros2": ("navy", "*"),
    "imex": ("magenta", "X"),
    "xpbd": ("teal", "P"),
    "projective_dynamics": ("maroon", "X"),
    "vbd": ("darkviolet", "H"),
    # The adaptive pairs, by tolerance: drawn dashed (plot_work_precision.py).
    "bs3": ("yellowgreen", "o"),
    "dopri5": ("black", "s"),
    "rkf78": ("dimgray", "D"),
}


# A lane's variant of its integrator (bench and stability spell lanes as compare takes them:
# "implicit_euler_fixed_point", "xpbd:10"): the integrator's colour, another marker.
FIXED_POINT = "implicit_euler_fixed_point"
VARIANT_MARKERS = ["P", "X", "*", "h", "p"]


def style(name):
    if name in STYLE:
        return STYLE[name]
    base, _, iterations = name.partition(":")
    if base == FIXED_POINT:
        color = "tab:brown" if not iterations else "tab:pink"
        return color, "P"
    color = STYLE.get(base, ("tab:gray", "."))[0]
    if not iterations:
        return color, "."
    return color, VARIANT_MARKERS[int(iterations) % len(VARIANT_MARKERS)] if iterations.isdigit() else "."


def lane_label(name):
    """A lane as compare labels it (LaneSpec::name): "implicit_euler (fixed point)", "xpbd:10"."""
    base, colon, iterations = name.partition(":")
    if base == FIXED_POINT:
        return "implicit_euler" + colon + iterations + " (fixed point)"
    if base == "implicit_euler" and iterations == "1":
        return name + " (Baraff & Witkin)"
    return name


def study_parser(doc, study):
    """The options every study's figure takes: --csv (the study's), --out and --title."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--csv", required=True, help="output of clothsim %s --csv" % study)
    ap.add_argument("--out", required=True, help="PNG to write")
    ap.add_argument("--title", default="", help="figure title")
    return ap


def read_rows(path):
    """Rows of a CSV as dicts; exits with a one-line message naming the file on failure."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        fail(f"{path}: cannot read: {e.strerror}")
    if not rows:
        fail(f"{path}: no rows")
    return rows


def number(text):
    """A CSV cell as a float; empty or unparsable cells are NaN."""
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def require(rows, path, columns):
    missing = [c for c in columns if c not in rows[0]]
    if missing:
        fail(f"{path}: missing column(s) {', '.join(missing)}")


def fail(message):
    sys.stderr.write(f"plot: {message}\n")
    sys.exit(2)


def save(fig, out):
    """Writes the PNG under a temporary name and renames it, so `out` is whole or absent.
    A descriptor (/dev/fd/N: clothsim's nameless file) or a device is written straight."""
    if out.startswith("/dev/fd/") or (os.path.exists(out) and not os.path.isfile(out)):
        try:
            fig.savefig(out, dpi=120, format="png")
        except OSError as e:
            fail(f"cannot write {out}: {e.strerror}")
        finally:
            plt.close(fig)
        return
    directory = os.path.dirname(os.path.abspath(out))
    if not os.path.isdir(directory):
        fail(f"cannot write {out}: directory {directory} does not exist")
    temp = os.path.join(directory, f".{os.path.basename(out)}.partial-{os.getpid()}.png")
    try:
        fig.savefig(temp, dpi=120)
        os.replace(temp, out)
    except OSError as e:
        if os.path.exists(temp):
            os.remove(temp)
        sys.stderr.write(f"plot: cannot write {out}: {e.strerror}\n")
        sys.exit(1)
    finally:
        plt.close(fig)


# Offsets (points) tried for a point's label, nearest first: right-above, right-below,
# left-above, left-below, then further out.
LABEL_OFFSETS = [(4, 3), (4, -9), (-4, 3), (-4, -9), (8, 10), (8, -16), (-8, 10), (-8, -16)]


def place_labels(ax, items, fontsize=6):
    """Labels points without overlap: items are (x, y, text, color) in data coordinates.

    Each label takes the first offset whose box clears every label placed before it and every
    point; where none does, the first. Call after the axes' scales and limits are set.
    """
    fig = ax.figure
    fig.canvas.draw()  # settles the limits, so data -> display is final
    renderer = fig.canvas.get_renderer()
    scale = fig.dpi / 72.0
    points = [ax.transData.transform((x, y)) for x, y, _, _ in items]
    taken = []
    for (x, y, text, color), (px, py) in zip(items, points):
        probe = ax.text(0, 0, text, fontsize=fontsize)
        box = probe.get_window_extent(renderer)
        probe.remove()
        w, h = box.width, box.height
        choice = None
        for dx, dy in LABEL_OFFSETS:
            x0 = px + dx * scale - (w if dx < 0 else 0)
            y0 = py + dy * scale
            rect = (x0, y0, x0 + w, y0 + h)
            if not any(_overlaps(rect, t) for t in taken) and \
                    not any(_overlaps(rect, (qx - 3, qy - 3, qx + 3, qy + 3)) for qx, qy in points):
                choice = (dx, dy, rect)
                break
        if choice is None:
            dx, dy = LABEL_OFFSETS[0]
            x0 = px + dx * scale
            choice = (dx, dy, (x0, py + dy * scale, x0 + w, py + dy * scale + h))
        dx, dy, rect = choice
        taken.append(rect)
        ax.annotate(text, (x, y), textcoords="offset points", xytext=(dx, dy), fontsize=fontsize,
                    color=color, ha="right" if dx < 0 else "left")


def _overlaps(a, b):
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]
