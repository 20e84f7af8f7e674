"""tools/plot_budget.py: a line per solver against the substeps; diverged, WRONG and unresolved splits marked."""
import os
import subprocess

from conftest import legend_texts

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "tools", "plot_budget.py")
COLUMNS = ("solver,lane,budget,substeps,iterations,dt,fps,duration,frames,steps,force_evals,solver_iterations,"
           "newton_iterations,cg_iterations,wall_seconds,cpu_seconds,max_error,max_error_t,final_error,max_strain,"
           "energy_lost_per_s,unresolved,diverged,diverged_at,reason,unconverged_steps,max_residual,wrong,wrong_at,"
           "wrong_reason,reference_error,reference_max_strain,reference_energy_lost_per_s,colliders_move")


def row(solver, s, error, strain, unresolved=0, diverged=0, wrong=0):
    cells = dict(solver=solver, lane=f"{solver}@1/{60 * s}:{6 // s}", budget=6, substeps=s, iterations=6 // s,
                 dt=1 / (60 * s), fps=60, duration=0.5, frames=30, steps=30 * s, force_evals=0, solver_iterations=180,
                 newton_iterations=0, cg_iterations=0, wall_seconds=0.01, cpu_seconds=0.01, max_error=error,
                 max_error_t=0.5, final_error=error, max_strain=strain, energy_lost_per_s=1, unresolved=unresolved,
                 diverged=diverged, diverged_at="0.2" if diverged else "", reason="", unconverged_steps=0,
                 max_residual=0, wrong=wrong, wrong_at="", wrong_reason="", reference_error=1e-4,
                 reference_max_strain=0.07, reference_energy_lost_per_s=1, colliders_move=0)
    return ",".join(str(cells[c]) for c in COLUMNS.split(",")) + "\n"


def legend(tmp_path, csv):
    out = tmp_path / "b.png"
    labels = legend_texts(SCRIPT, csv, out)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    return labels


def test_each_solver_is_a_line_and_each_mark_is_explained(tmp_path):
    csv = tmp_path / "b.csv"
    csv.write_text(COLUMNS + "\n" + row("xpbd", 1, 0.2, 0.1, wrong=1) + row("xpbd", 2, "nan", "nan", diverged=1)
                   + row("xpbd", 3, 0.1, 0.08) + row("xpbd", 6, 0.05, 0.075)
                   + row("vbd", 1, 0.09, 0.064) + row("vbd", 2, 0.06, 0.068) + row("vbd", 3, 0.04, 0.07)
                   + row("vbd", 6, "nan", 0.073, unresolved=1))
    labels = legend(tmp_path, csv)
    for text in ("xpbd", "vbd", "diverged", "wrong (energy made or over-stretched)",
                 "10x the reference's error (unresolved under it)", "reference's strain"):
        assert text in labels, labels


def test_a_csv_without_the_budget_columns_is_refused_naming_the_file(tmp_path):
    csv = tmp_path / "wp.csv"
    csv.write_text("integrator,dt,rms_error\nrk4,0.001,1e-6\n")
    r = subprocess.run(["/usr/bin/python3", SCRIPT, "--csv", str(csv), "--out", str(tmp_path / "x.png")],
                       capture_output=True, text=True)
    assert r.returncode == 2
    assert r.stderr.startswith(f"plot: {csv}: missing column(s) solver, budget, substeps"), r.stderr
    assert not (tmp_path / "x.png").exists()
