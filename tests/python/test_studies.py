# bench, stability and converge from Python with the CLI's defaults (tools/python/study_binding.cpp
# plans them with the CLI's own code, src/clip/studies/*_plan.h): a call with only a scene is the
# CLI's study with only a scene, its CSV equal to the last bit but for the measured times.
import os

import pytest

import clothsim
from conftest import SCENES

SPRING = os.path.join(SCENES, "spring.yaml")
DRAPE = os.path.join(SCENES, "drape.yaml")


def _csv_pair(cli, tmp_path, command, call):
    """The study's CSV from Python (`call(csv=...)`) and from `clothsim COMMAND SPRING --csv`."""
    frame = call(csv=str(tmp_path / "py.csv"))
    code, _, err = cli(command, SPRING, "--csv", str(tmp_path / "cli.csv"), "--quiet")
    assert code == 0, err
    return frame, (tmp_path / "py.csv").read_text().splitlines(), (tmp_path / "cli.csv").read_text().splitlines()


def _without(lines, columns):
    """Each row without the named columns (the measured times), split at commas outside quotes."""
    import csv
    rows = list(csv.reader(lines))
    drop = {rows[0].index(c) for c in columns}
    return [[cell for i, cell in enumerate(row) if i not in drop] for row in rows]


def test_bench_with_only_a_scene_is_the_clis_bench_with_only_a_scene(cli, tmp_path):
    scene = clothsim.load_scene(SPRING)
    frame, py, ref = _csv_pair(cli, tmp_path, "bench", lambda **kw: clothsim.bench(scene, **kw))
    assert list(frame.columns) == ref[0].split(",")
    # The CLI's defaults: four lanes at the scene's dt x 0.25 .. 8.
    assert sorted(set(frame.integrator)) == ["explicit_euler", "implicit_euler", "midpoint", "rk4"]
    assert sorted(set(frame.dt)) == pytest.approx([f * scene.dt for f in (0.25, 0.5, 1, 2, 4, 8)])
    assert _without(py, ["wall_seconds", "cpu_seconds"]) == _without(ref, ["wall_seconds", "cpu_seconds"])
    # Explicit Euler's error grows with its step where it is resolved (NaN under the reference's).
    euler = frame[(frame.integrator == "explicit_euler") & (frame.diverged == 0) & (frame.unresolved == 0)]
    assert len(euler) >= 2 and euler.sort_values("dt").rms_error.is_monotonic_increasing


def test_stability_with_only_a_scene_is_the_clis_stability_with_only_a_scene(cli, tmp_path):
    scene = clothsim.load_scene(SPRING)
    frame, py, ref = _csv_pair(cli, tmp_path, "stability", lambda **kw: clothsim.stability(scene, **kw))
    assert list(frame.columns) == ref[0].split(",")
    # The scene's stiffness (100 N/m) x 1 .. 1e4, each with the four default lanes.
    assert sorted(set(frame.value)) == [100, 1e3, 1e4, 1e5, 1e6] and len(frame) == 5 * 4
    assert _without(py, ["cpu_seconds"]) == _without(ref, ["cpu_seconds"])
    # Stiffer springs, a smaller stable step for an explicit method.
    euler = frame[(frame.integrator == "explicit_euler") & (frame.outcome == "bracketed")].sort_values("value")
    assert euler.stable_dt.is_monotonic_decreasing and len(euler) >= 2


def test_converge_with_only_a_scene_is_the_clis_converge_with_only_a_scene(cli, tmp_path):
    scene = clothsim.load_scene(SPRING)
    frame, py, ref = _csv_pair(cli, tmp_path, "converge", lambda **kw: clothsim.converge(scene, **kw))
    assert list(frame.columns) == ref[0].split(",")
    assert len(frame) == 5 * 4 * 50  # the CLI's 5 states x 4 methods x 50 iterations
    assert _without(py, ["cpu_seconds"]) == _without(ref, ["cpu_seconds"])


def test_studies_refuse_as_the_cli_does_with_its_message():
    scene = clothsim.load_scene(SPRING)
    with pytest.raises(clothsim.UsageError, match="bench sweeps the step"):
        clothsim.bench(scene, integrators="rk4@1e-3")
    with pytest.raises(clothsim.UsageError, match="--integrators: 'rk4' is not an iterative method"):
        clothsim.converge(scene, integrators=["rk4"])
    with pytest.raises(ValueError, match="--param"):
        clothsim.stability(scene, param="cloth.no_such_key", values=[1, 2])


def test_compare_runs_a_loaded_scenes_duration_and_step():
    scene = clothsim.load_scene(SPRING, duration=0.1, dt=5e-4)
    frame = clothsim.compare(scene, integrators="symplectic_euler,rk4", match="none")
    # Every lane at the loaded step, to the loaded duration: 0.1 s / 5e-4 s = 200 steps.
    assert list(frame.dt) == [5e-4, 5e-4]
    assert list(frame.steps) == [200, 200]
    # The keyword still wins over the loaded scene's duration, as --duration does.
    assert list(clothsim.compare(scene, integrators="rk4", match="none", duration=0.05).steps) == [100]


