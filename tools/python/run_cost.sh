#!/usr/bin/env bash
# Simulation.run against `clothsim run` on the same lane: instructions executed inside
# Run::advance_to (valgrind's callgrind, so a loaded machine does not move the figure), and the
# stepping thread's CPU seconds of runs interleaved in one go. BENCHMARKS.md, "Python module".
# Usage: tools/python/run_cost.sh [BUILD_DIR] [LANE] [DURATION]
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build} lane=${2:-rk4@4e-4} duration=${3:-0.5}
name=${lane%@*} step=${lane#*@}
scene=scenes/drape.yaml
export PYTHONPATH=$PWD/$build/python
py="import clothsim; s = clothsim.Simulation(clothsim.load_scene('$scene', duration=$duration), lane='$lane'); s.run(until=$duration); print(s.totals['cpu_seconds'])"
cli=("$build/libexec/clothsim" run "$scene" --integrator "$name" --dt "$step" --duration "$duration" --quiet)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
instructions() {  # the inclusive Ir of Run::advance_to in a callgrind run of "$@"
  valgrind --tool=callgrind --toggle-collect='clothsim::Run::advance_to(double)' \
    --callgrind-out-file="$tmp/cg.out" "$@" >/dev/null 2>&1
  awk '/^summary:/ {print $2}' "$tmp/cg.out"
}
cli_ir=$(instructions "${cli[@]}")
py_ir=$(instructions /usr/bin/python3 -c "$py")
echo "instructions in Run::advance_to, $lane on $scene for $duration s:"
echo "  clothsim run       $cli_ir"
echo "  Simulation.run     $py_ir"
awk -v a="$py_ir" -v b="$cli_ir" 'BEGIN {printf "  ratio Python / CLI %.4f\n", a / b}'
cpu_cli=() cpu_py=()
for _ in 1 2 3 4 5; do  # interleaved: the machine's load falls on both alike
  cpu_cli+=("$("${cli[@]}" 2>/dev/null | sed -n 's/.*, \([0-9.]*\) s of CPU (.*/\1/p')")
  cpu_py+=("$(/usr/bin/python3 -c "$py" | xargs printf "%.3f")")
done
median() { printf '%s\n' "$@" | sort -g | sed -n 3p; }
echo "stepping thread's CPU, median of 5 interleaved runs: clothsim run $(median "${cpu_cli[@]}") s," \
     "Simulation.run $(median "${cpu_py[@]}") s"
