# Where the tests find the module and the CLI: PYTHONPATH=build/python (ctest's Python.Pytest
# sets it) and CLOTHSIM_BINARY (default build/clothsim).
import os
import subprocess

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
