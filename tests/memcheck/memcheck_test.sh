#!/bin/sh
# The memory-checked tier: one method's step kernels under valgrind's memcheck, on sheets whose
# sizes leave vector tails (9 x 9, 12 x 12, 25 x 25: 81, 144 and 625 particles, 80, 132 and 600
# springs a row family, none a whole number of 8-lane vectors or 2L-wide pairs), through the
# projection drape, the barrier drape (where the method takes it) and the curtain. Any invalid
# read or write, use of an uninitialised value or leak of a block fails the test.
# Usage: memcheck_test.sh METHOD PROGRAM SCENES_DIR
set -eu
method=$1 program=$2 scenes=$3
command -v valgrind >/dev/null || { echo "skipped: valgrind not installed (tools/install-deps.sh test installs it)"; exit 77; }
# Three frame steps for the implicit methods, 200 steps inside every explicit limit for the rest.
case $method in
  xpbd | projective_dynamics | vbd | implicit_euler | implicit_midpoint | newmark | generalized_alpha | bdf2)
    dt=1/60 duration=0.05 ;;
  ros2) dt=1/240 duration=0.0125 ;;  # a linearly implicit step: stable on the drape at 1/240 s
  *) dt=5e-5 duration=0.01 ;;
esac
lane="$method at dt = $dt"
run() {
  valgrind -q --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite \
    "$program" run "$@" --integrator "$method" --dt "$dt" --duration "$duration" --quiet
}
for n in 9 12 25; do
  echo "memcheck: $lane on the drape at $n x $n"
  run "$scenes/drape.yaml" --set "cloth.particles=[$n, $n]"
  case $method in
    xpbd | projective_dynamics | ros2) ;;  # no barrier contact (they project constraints; ros2 has no line search)
    *) echo "memcheck: $lane on the barrier drape at $n x $n"
       run "$scenes/drape_smooth.yaml" --set "cloth.particles=[$n, $n]" ;;
  esac
done
echo "memcheck: $lane on the curtain at 12 x 12"
run "$scenes/curtain.yaml" --set "cloth.particles=[12, 12]"
echo "memcheck: $lane clean"
