"""tools/plot_energy.py: a line per lane (integrator and step), the legend beside the axes."""
import plot_energy as pe


def rows(integrator, dt, energies):
    return [{"t": str(0.1 * i), "total_energy": str(e), "integrator": integrator, "dt": str(dt), "scene": "drape"}
            for i, e in enumerate(energies)]


RUNS = [rows("implicit_euler", 1 / 60, [5, 4, 3]), rows("implicit_euler", 1 / 240, [5, 4.5, 4]),
        rows("rk4", 1e-4, [5, 5, 5]), rows("implicit_euler_fixed_point", 1e-4, [5, 6, 7])]


def test_two_steps_of_one_integrator_are_two_lanes_told_apart():
    labels = pe.run_labels(["a", "b", "c", "d"], RUNS)
    assert len(set(labels)) == 4
    styles = pe.lane_styles(RUNS, labels)
    assert styles[0][0] == styles[1][0], "one integrator, one colour"
    assert styles[0][1] != styles[1][1], "its two steps, two line styles"
    assert styles[3][0] not in (styles[0][0], None), "the fixed point has a colour of its own"


def test_the_legend_sits_beside_the_axes_not_over_the_curves():
    labels = pe.run_labels(["a", "b", "c", "d"], RUNS)
    fig, ax = pe.plot(RUNS, labels, relative=True)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    legend = ax.get_legend().get_window_extent(renderer)
    axes = ax.get_window_extent(renderer)
    assert legend.x0 >= axes.x1, "the legend starts right of the axes"
    assert legend.x1 <= fig.bbox.x1 + 1, "and is inside the figure"
    assert [t.get_text() for t in ax.get_legend().get_texts()] == labels
    assert ax.get_ylabel().startswith("total energy - its initial value")


def test_each_lane_prints_its_change_and_extremes():
    labels = pe.run_labels(["a", "b", "c", "d"], RUNS)
    lines = pe.summary(RUNS, labels)
    assert lines[0] == ("implicit_euler, dt = 0.0166667 s: total_energy at t = 0.2 s minus at 0: -2 J; "
                        "lowest -2 J, highest 0 J")
    assert lines[3].endswith("highest 2 J")


def test_the_families_figure_gives_each_lane_a_colour_of_its_own():
    # docs/report.md's families figure: imex once fell back to the colour cycle's first, rk4's blue.
    names = ["rk4", "implicit_euler", "newmark", "implicit_midpoint", "bdf2", "imex"]
    runs = [rows(n, 1 / 60, [5, 4]) for n in names]
    colours = [c for c, _ in pe.lane_styles(runs, pe.run_labels(names, runs))]
    assert None not in colours and len(set(colours)) == len(names), colours
