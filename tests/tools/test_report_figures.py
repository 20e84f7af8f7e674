"""tools/report_figures.sh: its folders are taken where the caller stands."""
import os
import subprocess

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "tools", "report_figures.sh")
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def test_relative_folders_are_where_the_caller_stands(tmp_path):
    # `report_figures.sh out` wrote the repository's out/, not the one beside the caller.
    name = "report_figures_relative_out"
    assert not os.path.exists(os.path.join(ROOT, name))
    build = tmp_path / "mybuild"
    build.mkdir()
    fake = build / "clothsim"  # a clothsim that fails at once: the first figure stops the script
    fake.write_text("#!/bin/sh\nexit 1\n")
    fake.chmod(0o755)
    p = subprocess.run(["sh", SCRIPT, "--small", name, "mybuild"], cwd=tmp_path, capture_output=True, text=True)
    assert p.returncode == 1
    assert "report_figures.sh: clip failed: " + str(build / "clothsim") + " compare" in p.stderr, p.stderr
    assert (tmp_path / name).is_dir()
    assert not os.path.exists(os.path.join(ROOT, name))
    missing = subprocess.run(["sh", SCRIPT, "--small", name, "nobuild"], cwd=tmp_path, capture_output=True, text=True)
    assert missing.returncode == 1
    assert str(tmp_path / "nobuild" / "clothsim") + " not found" in missing.stderr, missing.stderr
