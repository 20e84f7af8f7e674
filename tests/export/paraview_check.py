# Run by clients_test.sh with pvpython: ParaView's PVD reader opens p.pvd, the cloth block
# (part 0) at frame FRAME's time against state.csv, its fields by name, the sphere block.
import os
import sys

from paraview import servermanager
from paraview.simple import PVDReader

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from state_csv import float32 as f32, read_state  # noqa: E402

out, frame = sys.argv[1], int(sys.argv[2])
x, v = read_state(os.path.join(out, "state.csv"))
reader = PVDReader(FileName=os.path.join(out, "p.pvd"))
times = list(reader.TimestepValues)
reader.UpdatePipeline(time=times[frame])
data = servermanager.Fetch(reader)


def leaves(block):
    """The data sets of a (nested) multiblock, in order: the PVD's parts."""
    if not block.IsA("vtkMultiBlockDataSet"):
        return [block]
    return [leaf for i in range(block.GetNumberOfBlocks()) for leaf in leaves(block.GetBlock(i))]


blocks = leaves(data)
cloth = blocks[0]
points = [cloth.GetPoint(i) for i in range(cloth.GetNumberOfPoints())]
worst = max(abs(a - f32(b)) for p, q in zip(points, x) for a, b in zip(p, q))
velocity = cloth.GetPointData().GetArray("velocity")
worst_v = max(abs(velocity.GetTuple3(i)[k] - f32(v[i][k])) for i in range(len(v)) for k in range(3))
names = sorted(cloth.GetPointData().GetArrayName(i) for i in range(cloth.GetPointData().GetNumberOfArrays()))
ok = (len(times) == 7 and abs(times[frame] - frame / 30.0) < 1e-12 and len(points) == len(x) and worst == 0.0
      and worst_v == 0.0 and names == ["speed", "strain", "velocity"] and len(blocks) == 2
      and blocks[1].GetNumberOfPoints() > 0)
print("check: p.pvd: %s: %d times, %d blocks, cloth at t = %.6g s: %d points, largest difference from --state "
      "as float32 %g m (velocity %g m/s), fields %s"
      % ("ok" if ok else "FAILED", len(times), len(blocks), times[frame], len(points), worst, worst_v, names))
sys.exit(0 if ok else 1)
