# The Python module against the CLI: the same scenes, the same states to the last bit, the
# same one-line messages, the same pictures and exported files.
import os
import textwrap
import time

import numpy as np
import pytest

import clothsim
from conftest import ROOT, SCENES, interrupted_script, read_state_csv

DRAPE = os.path.join(SCENES, "drape.yaml")
STIFF = os.path.join(SCENES, "stiff.yaml")


# The lane grammar's strings (scene/lane.h) as tests/cli/lane_doors_test.cpp runs them through
# the CLI's doors: Python's Simulation(lane=...) is one more door, to the last bit the same run.
@pytest.mark.parametrize("lane", ["rk4@1e-4", "symplectic_euler", "implicit_euler@4e-3", "xpbd@2e-3",
                                  "xpbd@1/60:5", "vbd@1/100:tol=1e-4", "implicit_euler@1/60:1",
                                  "implicit_euler_fixed_point@1e-4", " projective_dynamics @ 1/200 : 4 ",
                                  "dopri5@1e-3:tol=1e-6", "rkf78:rtol=1e-8:atol=1e-6",
                                  "newmark@1/60:beta=0.3:gamma=0.6", "generalized_alpha@1/60:rho=0.5", "bdf2@1/60"])
def test_run_ends_in_the_clis_final_state_to_the_last_bit(cli, tmp_path, lane):
    adaptive = lane.startswith(("dopri5", "rkf78"))
    path = os.path.join(SCENES, "drape_smooth.yaml") if adaptive else DRAPE  # contact its error control sees
    scene = clothsim.load_scene(path, duration=0.2)
    sim = clothsim.Simulation(scene, lane=lane)
    sim.run(until=0.2)
    code, _, err = cli("run", path, "--duration", "0.2", "--integrator", lane, "--state", str(tmp_path / "s.csv"),
                       "--quiet")
    assert code == 0, err
    x, v = read_state_csv(tmp_path / "s.csv")
    if adaptive:
        # An adaptive pair shortens a step to land on every target: the CLI's run lands on its
        # frames, run(until=0.2) on 0.2 only, so the two agree to the tolerance, not the bit.
        assert np.allclose(sim.positions, x, rtol=0, atol=1e-5)
        return
    assert np.array_equal(sim.positions, x)
    assert np.array_equal(sim.velocities, v)


def test_set_takes_the_clis_keys_and_the_ks_alias_sets_every_spring_type(cli, tmp_path):
    scene = clothsim.load_scene(DRAPE, set={"ks": 5000, "air_drag": 0.01}, duration=0.1)
    sim = clothsim.Simulation(scene)
    sim.run(until=0.1)
    sets = [f"cloth.springs.{t}.stiffness=5000" for t in ("structural", "shear", "bend")] + ["air_drag=0.01"]
    code, _, err = cli("run", DRAPE, "--duration", "0.1", "--state", str(tmp_path / "s.csv"), "--quiet",
                       *[a for s in sets for a in ("--set", s)])
    assert code == 0, err
    x, _ = read_state_csv(tmp_path / "s.csv")
    assert np.array_equal(sim.positions, x)


def test_positions_and_velocities_are_read_only_views_of_the_state_not_copies():
    sim = clothsim.Simulation(clothsim.load_scene(DRAPE))
    p = sim.positions
    assert p.shape == (625, 3) and p.dtype == np.float64
    assert p.strides == (24, 8)  # the 3 x P column-major matrix, seen as P x 3 rows
    assert not p.flags.owndata and not p.flags.writeable
    assert np.shares_memory(p, sim.positions)
    before = p.copy()
    sim.step()
    assert sim.steps == 1 and sim.t == pytest.approx(1e-4)
    assert not np.array_equal(sim.positions, before)  # the view shows the state as it is now


