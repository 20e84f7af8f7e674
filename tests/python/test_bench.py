# clothsim.bench with every option of `clothsim bench` as a keyword (tools/python/bench_binding.cpp,
# planned, run and written by src/clip/studies like the CLI's): vary=, scale=, shard=, summary= and
# plot= against the CLI's files for the same options, cell for cell but the measured times.
import csv
import json
import os
import textwrap

import pandas as pd
import pytest

import clothsim
from conftest import SCENES, interrupted_script

SPRING = os.path.join(SCENES, "spring.yaml")
DRAPE = os.path.join(SCENES, "drape.yaml")
TIMES = ["wall_seconds", "cpu_seconds", "cpu_per_sim_second", "peak_rss_mb"]  # measured, never equal
SMALL = dict(integrators="midpoint,rk4", dts=[0.01, 0.005], duration=0.2, frame_dts=[])
SMALL_ARGS = ["--integrators", "midpoint,rk4", "--dts", "0.01,0.005", "--duration", "0.2", "--frame-dts", "none"]


def rows_without_times(path):
    """A CSV's rows (cells as written) without the measured-time columns."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    keep = [i for i, c in enumerate(rows[0]) if c not in TIMES]
    return [[row[i] for i in keep] for row in rows]


def same_frame(frame, path):
    """The DataFrame is the CLI's CSV read back: its columns, and but for the times its values to the last bit
    (its 0 / 1 verdict columns as booleans)."""
    ref = pd.read_csv(path, float_precision="round_trip")
    for verdict in ("diverged", "wrong", "unresolved", "converged", "frame_step", "finished"):
        if verdict in ref.columns and ref[verdict].isin([0, 1]).all():  # booleans in the DataFrame
            ref[verdict] = ref[verdict].astype(bool)
    assert list(frame.columns) == list(ref.columns)
    cols = [c for c in ref.columns if c not in TIMES]
    pd.testing.assert_frame_equal(frame[cols].reset_index(drop=True), ref[cols], check_exact=True)


def run_cli(cli, *args):
    code, out, err = cli(*args, *(["--quiet"] if args[0] != "merge" else []))  # merge prints no progress
    assert code == 0, err
    return out


def test_vary_is_the_clis_bench_vary_a_study_per_value(cli, tmp_path):
    frame = clothsim.bench(clothsim.load_scene(SPRING), vary="ks=100,400", csv=str(tmp_path / "py.csv"), **SMALL)
    run_cli(cli, "bench", SPRING, *SMALL_ARGS, "--vary", "ks=100,400", "--csv", str(tmp_path / "cli.csv"))
    assert rows_without_times(tmp_path / "py.csv") == rows_without_times(tmp_path / "cli.csv")
    same_frame(frame, tmp_path / "cli.csv")
    assert sorted(set(frame.integrator)) == ["midpoint (ks = 100)", "midpoint (ks = 400)", "rk4 (ks = 100)",
                                             "rk4 (ks = 400)"]
    # Four times the stiffness, twice the frequency: at one step midpoint's error (~ w^3 h^2) grows.
    mid = frame[frame.integrator.str.startswith("midpoint")].set_index(["integrator", "dt"])
    assert mid.loc[("midpoint (ks = 400)", 0.01), "rms_error"] > 2 * mid.loc[("midpoint (ks = 100)", 0.01), "rms_error"]


def test_scale_is_the_clis_bench_scale_cost_against_sheet_size(cli, tmp_path):
    kw = dict(integrators="symplectic_euler@1e-3", duration=0.02)
    frame = clothsim.bench(clothsim.load_scene(DRAPE), scale=[3, 6], csv=str(tmp_path / "py.csv"), **kw)
    run_cli(cli, "bench", DRAPE, "--integrators", kw["integrators"], "--duration", "0.02", "--scale", "3,6",
            "--csv", str(tmp_path / "cli.csv"))
    assert rows_without_times(tmp_path / "py.csv") == rows_without_times(tmp_path / "cli.csv")
    same_frame(frame, tmp_path / "cli.csv")
    assert list(frame.side) == [3, 6] and list(frame.particles) == [9, 36]
    # The sheet's total mass is fixed: 4x the particles, a quarter of the mass each.
    assert frame.particle_mass[1] == pytest.approx(frame.particle_mass[0] * 9 / 36)


def test_shards_merged_by_the_cli_are_the_clis_whole_bench(cli, tmp_path):
    scene = clothsim.load_scene(SPRING)
    parts = [clothsim.bench(scene, shard=f"{k}/2", csv=str(tmp_path / "py.csv"), **SMALL) for k in (1, 2)]
    assert sum(len(p) for p in parts) == 2 * 2  # two lanes x two steps, each run in one part
    dirs = [str(tmp_path / f"py.csv.shard-{k}-of-2") for k in (1, 2)]
    run_cli(cli, "merge", *dirs, "--csv", str(tmp_path / "merged.csv"))
    run_cli(cli, "bench", SPRING, *SMALL_ARGS, "--csv", str(tmp_path / "cli.csv"))
    assert rows_without_times(tmp_path / "merged.csv") == rows_without_times(tmp_path / "cli.csv")
    same_frame(pd.concat(parts).sort_values(["integrator", "dt"]), tmp_path / "merged.csv")
    # A rerun of a finished part runs nothing and returns the same rows.
    again = clothsim.bench(scene, shard="1/2", csv=str(tmp_path / "py.csv"), **SMALL)
    assert again.drop(columns=TIMES, errors="ignore").equals(parts[0].drop(columns=TIMES, errors="ignore"))
    with pytest.raises(clothsim.UsageError, match="--shard: needs --csv"):
        clothsim.bench(scene, shard="1/2", **SMALL)


def without_timing(summary):
    """A summary without what differs between two processes: the command, times per lane."""
    summary.pop("command")
    for lane in summary["lanes"]:
        for key in ("cpu_seconds", "wall_seconds"):
            lane.pop(key, None)
    return summary


def test_summary_is_the_clis_summary_and_the_plot_is_drawn(cli, tmp_path):
    clothsim.bench(clothsim.load_scene(SPRING), summary=str(tmp_path / "py.json"), plot=str(tmp_path / "py.png"),
                   **SMALL)
    run_cli(cli, "bench", SPRING, *SMALL_ARGS, "--summary", str(tmp_path / "cli.json"))
    py, ref = (json.loads((tmp_path / f"{n}.json").read_text()) for n in ("py", "cli"))
    assert without_timing(py) == without_timing(ref)
    assert py["complete"] is True and len(py["lanes"]) == 4
    assert (tmp_path / "py.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_options_that_do_not_go_together_are_refused_with_the_clis_message(tmp_path):
    scene = clothsim.load_scene(SPRING)
    with pytest.raises(clothsim.UsageError, match="--vary: --summary and --shard take one scene's study"):
        clothsim.bench(scene, vary="ks=100,400", summary=str(tmp_path / "x.json"))
    with pytest.raises(clothsim.UsageError, match="--scale: give lanes as NAME@STEP"):
        clothsim.bench(scene, scale=[3], dts=[0.01])
    with pytest.raises(clothsim.UsageError, match="--plot: a shard draws no plot"):
        clothsim.bench(scene, shard="1/2", csv=str(tmp_path / "x.csv"), plot=str(tmp_path / "x.png"), **SMALL)
    assert not any(tmp_path.iterdir()), "nothing written for a refused call"


def test_ctrl_c_raises_keyboard_interrupt_and_writes_none_of_the_files(tmp_path):
    files = {k: str(tmp_path / f"wp.{k}") for k in ("csv", "json", "png")}
    script = textwrap.dedent(f"""
        import time, clothsim
        scene = clothsim.load_scene({DRAPE!r})
        print("running", flush=True)
        try:
            clothsim.bench(scene, dts=[2e-5, 4e-5], integrators="rk4", duration=0.5, frame_dts=[],
                           csv={files["csv"]!r}, summary={files["json"]!r}, plot={files["png"]!r})
        except KeyboardInterrupt:
            print("interrupted after", time.monotonic(), flush=True)
    """)
    out, sent = interrupted_script(script, after=2.0)
    assert out.startswith("interrupted after "), out
    # The delay is printed (docs/python.md), not asserted: a shared machine's load would decide it.
    print(f"bench: KeyboardInterrupt {1000 * (float(out.split()[2]) - sent):.0f} ms after SIGINT")
    assert list(tmp_path.iterdir()) == [], "no CSV, summary, plot or temporary"


def test_tols_and_error_are_the_clis_adaptive_lanes_by_tolerance(cli, tmp_path):
    """An adaptive lane runs once per tolerance (column tolerance), judged by its error over time by default."""
    kw = dict(integrators="rk4,dopri5", dts=[0.01, 0.005], duration=0.2, frame_dts=[])
    frame = clothsim.bench(clothsim.load_scene(SPRING), tols=[1e-4, 1e-7], csv=str(tmp_path / "py.csv"), **kw)
    run_cli(cli, "bench", SPRING, "--integrators", "rk4,dopri5", "--dts", "0.01,0.005", "--duration", "0.2",
            "--frame-dts", "none", "--tols", "1e-4,1e-7", "--csv", str(tmp_path / "cli.csv"))
    assert rows_without_times(tmp_path / "py.csv") == rows_without_times(tmp_path / "cli.csv")
    same_frame(frame, tmp_path / "cli.csv")
    pairs = frame[frame.integrator == "dopri5"].set_index("tolerance")
    assert sorted(pairs.index) == [1e-7, 1e-4]
    assert pairs.loc[1e-7, "rms_error"] < pairs.loc[1e-4, "rms_error"] < 100 * 1e-4
    assert (frame.error_measure == "time").all()
    assert (frame.rms_error == frame.rms_error_over_time).all()
    assert (frame.rms_error_over_time >= frame.rms_error_at_end).all()  # T is one of the sample times
    end = clothsim.bench(clothsim.load_scene(SPRING), tols=[1e-4], error="end", **kw)
    assert (end.rms_error == end.rms_error_at_end).all()
    with pytest.raises(clothsim.UsageError, match="--error"):
        clothsim.bench(clothsim.load_scene(SPRING), tols=[1e-4], error="sometimes", **kw)
