"""tools/plot_stability.py: frame-step markers by lane; identical limits both visible."""
import os

from conftest import legend_texts

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "tools", "plot_stability.py")
HEADER = ("param,value,integrator,outcome,stable_dt,unstable_dt,trials,cpu_seconds,w_max,c_max,dt_springs,"
          "dt_with_damping,duration,min_dt,max_dt,precision,reason,failure,frame_steps\n")


def row(value, name, stable, frames=""):
    return (f"ks,{value},{name},bracketed,{stable},{stable * 1.1},5,0.1,100,1,0.02,0.02,1,1e-5,1,0.01,,,"
            f"\"{frames}\"\n")


def test_the_fixed_point_and_backward_euler_frame_steps_are_labelled_apart(tmp_path):
    csv = tmp_path / "s.csv"
    csv.write_text(HEADER
                   + row(100, "explicit_euler", 0.001) + row(400, "explicit_euler", 0.0005)
                   + row(100, "midpoint", 0.001) + row(400, "midpoint", 0.0005)
                   + row(100, "implicit_euler", 0.01, "1/60 s: ok, 12 steps converged")
                   + row(100, "implicit_euler_fixed_point", 0.001, "1/60 s: diverged at t = 0.1 s"))
    out = tmp_path / "s.png"
    labels = legend_texts(SCRIPT, csv, out)
    assert "implicit_euler at one step per frame: converged" in labels
    assert "implicit_euler (fixed point) at one step per frame: diverged" in labels
    assert not any(l.startswith("implicit_euler at one step per frame: diverged") for l in labels)
    assert "midpoint (the same limits as explicit_euler)" in labels, labels
    assert out.stat().st_size > 0


def test_limits_shared_at_some_values_are_drawn_apart_and_counted(tmp_path):
    # As on the drape: explicit Euler and midpoint meet where the dampers bind, part where the
    # springs do; midpoint's line must not hide explicit Euler's where they meet.
    csv = tmp_path / "s.csv"
    csv.write_text(HEADER
                   + row(100, "explicit_euler", 0.001) + row(400, "explicit_euler", 0.001)
                   + row(1600, "explicit_euler", 0.0001)
                   + row(100, "midpoint", 0.001) + row(400, "midpoint", 0.00101) + row(1600, "midpoint", 0.0005))
    out = tmp_path / "s.png"
    labels = legend_texts(SCRIPT, csv, out)
    assert "midpoint (the same limits as explicit_euler at 2 of 3 values)" in labels, labels
    assert "explicit_euler" in labels
