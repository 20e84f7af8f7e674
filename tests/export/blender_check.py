# Run by clients_test.sh inside Blender (blender -b --python blender_check.py -- OUT FRAME): the
# rest mesh c.obj imported as a user does (File > Import > Wavefront, defaults), a Mesh Cache
# modifier on c.pc2, the scene at FRAME, the evaluated vertices against state.csv.
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from state_csv import float32 as f32, read_state  # noqa: E402

out, frame = sys.argv[sys.argv.index("--") + 1], int(sys.argv[-1])
x, _ = read_state(os.path.join(out, "state.csv"))
bpy.ops.wm.read_factory_settings(use_empty=True)
failures = 0
for name, expected in (("c", x), ("c.sphere0", None)):
    before = set(bpy.data.objects)
    bpy.ops.wm.obj_import(filepath=os.path.join(out, name + ".obj"))
    obj = next(o for o in bpy.data.objects if o not in before)
    cache = obj.modifiers.new("clothsim", "MESH_CACHE")
    cache.cache_format = "PC2"
    cache.filepath = os.path.join(out, name + ".pc2")
    bpy.context.scene.frame_set(frame)
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    got = [tuple(vert.co) for vert in evaluated.data.vertices]
    if expected is None:  # the sphere: its cache plays on its own mesh, centred at (0, 0, 0)
        centre = [sum(p[k] for p in got) / len(got) for k in range(3)]
        ok = len(got) == len(obj.data.vertices) and max(abs(c) for c in centre) < 1e-6
        print("check: %s: %s, %d vertices, centre %s" % (name, "ok" if ok else "FAILED", len(got), centre))
    else:
        # Blender holds vertices as float32: the state's positions rounded to float, exactly.
        worst = max(abs(a - f32(b)) for p, q in zip(got, expected) for a, b in zip(p, q))
        ok = len(got) == len(expected) and worst == 0.0
        print("check: %s at frame %d: %s, %d vertices, largest difference from --state as float32 %g m"
              % (name, frame, "ok" if ok else "FAILED", len(got), worst))
    failures += not ok
sys.exit(1 if failures else 0)