def test_spheres_are_where_the_scenes_timeline_has_moved_them_at_t():
    # drape's kinematic ball rests at the origin, then moves at 5 m/s along z from t = 1 to 1.3.
    sim = clothsim.Simulation(clothsim.load_scene(DRAPE, set={"cloth.particles": [5, 5]}), lane="symplectic_euler@1e-4")
    assert sim.spheres.shape == (1, 3) and list(sim.sphere_radii) == [1.0]
    sim.run(until=0.5)
    assert np.array_equal(sim.spheres, [[0.0, 0.0, 0.0]])
    sim.run(until=1.2)
    assert sim.spheres[0] == pytest.approx([0.0, 0.0, 5.0 * (sim.t - 1.0)], abs=5.0 * sim.dt)
    sim.run(until=2.0)  # stopped at 1.3: 1.5 m along z
    assert sim.spheres[0] == pytest.approx([0.0, 0.0, 1.5], abs=5.0 * sim.dt)
    # A view of the state, as .positions: the sphere is body P of the same matrix.
    assert not sim.spheres.flags.writeable and sim.spheres.strides == (24, 8)


def test_a_bad_scene_raises_the_clis_one_line_message(cli, tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text(open(DRAPE).read().replace("air_drag: 3.4e-4", "air_drag: -1"))
    with pytest.raises(clothsim.SceneError) as e:
        clothsim.load_scene(str(bad))
    code, _, err = cli("run", str(bad))
    assert code == 2
    assert err.strip() == "clothsim: " + str(e.value)


def test_an_unknown_set_key_names_the_key_as_run_does(cli):
    with pytest.raises(clothsim.SceneError) as e:
        clothsim.load_scene(DRAPE, set={"cloth.sprongs": 1})
    _, _, err = cli("run", DRAPE, "--set", "cloth.sprongs=1")
    assert err.strip() == "clothsim: " + str(e.value)


def test_divergence_is_the_verdict_and_message_run_gives(cli):
    stiff = os.path.join(SCENES, "stiff.yaml")
    sim = clothsim.Simulation(clothsim.load_scene(stiff), lane="explicit_euler")
    sim.run(until=1.0)
    code, _, err = cli("run", stiff, "--integrator", "explicit_euler", "--duration", "1", "--quiet")
    assert code == 3 and sim.diverged
    assert err.strip() == "clothsim: " + sim.divergence["message"]
    assert sim.t < 1.0  # stopped there


def test_energies_and_metrics_are_the_metrics_row_of_the_state(cli, tmp_path):
    sim = clothsim.Simulation(clothsim.load_scene(DRAPE, duration=0.1))
    sim.run(until=0.1)
    cli("run", DRAPE, "--duration", "0.1", "--metrics", str(tmp_path / "m.csv"), "--quiet")
    import pandas
    last = pandas.read_csv(tmp_path / "m.csv", float_precision="round_trip").iloc[-1]  # %.17g, exactly
    m = sim.metrics()
    for k in ("step", "kinetic", "spring_potential", "gravity_potential", "total_energy", "max_strain", "force_evals"):
        assert m[k] == last[k], k
    assert sim.energies()["total_energy"] == m["total_energy"]
    assert sim.not_converged == 0 and not sim.diverged and sim.divergence is None


def test_render_draws_what_run_still_draws(cli, tmp_path):
    from PIL import Image
    sim = clothsim.Simulation(clothsim.load_scene(DRAPE))
    sim.run(until=0.5)
    image = clothsim.render(sim, 320, 180)
    assert image.shape == (180, 320, 3) and image.dtype == np.uint8
    code, _, err = cli("run", DRAPE, "--still", "0.5", "-o", str(tmp_path / "s.png"), "--width", "320", "--height",
                       "180", "--overlay", "none", "--quiet")
    assert code == 0, err
    png = np.asarray(Image.open(tmp_path / "s.png").convert("RGB"))
    assert np.array_equal(image, png)
    strain = clothsim.render(sim, 320, 180, color="strain")
    assert not np.array_equal(strain, image)  # coloured, not the checker


def test_export_writes_the_files_run_export_writes(cli, tmp_path):
    scene = clothsim.load_scene(DRAPE, duration=0.1)
    sim = clothsim.Simulation(scene)
    out = clothsim.Export(scene, str(tmp_path / "py.pc2"))
    for k in range(4):  # frames at k / 30 s up to 0.1 s
        sim.run(until=k / 30.0)
        out.add(sim)
    out.finish()
    code, _, err = cli("run", DRAPE, "--duration", "0.1", "--export", str(tmp_path / "cli.pc2"), "--quiet")
    assert code == 0, err
    for ext in (".pc2", ".sphere0.pc2", ".sphere0.obj"):
        assert (tmp_path / ("py" + ext)).read_bytes() == (tmp_path / ("cli" + ext)).read_bytes(), ext
    with pytest.raises(clothsim.ExportError, match="--export: x.stl: unknown format"):
        clothsim.Export(scene, "x.stl")


def test_a_shipped_scene_loads_by_bare_name_and_a_nul_never_truncates_a_path(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # no drape.yaml here: the shipped one
    assert clothsim.load_scene("drape").particles == clothsim.load_scene(DRAPE).particles
    with pytest.raises(ValueError, match="NUL"):
        clothsim.load_scene(os.path.join(SCENES, "spring.yaml") + "\0.evil")
    scene = clothsim.load_scene(DRAPE, duration=0.1)
    with pytest.raises(ValueError, match="NUL"):
        clothsim.Export(scene, str(tmp_path / "x\0y.pc2"))
    for fps in (0, -1, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="fps"):
            clothsim.Export(scene, str(tmp_path / "v.pvd"), fps=fps)


def test_the_niceties_a_user_expects(cli, tmp_path):
    code, out, _ = cli("--version")
    assert clothsim.__version__ in out
    # A path wherever a Scene is taken; verdicts as booleans; Export.written as paths.
    frame = clothsim.bench(os.path.join(SCENES, "spring.yaml"), integrators="rk4,explicit_euler", duration=0.2)
    assert frame["diverged"].dtype == bool and frame["unresolved"].dtype == bool
    assert frame[~frame.diverged].shape[0] == frame.shape[0]
    scene = clothsim.load_scene(DRAPE, duration=0.1)
    out = clothsim.Export(scene, str(tmp_path / "o" / "f_%05d.obj"))
    assert clothsim.Simulation(DRAPE).positions.shape == (scene.particles, 3)
    sim = clothsim.Simulation(scene)
    out.add(sim)
    out.finish()
    assert out.written == [str(tmp_path / "o" / "f_00000.obj"), str(tmp_path / "o" / "f_sphere0_00000.obj")]
    assert out.summary.startswith("2 OBJ files in ")


def test_export_refuses_a_frame_name_linked_to_the_scene(tmp_path):
    scene_path = tmp_path / "s.yaml"
    scene_path.write_bytes(open(DRAPE, "rb").read())
    (tmp_path / "out").mkdir()
    os.symlink("../s.yaml", tmp_path / "out" / "frame_00000.obj")
    scene = clothsim.load_scene(str(scene_path), duration=0.1)
    out = clothsim.Export(scene, str(tmp_path / "out" / "frame_%05d.obj"))
    with pytest.raises(clothsim.ExportError, match="an output never replaces an input"):
        out.add(clothsim.Simulation(scene))
    assert scene_path.read_bytes() == open(DRAPE, "rb").read()


def test_ctrl_c_raises_keyboard_interrupt_in_a_long_run():
    # A run of minutes, interrupted 1 s in by SIGINT, as Ctrl-C sends it.
    script = textwrap.dedent(f"""
        import time, clothsim
        sim = clothsim.Simulation(clothsim.load_scene({DRAPE!r}), lane="rk4@1e-5")
        print("running", flush=True)
        try:
            sim.run(until=1e3)
        except KeyboardInterrupt:
            print("interrupted at t =", sim.t, "after", time.monotonic(), flush=True)
    """)
    out, sent = interrupted_script(script, after=1.0)
    assert out.startswith("interrupted at t = "), out
    t, after = float(out.split()[4]), float(out.split()[6])
    assert 0 < t < 1e3
    print(f"KeyboardInterrupt {1000 * (after - sent):.0f} ms after SIGINT")  # docs/python.md; not asserted


def test_run_releases_the_gil():
    import threading
    sim = clothsim.Simulation(clothsim.load_scene(DRAPE), lane="rk4@1e-4")
    ticks = []
    worker = threading.Thread(target=sim.run, kwargs={"until": 0.3})
    worker.start()
    while worker.is_alive():
        ticks.append(time.monotonic())  # Python runs while the engine steps
        time.sleep(0.001)
    worker.join()
    assert len(ticks) > 5 and sim.t >= 0.3


def test_threads_sharing_a_simulation_step_it_one_at_a_time_to_the_serial_state():
    # Two threads in run() on one Simulation crashed the interpreter (5 runs of 6) or, with rk4,
    # ended at t = 0.006 instead of 0.6: now one steps at a time and the other goes on from there.
    import threading
    scene = clothsim.load_scene(DRAPE, set={"cloth.particles": [9, 9]}, duration=0.3)
    serial = clothsim.Simulation(scene, lane="rk4@2.5e-4")
    serial.run(until=0.3)
    for _ in range(4):
        sim = clothsim.Simulation(scene, lane="rk4@2.5e-4")
        seen, errors = [], []

        def run(until):
            try:
                sim.run(until=until)
            except Exception as e:  # noqa: BLE001 - the test reports any
                errors.append(e)

        def read():
            while any(t.is_alive() for t in runners):
                seen.append((sim.t, sim.totals["steps"], sim.positions.shape, sim.metrics()["t"]))
        runners = [threading.Thread(target=run, args=(u,)) for u in (0.3, 0.3, 0.15)]
        reader = threading.Thread(target=read)
        for t in runners:
            t.start()
        reader.start()
        for t in runners + [reader]:
            t.join()
        assert not errors
        assert not serial.diverged and sim.t == serial.t and sim.steps == serial.steps == 1200
        assert np.array_equal(sim.positions, serial.positions)
        assert all(0.0 <= t <= 0.3 + 1e-12 and shape == (81, 3) for t, _, shape, _ in seen)
        assert [s for _, s, _, _ in seen] == sorted(s for _, s, _, _ in seen)  # whole steps, in order


def test_run_until_a_time_that_is_not_one_raises():
    sim = clothsim.Simulation(clothsim.load_scene(DRAPE))
    for until in (float("nan"), float("inf")):
        with pytest.raises(ValueError, match="until must be a finite time in s, got " + str(until)):
            sim.run(until=until)
    assert sim.t == 0.0 and sim.steps == 0


def test_threads_rendering_at_once_draw_what_one_thread_draws():
    # Four threads rendering at once got "eglMakeCurrent failed (EGL error 0x3002)".
    import threading
    sim = clothsim.Simulation(clothsim.load_scene(DRAPE))
    sim.run(until=0.2)
    alone = clothsim.render(sim, 160, 90)
    images, errors = [], []

    def draw():
        try:
            for _ in range(3):
                images.append(clothsim.render(sim, 160, 90))
        except Exception as e:  # noqa: BLE001 - the test reports any
            errors.append(e)
    threads = [threading.Thread(target=draw) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    assert len(images) == 12 and all(np.array_equal(i, alone) for i in images)


def test_export_takes_a_lane_with_settings_of_its_scene_and_writes_what_run_writes(cli, tmp_path):
    # Export.add refused a vbd@1/60:3 Simulation of the same scene as "of another scene": its
    # lane's iterations gave it a model of its own.
    scene = clothsim.load_scene(DRAPE, duration=0.1)
    sim = clothsim.Simulation(scene, lane="vbd@1/60:3")
    out = clothsim.Export(scene, str(tmp_path / "py.pc2"))
    for k in range(4):
        sim.run(until=k / 30.0)
        out.add(sim)
    out.finish()
    code, _, err = cli("run", DRAPE, "--duration", "0.1", "--integrator", "vbd@1/60:3", "--export",
                       str(tmp_path / "cli.pc2"), "--quiet")
    assert code == 0, err
    assert (tmp_path / "py.pc2").read_bytes() == (tmp_path / "cli.pc2").read_bytes()
    other = clothsim.Simulation(clothsim.load_scene(DRAPE, duration=0.1), lane="vbd@1/60:3")
    with pytest.raises(ValueError, match="of another scene"):
        out.add(other)


def test_help_has_docstrings():
    for thing in (clothsim, clothsim.load_scene, clothsim.Simulation, clothsim.Simulation.run, clothsim.render,
                  clothsim.Export):
        assert thing.__doc__ and len(thing.__doc__) > 40, thing


def subprocess_run_integrator(lane):
    import subprocess
    binary = os.environ.get("CLOTHSIM_BINARY", os.path.join(ROOT, "build", "clothsim"))
    p = subprocess.run([binary, "run", DRAPE, "--integrator", lane, "--duration", "0"], capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def test_a_lane_takes_a_step_as_a_fraction_and_refuses_a_bad_one():
    scene = clothsim.load_scene(DRAPE)
    assert clothsim.Simulation(scene, lane="implicit_euler@1/60").dt == 1 / 60
    assert clothsim.Simulation(scene, lane="rk4").dt == scene.dt
    assert clothsim.Simulation(scene).integrator == scene.integrator == "symplectic_euler"
    # The course's fixed point by the name run --metrics gives it, not backward Euler's.
    assert clothsim.Simulation(scene, lane="implicit_euler_fixed_point@1e-4").integrator == "implicit_euler_fixed_point"
    assert clothsim.Simulation(scene, lane="implicit_euler@1/60").integrator == "implicit_euler"
    assert clothsim.Simulation(scene, lane="rk4@1e-3 ").dt == 1e-3, "spaces around the pieces, as the CLI"
    # The CLI's words after its option's name: one grammar, one message.
    for bad, why in (("rk5@1e-4", "unknown integrator 'rk5'"), ("rk4@", "has no step after '@'"),
                     ("rk4@-1", "must be > 0 s"), ("rk4@1/0", "is not a number"), ("rk4@1e-4x", "is not a number"),
                     ("rk4@1/ 60", "is not a number"), ("rk4:3", "rk4 has no iterations to set"),
                     ("vbd@1/60:tol=0.9", "at most 0.5")):
        with pytest.raises(ValueError, match="^lane: .*" + why.replace("(", r"\(")):
            clothsim.Simulation(scene, lane=bad)
        code, _, err = subprocess_run_integrator(bad)
        assert code == 2 and ("--integrator: " in err and why in err), err


def test_converge_is_the_clis_study_and_writes_its_csv(cli, tmp_path):
    scene = clothsim.load_scene(DRAPE)
    frame = clothsim.converge(scene, integrators=["xpbd", "vbd"], states=2, max_iterations=4,
                              csv=str(tmp_path / "py.csv"))
    code, _, err = cli("converge", DRAPE, "--integrators", "xpbd,vbd", "--states", "2", "--max-iterations", "4",
                       "--csv", str(tmp_path / "cli.csv"), "--quiet")
    assert code == 0, err
    py_lines = (tmp_path / "py.csv").read_text().splitlines()
    cli_lines = (tmp_path / "cli.csv").read_text().splitlines()
    assert list(frame.columns) == cli_lines[0].split(",") == py_lines[0].split(",")
    assert len(frame) == len(cli_lines) - 1 == 2 * 2 * 4
    # cpu_seconds, the ninth column, differs run to run (the columns before it hold no comma).
    drop_cpu = lambda line: ",".join(line.split(",", 9)[:8] + line.split(",", 9)[9:])  # noqa: E731
    assert [drop_cpu(l) for l in py_lines] == [drop_cpu(l) for l in cli_lines]


def test_bench_is_the_clis_work_precision_study_and_writes_its_csv(cli, tmp_path):
    scene = clothsim.load_scene(DRAPE)
    frame = clothsim.bench(scene, integrators=["symplectic_euler", "midpoint"], dts=[1e-4, 2e-4], duration=0.02,
                           csv=str(tmp_path / "py.csv"))
    code, _, err = cli("bench", DRAPE, "--integrators", "symplectic_euler,midpoint", "--dts", "1e-4,2e-4",
                       "--duration", "0.02", "--frame-dts", "none", "--csv", str(tmp_path / "cli.csv"), "--quiet")
    assert code == 0, err
    py_lines = (tmp_path / "py.csv").read_text().splitlines()
    cli_lines = (tmp_path / "cli.csv").read_text().splitlines()
    assert list(frame.columns) == cli_lines[0].split(",") == py_lines[0].split(",")
    assert len(frame) == 4 and frame.rms_error.max() > 0
    timeless = lambda line: [c for i, c in enumerate(line.split(",")) if i not in (6, 7)]  # noqa: E731  wall, CPU
    assert [timeless(l) for l in py_lines] == [timeless(l) for l in cli_lines]


def test_stability_is_the_clis_search_and_writes_its_csv(cli, tmp_path):
    spring = os.path.join(SCENES, "spring.yaml")
    scene = clothsim.load_scene(spring)
    frame = clothsim.stability(scene, integrators=["symplectic_euler", "rk4"], param="ks", values=[1e4, 4e4],
                               duration=1.0, min_dt=1e-3, max_dt=0.05, csv=str(tmp_path / "py.csv"))
    code, _, err = cli("stability", spring, "--integrators", "symplectic_euler,rk4", "--param", "ks", "--values",
                       "1e4,4e4", "--duration", "1", "--min-dt", "1e-3", "--max-dt", "0.05", "--frame-dts", "none",
                       "--csv", str(tmp_path / "cli.csv"), "--quiet")
    assert code == 0, err
    py_lines = (tmp_path / "py.csv").read_text().splitlines()
    cli_lines = (tmp_path / "cli.csv").read_text().splitlines()
    assert list(frame.columns) == cli_lines[0].split(",")
    assert len(frame) == 4 and set(frame.outcome) == {"bracketed"}
    timeless = lambda line: [c for i, c in enumerate(line.split(",")) if i != 7]  # noqa: E731  CPU seconds
    assert [timeless(l) for l in py_lines] == [timeless(l) for l in cli_lines]


def test_a_run_that_makes_energy_reads_wrong_as_the_cli_does(cli, tmp_path):
    # XPBD at 1/30 s with 10 sweeps on the stiff sheet makes energy (docs/integrators.md, WRONG).
    scene = clothsim.load_scene(STIFF)
    sim = clothsim.Simulation(scene, lane="xpbd@1/30")  # the scene block's 10 sweeps
    sim.run(until=1.0)
    assert sim.wrong is not None and "energy rose" in sim.wrong["reason"]
    calm = clothsim.Simulation(scene, lane="implicit_euler@1/30")
    calm.run(until=1.0)
    assert calm.wrong is None


SMALL = {"cloth.particles": [7, 7]}


def _timeless(lanes):
    """--summary's lanes without the measured times (they differ run to run)."""
    return [{k: v for k, v in lane.items() if "cpu" not in k and "seconds" not in k} for lane in lanes]


def test_compare_is_the_clis_comparison_with_the_same_files_and_numbers(cli, tmp_path):
    import json
    frame = clothsim.compare(DRAPE, set=SMALL, duration=0.2, integrators=["symplectic_euler", "rk4@2e-4"],
                             match="none", color="strain", still=0.1, output=str(tmp_path / "py.png"), width=160,
                             height=90, summary=str(tmp_path / "py.json"))
    code, out, err = cli("compare", DRAPE, "--set", "cloth.particles=[7,7]", "--duration", "0.2", "--integrators",
                         "symplectic_euler,rk4@2e-4", "--match", "none", "--color", "strain", "--still", "0.1", "-o",
                         str(tmp_path / "cli.png"), "--width", "160", "--height", "90", "--summary",
                         str(tmp_path / "cli.json"), "--quiet")
    assert code == 0, err
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    py_json, cli_json = (json.loads((tmp_path / n).read_text()) for n in ("py.json", "cli.json"))
    assert _timeless(py_json["lanes"]) == _timeless(cli_json["lanes"])
    # The frame: a row per lane, --summary's keys as columns, its numbers to the last bit.
    assert len(frame) == 2 and frame.lane[1] == "rk4@2e-4"
    assert set(cli_json["lanes"][0]) <= set(frame.columns)
    assert list(frame.field_max) == [lane["field_max"] for lane in cli_json["lanes"]]
    assert frame.field_max.min() > 0  # strain measured in every lane
    assert list(frame.dt) == [1e-4, 2e-4]


def test_compare_returns_its_table_with_no_file_and_refuses_as_the_cli_does():
    frame = clothsim.compare(DRAPE, set=SMALL, duration=0.05, integrators="explicit_euler,midpoint", match="cost")
    assert len(frame) == 2 and set(frame.role) == {"lane"}
    # Matched on cost: the midpoint lane (two evaluations a step) takes twice the step.
    assert frame.dt[1] == pytest.approx(2 * frame.dt[0])
    with pytest.raises(clothsim.UsageError, match="--integrators"):
        clothsim.compare(DRAPE, integrators="rk5")
    with pytest.raises(ValueError, match="--still needs -o/--output"):
        clothsim.compare(DRAPE, still=0.5)


def test_compare_frames_are_each_lanes_metrics_and_error_at_every_clip_frame(cli, tmp_path):
    import pandas
    lanes = ["symplectic_euler", "rk4@2e-4"]
    frame = clothsim.compare(DRAPE, set=SMALL, duration=0.2, integrators=lanes, match="none", color="error")
    frames = frame.attrs["frames"]
    fps = clothsim.load_scene(DRAPE).fps
    count = int(0.2 * fps + 1e-9) + 1  # at k / fps, 0 and 0.2 included
    assert len(frames) == len(lanes) * count
    assert list(frames.groupby("lane").frame_t.apply(list)) == [[k / fps for k in range(count)]] * 2
    # At t = 0 every lane is the scene's initial state: one energy, no error.
    first = frames[frames.frame_t == 0]
    assert list(first.t) == [0.0, 0.0] and first.total_energy.nunique() == 1 and list(first.error) == [0.0, 0.0]
    # The summary's numbers are these frames': its final and largest error.
    for i, lane in enumerate(frame.lane[:2]):
        error = frames[frames.lane == lane].error
        assert error.iloc[-1] == frame.field_last[i] and error.max() == frame.field_max[i] > 0
    assert frame.unresolved.dtype == bool
    # Each row is the one `run --metrics` writes for the lane at that frame, under its names.
    code, _, err = cli("run", DRAPE, "--set", "cloth.particles=[7,7]", "--duration", "0.2", "--integrator",
                       "symplectic_euler", "--metrics", str(tmp_path / "m.csv"), "--quiet")
    assert code == 0, err
    run = pandas.read_csv(tmp_path / "m.csv", float_precision="round_trip")
    lane = frames[frames.name == "symplectic_euler"].reset_index(drop=True)
    assert set(run.columns) <= set(lane.columns)
    for column in run.columns:
        assert list(lane[column]) == list(run[column]), column
    # An end between two frames is a row too (the lanes end there); no --color error, no error.
    short = clothsim.compare(DRAPE, set=SMALL, duration=0.05, integrators="rk4", match="none")
    assert list(short.attrs["frames"].frame_t) == [0.0, 1 / fps, 0.05] and short.t_reached[0] == 0.05
    assert "error" not in short.attrs["frames"]


def test_compare_ctrl_c_raises_keyboard_interrupt_and_leaves_no_video(tmp_path):
    video = tmp_path / "clip.mp4"
    script = textwrap.dedent(f"""
        import time, clothsim
        print("running", flush=True)
        try:
            clothsim.compare({DRAPE!r}, duration=60, integrators="rk4@1e-5", match="none", video={str(video)!r},
                             width=160, height=90)
        except KeyboardInterrupt:
            print("interrupted after", time.monotonic(), flush=True)
    """)
    out, sent = interrupted_script(script, after=3.0)
    assert out.startswith("interrupted after "), out
    # The delay is printed (docs/python.md), not asserted: a shared machine's load would decide it.
    print(f"compare: KeyboardInterrupt {1000 * (float(out.split()[2]) - sent):.0f} ms after SIGINT")
    assert list(tmp_path.iterdir()) == []  # no clip, no temporary


def test_compare_releases_the_gil():
    import threading
    frames = []
    worker = threading.Thread(target=lambda: frames.append(clothsim.compare(
        DRAPE, duration=0.2, integrators="rk4@1e-5", match="none")))
    ticks = []
    worker.start()
    while worker.is_alive():
        ticks.append(time.monotonic())  # Python runs while the lanes step
        time.sleep(0.001)
    worker.join()
    assert len(ticks) > 5 and len(frames) == 1 and frames[0].t_reached[0] >= 0.2


def test_a_lane_with_iterations_steps_as_run_iterations_does(cli, tmp_path):
    scene = clothsim.load_scene(DRAPE, set=SMALL, duration=0.1)
    sim = clothsim.Simulation(scene, lane="vbd@0.01:3")
    sim.run(until=0.1)
    code, _, err = cli("run", DRAPE, "--set", "cloth.particles=[7,7]", "--duration", "0.1", "--integrator", "vbd",
                       "--dt", "0.01", "--iterations", "3", "--state", str(tmp_path / "s.csv"), "--quiet")
    assert code == 0, err
    x, v = read_state_csv(tmp_path / "s.csv")
    assert np.array_equal(sim.positions, x) and np.array_equal(sim.velocities, v)
    more = clothsim.Simulation(scene, lane="vbd@0.01:30")
    more.run(until=0.1)
    assert not np.array_equal(more.positions, x)  # the iterations are the lane's, not the scene's
    with pytest.raises(ValueError, match=r"lane: rk4 has no iterations to set \(in .rk4@0.01:3.\)"):
        clothsim.Simulation(scene, lane="rk4@0.01:3")  # the explicit family has no iterations


def test_not_converged_is_the_count_run_gives(cli, tmp_path):
    # One Newton iteration cannot meet a 1e-12 tolerance on the stiff cloth in contact.
    sets = {"implicit.newton_max_iterations": 1, "implicit.newton_tolerance": 1e-12}
    sim = clothsim.Simulation(clothsim.load_scene(STIFF, set=sets, duration=0.3))
    sim.run(until=0.3)
    code, _, err = cli("run", STIFF, "--duration", "0.3", *[a for k, v in sets.items() for a in ("--set", f"{k}={v}")],
                       "--summary", str(tmp_path / "run.json"), "--quiet")
    assert code == 0, err
    import json
    lane = json.loads((tmp_path / "run.json").read_text())["lanes"][0]
    assert sim.not_converged > 0 and sim.not_converged == lane["unconverged_steps"]
    assert not sim.diverged
