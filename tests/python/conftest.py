# Where the tests find the module and the CLI: PYTHONPATH=build/python (ctest's Python.Pytest
# sets it) and CLOTHSIM_BINARY (default build/clothsim).
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENES = os.path.join(ROOT, "scenes")


@pytest.fixture(scope="session")
def clothsim_binary():
    return os.environ.get("CLOTHSIM_BINARY", os.path.join(ROOT, "build", "clothsim"))


@pytest.fixture
def cli(clothsim_binary):
    """Runs `clothsim ARGS...`: (exit code, stdout, stderr)."""
    def run(*args):
        p = subprocess.run([clothsim_binary, *args], capture_output=True, text=True)
        return p.returncode, p.stdout, p.stderr
    return run


def read_state_csv(path):
    """run --state's CSV (%.17g: exact) as (positions, velocities), (P, 3) float64."""
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    return data[:, 1:4], data[:, 4:7]


def interrupted_script(script, after):
    """Runs `script` in a Python of its own, sends SIGINT (as Ctrl-C does) `after` s after it
    prints "running", and returns its output (it must exit 0) and when the signal was sent."""
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True, env=dict(os.environ))
    assert p.stdout.readline().strip() == "running"
    time.sleep(after)
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=60)
    assert p.returncode == 0, out
    return out, sent
