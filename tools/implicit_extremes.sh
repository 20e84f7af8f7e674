#!/usr/bin/env bash
# Measures implicit Euler at one step per frame (docs/integrators.md, "Implicit Euler at the
# extremes"): for stiff.yaml and drape.yaml at h = 1/240, 1/120, 1/60, 1/30 s, the steps that
# converged, Newton and CG iterations and sparse factorizations per step, CPU per simulated second, the largest
# frame-to-frame rise of total energy, the largest strain, contacts held in the solve and
# post-step projections; then symplectic Euler at its largest stable step for the cost ratio.
# Usage: tools/implicit_extremes.sh [BUILD_DIR]     (about a minute on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
clothsim="${1:-build}/clothsim"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

summarise() {  # scene label out.txt metrics.csv
  python3 - "$@" <<'PY'
import csv, re, sys
scene, label, out, metrics = sys.argv[1:5]
text = open(out).read()
steps = int(re.search(r"(\d+) steps to", text).group(1))
m = re.search(r"(\d+) Newton iterations, (\d+) CG iterations \((\d+) sparse factorizations\), largest final residual ([^,]+), (\d+) steps not converged; (\d+) contacts held in the solve, (\d+) post-step projections", text)
cpu = float(re.search(r"s of CPU \(([^ ]+) s of CPU per simulated s\)", text).group(1))
rows = list(csv.DictReader(open(metrics)))
E = [float(r["total_energy"]) for r in rows]
rise = max([(b - a) / abs(a) for a, b in zip(E, E[1:]) if a != 0] + [0.0])
strain = max(float(r["max_strain"]) for r in rows)
print(f"| {scene} | {label} | {steps - int(m.group(5))} of {steps} | {int(m.group(1))/steps:.1f} | "
      f"{int(m.group(2))/steps:.0f} | {int(m.group(3))/steps:.2f} | {float(m.group(4)):.2g} | {cpu:.3f} | "
      f"{100*rise:+.3f} % | {100*strain:.2f} % | {m.group(6)} | {m.group(7)} |")
PY
}

echo "| scene | h | converged steps | Newton / step | CG / step | factorizations / step | largest residual | CPU s per simulated s | largest energy rise, frame to frame | largest strain | contacts held | post-step projections |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
for scene in stiff drape; do
  for label in 1/240 1/120 1/60 1/30; do
    h=$(python3 -c "print(1/${label#1/})")
    "$clothsim" run "scenes/$scene.yaml" --integrator implicit_euler --dt "$h" \
      --metrics "$tmp/m.csv" > "$tmp/out.txt" 2>&1
    summarise "$scene" "$label" "$tmp/out.txt" "$tmp/m.csv"
  done
done
echo
echo "symplectic Euler at its largest stable step on stiff.yaml (4.2e-4 s, clothsim stability):"
"$clothsim" run scenes/stiff.yaml --integrator symplectic_euler --dt 4.2e-4 | head -1