def test_stability_and_converge_take_summary_plot_and_shard_as_the_cli(cli, tmp_path):
    scene = clothsim.load_scene(SPRING)
    kw = dict(integrators="symplectic_euler", values=[100, 400], precision=0.1, frame_dts=[])
    clothsim.stability(scene, summary=str(tmp_path / "py.json"), plot=str(tmp_path / "py.png"), **kw)
    code, _, err = cli("stability", SPRING, "--integrators", "symplectic_euler", "--values", "100,400",
                       "--precision", "0.1", "--frame-dts", "none", "--summary", str(tmp_path / "cli.json"), "--quiet")
    assert code == 0, err
    import json
    py, ref = (json.loads((tmp_path / f"{n}.json").read_text()) for n in ("py", "cli"))
    for s in (py, ref):
        s.pop("command")
        for lane in s["lanes"]:
            lane.pop("cpu_seconds")
    assert py == ref and len(py["lanes"]) == 2
    assert (tmp_path / "py.png").read_bytes()[:4] == b"\x89PNG"
    # converge's parts, merged by the CLI, are its whole study.
    ckw = dict(integrators="vbd,xpbd", states=2, max_iterations=3)
    parts = [clothsim.converge(scene, shard=f"{k}/2", csv=str(tmp_path / "cv.csv"), **ckw) for k in (1, 2)]
    assert sum(len(p) for p in parts) == 2 * 2 * 3
    code, _, err = cli("merge", str(tmp_path / "cv.csv.shard-1-of-2"), str(tmp_path / "cv.csv.shard-2-of-2"),
                       "--csv", str(tmp_path / "merged.csv"))
    assert code == 0, err
    code, _, err = cli("converge", SPRING, "--integrators", "vbd,xpbd", "--states", "2", "--max-iterations", "3",
                       "--csv", str(tmp_path / "cli.csv"), "--quiet")
    assert code == 0, err
    merged, whole = ((tmp_path / n).read_text().splitlines() for n in ("merged.csv", "cli.csv"))
    assert _without(merged, ["cpu_seconds"]) == _without(whole, ["cpu_seconds"])


def test_max_memory_and_compares_picture_keywords_are_the_clis_options(cli):
    scene = clothsim.load_scene(SPRING)
    # The budget is read by the CLI's own parser and checked by its own estimate, message and all.
    code, _, err = cli("bench", SPRING, "--max-memory", "1K", "--quiet")
    assert code == 2
    with pytest.raises(clothsim.UsageError) as e:
        clothsim.bench(scene, max_memory="1K")
    assert "clothsim: " + str(e.value) == err.strip().splitlines()[-1]
    with pytest.raises(clothsim.UsageError, match=r"--max-memory: 'lots' is not a size \(e.g. 4G"):
        clothsim.converge(scene, max_memory="lots")
    with pytest.raises(clothsim.UsageError, match="--max-memory"):
        clothsim.stability(scene, max_memory=1024)
    with pytest.raises(clothsim.UsageError, match="--camera"):
        clothsim.compare(scene, camera="sideways")
    frame = clothsim.compare(scene, integrators="rk4", match="none", duration=0.05, camera="auto", antialias="fxaa")
    assert list(frame.steps) == [50]


def test_compare_shard_draws_its_part_of_the_lanes_as_the_cli_part_does(cli, tmp_path):
    # Two lanes, part 1 of 2: each draws its own lanes' PNGs, byte for byte the CLI part's.
    args = dict(integrators="symplectic_euler,rk4", match="none", duration=0.05, width=96, height=64, fps=40,
                color="checker")
    clothsim.compare(SPRING, frames=str(tmp_path / "py"), shard="1/2", **args)
    code, _, err = cli("compare", SPRING, "--integrators", args["integrators"], "--match", "none", "--duration",
                       "0.05", "--width", "96", "--height", "64", "--fps", "40", "--color", "checker",
                       "--frames", str(tmp_path / "cli"), "--shard", "1/2", "--quiet")
    assert code == 0, err
    py = sorted(p.relative_to(tmp_path / "py") for p in (tmp_path / "py").rglob("*.png"))
    ref = sorted(p.relative_to(tmp_path / "cli") for p in (tmp_path / "cli").rglob("*.png"))
    assert py == ref and len(py) >= 2
    assert len({p.parts[0] for p in py}) == 1, "one of the two lanes in part 1"
    for p in py:
        assert (tmp_path / "py" / p).read_bytes() == (tmp_path / "cli" / p).read_bytes(), p
