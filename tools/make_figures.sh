#!/bin/sh
# Re-makes every picture in docs/images from the shipped scenes, with the exact commands the
# pages quote: docs/integrators.md's figures, the README's and docs/cli.md's pictures, and
# docs/report.md's (tools/report_figures.sh, saved as report_NAME.png). Each study's CSV is kept
# beside its figure so the numbers can be checked; tools/check_docs.sh --full remakes them all
# into a scratch folder and compares each with the one in the tree.
#
#   tools/make_figures.sh [BUILD_DIR [OUT_DIR]]   # defaults: build (holding clothsim), docs/images
#
# Needs python3-matplotlib (/usr/bin/python3). About 2 minutes on 2 cores at load 1.5 (4 at
# load 3), most of it the report's full-size clip and the drape studies; timings in the figures
# are CPU time of each run's thread.
set -eu
HERE=$(pwd)
from_here() { case $1 in /*) printf '%s\n' "$1" ;; *) printf '%s\n' "$HERE/$1" ;; esac; }
BUILD=${1:+$(from_here "$1")}
OUT=${2:+$(from_here "$2")}
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
OUT=${OUT:-docs/images}
CLOTHSIM=$BUILD/clothsim
[ -x "$CLOTHSIM" ] || { echo "make_figures.sh: $CLOTHSIM not found (build first, or pass the build directory)" >&2; exit 1; }
mkdir -p "$OUT"
PY=/usr/bin/python3
[ -x "$PY" ] || PY=python3

echo "== work precision, spring (smooth: the methods' orders)"
"$CLOTHSIM" bench scenes/spring.yaml \
  --integrators explicit_euler,symplectic_euler,midpoint,rk4,implicit_euler \
  --dts 0.01,0.005,0.0025,0.00125 --duration 1 \
  --csv $OUT/bench_spring.csv --plot $OUT/bench_spring.png

echo "== work precision, drape (the default study)"
"$CLOTHSIM" bench scenes/drape.yaml --csv $OUT/bench_drape.csv --plot $OUT/bench_drape.png

echo "== substeps against iterations, N = 30 on the smooth drape's first second"
"$CLOTHSIM" bench scenes/drape_smooth.yaml --budget 30 --fps 60 --duration 1 \
  --csv $OUT/budget_drape_smooth.csv --plot $OUT/budget_drape_smooth.png

echo "== stability, undamped spring (linear theory: 2/w, 2.83/w)"
"$CLOTHSIM" stability scenes/spring.yaml --set cloth.springs.structural.damping=0 \
  --integrators explicit_euler,symplectic_euler,rk4,implicit_euler \
  --values 25,100,400,1600,6400 --duration 400 --min-dt 0.001 --max-dt 1 \
  --csv $OUT/stability_spring.csv --plot $OUT/stability_spring.png

echo "== stability, drape (the default study)"
"$CLOTHSIM" stability scenes/drape.yaml --csv $OUT/stability_drape.csv --plot $OUT/stability_drape.png

echo "== energy over time, undamped spring"
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
for i in explicit_euler symplectic_euler midpoint rk4 implicit_euler; do
  "$CLOTHSIM" run scenes/spring.yaml --set cloth.springs.structural.damping=0 \
    --integrator $i --dt 0.005 --duration 10 --metrics "$TMP/$i.csv" >/dev/null
done
"$PY" tools/plot_energy.py "$TMP"/explicit_euler.csv "$TMP"/symplectic_euler.csv "$TMP"/midpoint.csv \
  "$TMP"/rk4.csv "$TMP"/implicit_euler.csv --log \
  --title "spring.yaml undamped, dt = 0.005 s (w h = 0.05): total energy" --out $OUT/energy_spring.png

echo "== energy over time, drape"
for i in explicit_euler symplectic_euler midpoint rk4 implicit_euler; do
  "$CLOTHSIM" run scenes/drape.yaml --integrator $i --duration 2 --metrics "$TMP/$i.csv" >/dev/null || true
done
"$PY" tools/plot_energy.py "$TMP"/explicit_euler.csv "$TMP"/symplectic_euler.csv "$TMP"/midpoint.csv \
  "$TMP"/rk4.csv "$TMP"/implicit_euler.csv --relative \
  --title "drape.yaml, dt = 1e-4 s: total energy - E(0)" --out $OUT/energy_drape.png
echo "== README: the default clip, the same step, parameter lanes; docs/cli.md: diverged lanes, a sheet"
"$CLOTHSIM" compare scenes/drape.yaml --still 2.5 -o $OUT/drape_compare.png --width 640 --height 360
"$CLOTHSIM" compare scenes/drape.yaml --match none --still 2.5 -o $OUT/drape_same_step.png --width 640 --height 360
"$CLOTHSIM" compare scenes/drape.yaml --vary ks=2e3,2e4,2e5 --width 960 --height 360 --still 1.5 -o $OUT/drape_vary.png
"$CLOTHSIM" compare scenes/drape.yaml --dt 3e-4 --color strain --still 1.5 -o $OUT/drape_diverged.png --width 640 --height 360
"$CLOTHSIM" compare scenes/drape.yaml --sheet $OUT/drape_sheet.png --times 0.1,0.5,2,4 --width 960 --height 540
"$CLOTHSIM" compare scenes/drape_smooth.yaml --still 2.5 -o $OUT/drape_smooth_compare.png --width 640 --height 360
"$CLOTHSIM" compare scenes/drape_smooth.yaml --vary collision.model=projection,barrier \
  --integrators symplectic_euler,midpoint,rk4 --color error --still 1 -o $OUT/drape_models.png --width 960 --height 540

echo "== docs/integrators.md: converge on the drape, at 64 x 64 and on stiff.yaml"
"$CLOTHSIM" converge scenes/drape.yaml --dt 1/60 --states 5 --max-iterations 100 \
  --csv $OUT/converge_drape.csv --plot $OUT/converge_drape.png
"$CLOTHSIM" converge scenes/drape.yaml --set cloth.particles=[64,64] --dt 1/60 --states 5 \
  --max-iterations 100 --csv $OUT/converge_drape64.csv --plot $OUT/converge_drape64.png
"$CLOTHSIM" converge scenes/stiff.yaml --dt 1/60 --states 5 --max-iterations 100 \
  --csv $OUT/converge_stiff.csv --plot $OUT/converge_stiff.png

echo "== docs/report.md: tools/report_figures.sh, its pictures saved as report_NAME.png"
sh tools/report_figures.sh "$TMP/report" "$BUILD"
for name in sheet stability_ks stability_kd energy_lanes energy ks kd families_energy fixed_point; do
  cp "$TMP/report/$name.png" "$OUT/report_$name.png"
done
cp "$TMP/report/stability_fp.png" "$OUT/report_fixed_point_stability.png"
# Section 7's study is docs/integrators.md's "The smooth drape" command, run once for both.
cp "$TMP/report/wp_cloth.png" "$OUT/bench_drape_smooth.png"
cp "$TMP/report/wp_cloth.csv" "$OUT/bench_drape_smooth.csv"
echo "figures in $OUT"
