#!/bin/sh
# Every figure of a course report (docs/report.md), one clothsim command each, into OUT_DIR.
#
#   tools/report_figures.sh [--small] [OUT_DIR] [BUILD_DIR]
#
# OUT_DIR (default report/) and a BUILD_DIR given are taken where you stand, as any command's
# paths are; BUILD_DIR defaults to the repository's build/ (holding clothsim). --small runs each command
# on a 9 x 9 cloth for 0.3 s at 320 x 180 (the test, ctest -R ReportFigures): the same commands,
# smaller, so a change that breaks one is caught in seconds. Needs python3-matplotlib for the
# stability plots. Stops at the first command that fails, naming it.
set -eu
HERE=$(pwd)
# A path as the caller meant it: relative to where they stand, not to the repository this
# script moves to (report_figures.sh out wrote the repository's out/).
from_here() { case $1 in /*) printf '%s\n' "$1" ;; *) printf '%s\n' "$HERE/$1" ;; esac; }
SMALL=
if [ "${1:-}" = "--small" ]; then SMALL=1; shift; fi
OUT=$(from_here "${1:-report}")
BUILD=${2:+$(from_here "$2")}
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
CLOTHSIM=$BUILD/clothsim
[ -x "$CLOTHSIM" ] || { echo "report_figures.sh: $CLOTHSIM not found (build first, or pass the build directory)" >&2; exit 1; }
mkdir -p "$OUT"

# A reduced run of the same command: a coarse cloth, a short clip, small pictures.
if [ -n "$SMALL" ]; then
  SCENE="--set cloth.particles=[9,9] --duration 0.3"
  SIZE="--width 320 --height 180"
  TIMES=0.1,0.2,0.3
  STILL=0.2
  VARY_STILL=0.2
  FP_STILL=0.2
  STUDY="--set cloth.particles=[9,9] --duration 0.05"
else
  SCENE=
  SIZE=
  TIMES=0.1,0.5,2,4
  STILL=2
  VARY_STILL=1.5
  FP_STILL=1
  STUDY=
fi

figure() {  # figure NAME OUTPUT COMMAND...: runs it, and fails naming it unless OUTPUT is written
  name=$1
  output=$2
  shift 2
  echo "== $name: $*"
  start=$(date +%s)
  # The wall time, and where /usr/bin/time is installed the CPU time too (less moved by the load).
  if [ -x /usr/bin/time ]; then
    /usr/bin/time -f "%e s wall, %U s user + %S s system CPU" -o "$OUT/.time" "$@" ||
      { echo "report_figures.sh: $name failed: $*" >&2; exit 1; }
    took=$(cat "$OUT/.time")
    rm -f "$OUT/.time"
  else
    "$@" || { echo "report_figures.sh: $name failed: $*" >&2; exit 1; }
    took="$(($(date +%s) - start)) s"
  fi
  [ -s "$output" ] || { echo "report_figures.sh: $name wrote no $output" >&2; exit 1; }
  echo "== $name: $output in $took (load $(cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo ?))"
}

# 1. The integrator clip and its contact sheet.
figure clip "$OUT/clip.mp4" "$CLOTHSIM" compare scenes/drape.yaml $SCENE $SIZE --video "$OUT/clip.mp4" --quiet
figure sheet "$OUT/sheet.png" "$CLOTHSIM" compare scenes/drape.yaml $SCENE --sheet "$OUT/sheet.png" --times $TIMES \
  ${SIZE:---width 1280 --height 720} --quiet
# 2. Speed and accuracy at about equal cost: the table on stdout, the same in JSON.
figure table "$OUT/table.json" "$CLOTHSIM" compare scenes/drape.yaml $SCENE --color error --overlay-cost cpu \
  --integrators explicit_euler@1e-4,midpoint@2e-4,rk4@4e-4,implicit_euler@1/60 --summary "$OUT/table.json" --quiet
# 3. Where each method breaks as the springs stiffen.
figure stiffness "$OUT/stability_ks.png" "$CLOTHSIM" stability scenes/drape.yaml $STUDY --csv "$OUT/stability_ks.csv" \
  --plot "$OUT/stability_ks.png" --quiet
# 4. The effect of the damper on where each method breaks.
figure damping "$OUT/stability_kd.png" "$CLOTHSIM" stability scenes/drape.yaml $STUDY --param cloth.springs.structural.damping \
  --values 75,750,7500 --csv "$OUT/stability_kd.csv" --plot "$OUT/stability_kd.png" --quiet
# 5. Energy: each lane's E - Eref (its total energy minus the reference lane's) in its tile, on shared axes.
figure energy "$OUT/energy.png" "$CLOTHSIM" compare scenes/drape.yaml $SCENE $SIZE --inset energy --color checker \
  --integrators explicit_euler@2e-4,symplectic_euler@2e-4,rk4@2e-4,implicit_euler@1/60 --still $STILL -o "$OUT/energy.png" --quiet
# 5b. Energy over time by lane: the course's four at the scene's step, backward Euler at one and
# four steps per frame, each run's metrics, one figure (a colour per integrator, a style per step).
i=0
for lane in explicit_euler: implicit_euler_fixed_point: midpoint: rk4: implicit_euler:1/60 implicit_euler:1/240; do
  i=$((i + 1))
  name=${lane%%:*}
  step=${lane#*:}
  figure "energy lane $i" "$OUT/energy_$i.csv" "$CLOTHSIM" run scenes/drape.yaml $SCENE --integrator "$name" \
    ${step:+--dt $step} --metrics "$OUT/energy_$i.csv" --quiet
done
figure "energy by lane" "$OUT/energy_lanes.png" /usr/bin/python3 tools/plot_energy.py "$OUT"/energy_[1-6].csv --relative \
  --out "$OUT/energy_lanes.png"
# 6. The effect of ks and of kd on the cloth: a lane per value, coloured by strain, and by speed.
figure ks "$OUT/ks.png" "$CLOTHSIM" compare scenes/drape.yaml $SCENE --vary ks=2e3,2e4,2e5 \
  ${SIZE:---width 960 --height 360} --still $VARY_STILL -o "$OUT/ks.png" --quiet
figure kd "$OUT/kd.png" "$CLOTHSIM" compare scenes/drape.yaml $SCENE --vary kd=75,750,7500 --color speed \
  ${SIZE:---width 960 --height 360} --still $VARY_STILL -o "$OUT/kd.png" --quiet
# 7. Work precision on the cloth, with contact as a smooth barrier (the orders come back).
if [ -n "$SMALL" ]; then WP="--set cloth.particles=[9,9] --duration 0.02 --dts 1e-4,2e-4"; else WP="--duration 0.8 --dts 1e-4,1.6e-4,2e-4,2.5e-4"; fi
figure "work precision" "$OUT/wp_cloth.png" "$CLOTHSIM" bench scenes/drape_smooth.yaml $WP --frame-dts none \
  --integrators explicit_euler,symplectic_euler,midpoint,rk4,implicit_euler --csv "$OUT/wp_cloth.csv" --plot "$OUT/wp_cloth.png" --quiet
# 8. The course's fixed point against backward Euler: where each breaks, and the cloth.
figure "fixed point stability" "$OUT/stability_fp.png" "$CLOTHSIM" stability scenes/drape.yaml $STUDY \
  --integrators explicit_euler,implicit_euler_fixed_point,implicit_euler --csv "$OUT/stability_fp.csv" --plot "$OUT/stability_fp.png" --quiet
figure "fixed point clip" "$OUT/fixed_point.png" "$CLOTHSIM" compare scenes/drape_smooth.yaml $SCENE --still $FP_STILL \
  -o "$OUT/fixed_point.png" ${SIZE:---width 960 --height 540} \
  --integrators implicit_euler_fixed_point@1e-4,implicit_euler@1e-4,implicit_euler_fixed_point@2e-4,implicit_euler@2e-4 --quiet
# 9-14. The families on the smooth drape (its first 0.8 s): each lane's metrics, one energy figure.
i=0
for lane in rk4@1e-4 implicit_euler@1/60 newmark@1/60 implicit_midpoint@1/60 bdf2@1/60 imex@1e-3; do
  i=$((i + 1))
  figure "family lane $i" "$OUT/families_$i.csv" "$CLOTHSIM" run scenes/drape_smooth.yaml ${SCENE:---duration 0.8} \
    --integrator "$lane" --metrics "$OUT/families_$i.csv" --quiet
done
figure "families energy" "$OUT/families_energy.png" /usr/bin/python3 tools/plot_energy.py "$OUT"/families_[1-6].csv \
  --relative --out "$OUT/families_energy.png"
echo "figures in $OUT"
