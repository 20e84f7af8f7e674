# PLY and OBJ sequences from clients_test.sh, read back with meshio (Debian's python3-meshio).
import math
import os
import sys

import meshio
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from state_csv import read_state, worst_float32_gap  # noqa: E402

out, frame = sys.argv[1], int(sys.argv[2])
x, v = read_state(os.path.join(out, "state.csv"))
failures = []


def expect(ok, what):
    print(("ok: " if ok else "FAILED: ") + what)
    if not ok:
        failures.append(what)


ply = meshio.read(os.path.join(out, "ply", "f_%05d.ply" % frame))
expect(len(ply.points) == len(x) and worst_float32_gap(ply.points.tolist(), x) == 0,
       "PLY points are the state's positions as float32")
vel = np.stack([ply.point_data[k] for k in ("vx", "vy", "vz")], axis=1)
expect(worst_float32_gap(vel.tolist(), v) == 0, "PLY vx, vy, vz are the state's velocities as float32")
speed = [math.sqrt(sum(c * c for c in row)) for row in v]
expect(worst_float32_gap([[s] for s in ply.point_data["speed"].tolist()], [[s] for s in speed]) == 0,
       "PLY speed is |v|")
expect(float(ply.point_data["strain"].max()) > 0 and "error" not in ply.point_data,
       "PLY strain is measured; run has no error field")
expect(ply.cells_dict["triangle"].shape == (2 * 24 * 24, 3), "PLY has the cloth's 1152 triangles")
sphere = meshio.read(os.path.join(out, "ply", "f_sphere0_%05d.ply" % frame))
centre = sphere.points.mean(axis=0)
radii = np.linalg.norm(sphere.points - centre, axis=1)
expect(np.allclose(centre, 0, atol=1e-6) and np.allclose(radii, 1.0, atol=1e-6),
       "the sphere is its own PLY, of radius 1 m around its centre (0, 0, 0)")
obj = meshio.read(os.path.join(out, "obj", "f_%05d.obj" % frame))
expect(worst_float32_gap(obj.points.tolist(), x) == 0, "OBJ points are the state's positions as float32")
frames = sorted(f for f in os.listdir(os.path.join(out, "obj")) if not f.startswith("f_sphere"))
expect(len(frames) == 7, "OBJ: 7 frames over 0.2 s at 30 frames/s (%d)" % len(frames))
err = meshio.read(os.path.join(out, "err", "f_%05d.ply" % 3)).point_data.get("error")
expect(err is not None and np.all(np.isfinite(err)) and err.max() > 0,
       "run --color error carries the error against its reference")
for lane in ("rk4", "symplectic_euler"):
    lane_ply = meshio.read(os.path.join(out, "compare", lane, "f_%05d.ply" % 3))
    err = lane_ply.point_data.get("error")
    expect(err is not None and np.all(np.isfinite(err)) and err.max() > 0,
           "compare's %s lane carries its error against the reference" % lane)
sys.exit(1 if failures else 0)
