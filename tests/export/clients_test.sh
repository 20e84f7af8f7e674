#!/bin/sh
# The exported files read back by real clients, headless, each against `clothsim run --state`
# at the frame it reads (frame 4 of scenes/drape.yaml at 30 frames/s, t = 4/30 s):
#   meshio    PLY and OBJ sequences (points, velocity, speed, strain; the sphere; the error of
#             run --color error and of compare's lanes)
#   blender   the rest OBJ imported, a Mesh Cache modifier on the PC2, the evaluated vertices
#   paraview  pvpython opens the PVD, the cloth block at that time, its points and fields
# Usage: clients_test.sh meshio|blender|paraview CLOTHSIM OUTDIR. Exit 77 (ctest: skipped) when the
# client is not installed; tools/install-deps.sh installs every one.
set -eu
client=$1 clothsim=$2 out=$3
here=$(cd "$(dirname "$0")" && pwd)
scene=$here/../../scenes/drape.yaml
case $client in
  meshio) /usr/bin/python3 -c 'import meshio, numpy' 2>/dev/null ||
            { echo "skipped: python3-meshio is not installed (tools/install-deps.sh)"; exit 77; } ;;
  blender) command -v blender >/dev/null || { echo "skipped: blender is not installed (tools/install-deps.sh)"; exit 77; } ;;
  paraview) command -v pvpython >/dev/null ||
              { echo "skipped: pvpython (python3-paraview) is not installed (tools/install-deps.sh)"; exit 77; } ;;
  *) echo "clients_test.sh: unknown client $client" >&2; exit 2 ;;
esac
rm -rf "$out"
mkdir -p "$out"
# Frame 4's state: the run ends at t = 4/30 s (0.13333333333333333, the same double), the time
# the export's frame 4 is taken at.
"$clothsim" run "$scene" --duration 0.13333333333333333 --state "$out/state.csv" --quiet >/dev/null
run() { "$clothsim" run "$scene" --duration 0.2 --quiet "$@" >/dev/null; }
case $client in
  meshio)
    run --export "$out/ply/f_%05d.ply"
    run --export "$out/obj/f_%05d.obj"
    "$clothsim" run "$scene" --duration 0.1 --color error --export "$out/err/f_%05d.ply" --quiet >/dev/null
    "$clothsim" compare "$scene" --integrators rk4,symplectic_euler --duration 0.1 --match none --color error \
      --export "$out/compare/f_%05d.ply" --quiet >/dev/null
    exec /usr/bin/python3 "$here/meshio_check.py" "$out" 4 ;;
  blender)
    run --export "$out/c.pc2"
    blender -b --factory-startup --python "$here/blender_check.py" -- "$out" 4 > "$out/blender.log" 2>&1 ||
      { cat "$out/blender.log"; exit 1; }
    grep '^check:' "$out/blender.log" ;;
  paraview)
    run --export "$out/p.pvd"
    exec pvpython --force-offscreen-rendering "$here/paraview_check.py" "$out" 4 ;;
esac
