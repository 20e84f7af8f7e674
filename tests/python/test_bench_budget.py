# clothsim.bench(..., budget=N): `clothsim bench --budget N` as a keyword (tools/python/bench_binding.cpp,
# planned and written by src/clip/studies/budget_plan like the CLI's): the same CSV cell for cell but
# the measured times, the verdicts the CLI prints, and its refusals.
import os

import pytest

import clothsim
from conftest import SCENES
from test_bench import rows_without_times, run_cli, same_frame

DRAPE = os.path.join(SCENES, "drape.yaml")
SETS = {"cloth.particles": "[5,5]"}


def test_budget_is_the_clis_bench_budget_with_its_verdicts(cli, tmp_path):
    scene = clothsim.load_scene(DRAPE, set=SETS)
    frame = clothsim.bench(scene, budget=2, duration=0.1, csv=str(tmp_path / "py.csv"))
    out = run_cli(cli, "bench", DRAPE, "--set", "cloth.particles=[5,5]", "--budget", "2", "--duration", "0.1",
                  "--csv", str(tmp_path / "cli.csv"))
    assert rows_without_times(tmp_path / "py.csv") == rows_without_times(tmp_path / "cli.csv")
    same_frame(frame, tmp_path / "cli.csv")
    assert list(frame.solver.unique()) == ["xpbd", "vbd", "projective_dynamics", "implicit_euler"]
    assert list(frame.substeps * frame.iterations) == [2] * 8
    # Equal sweeps a frame, whatever the split: s x k x frames for the iterative solvers.
    sweeps = frame[frame.solver != "implicit_euler"]
    assert (sweeps.solver_iterations == 2 * sweeps.frames).all()
    verdicts = frame.attrs["verdicts"]
    assert len(verdicts) == 4 and all(v.partition(", CPU ")[0] in out for v in verdicts)  # CPU: measured
    assert verdicts[0].startswith("xpbd at N = 2: ")


def test_budget_refuses_as_the_cli_does(tmp_path):
    scene = clothsim.load_scene(DRAPE, set=SETS)
    with pytest.raises(clothsim.UsageError, match="--integrators: 'rk4': not an iterative solver"):
        clothsim.bench(scene, budget=4, integrators="rk4", duration=0.1)
    with pytest.raises(clothsim.UsageError, match="--budget: --dts sweeps steps"):
        clothsim.bench(scene, budget=4, dts=[1e-3], duration=0.1)
    with pytest.raises(clothsim.UsageError, match="--fps: the frame of --budget"):
        clothsim.bench(scene, fps=60, duration=0.1)
    with pytest.raises(clothsim.UsageError, match="not a whole number of frames at 60 frames/s"):
        clothsim.bench(scene, budget=4, fps=60, duration=0.11, csv=str(tmp_path / "x.csv"))
    assert not any(tmp_path.iterdir()), "nothing written for a refused call"
