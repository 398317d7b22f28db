#!/usr/bin/env bash
# Seed 002 (the hybrid serial-parallel quadruped leg, issue 12) and seed 003's walking example
# from a clean clone, into out/:
#   scripts/run_seeds.sh             every step below, in order
#   scripts/run_seeds.sh swing ...   only the named steps (each expects the earlier ones' files)
# Spatial models have no generated kernels yet (issue 11): everything runs on the numeric
# reference solver. MECHGEN_SAMPLES sets the workspace draws (default 100000, about 80 us CPU each).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
jobs=${MECHGEN_JOBS:-2}
samples=${MECHGEN_SAMPLES:-100000}
mechgen=build/mechgen
leg=models/quadruped_leg.yaml
swing=models/quadruped_leg_swing.yaml
out=out

steps=(
  build      # Release build of build/mechgen
  workspace  # Monte Carlo over the strokes -> out/quadruped_leg{_sagittal,_frontal}.svg, .csv;
             # the leg's own plane (l3 held at theta10 = 0) -> out/quadruped_leg_plane*
  swing      # the seed's swing S = 0.5 m, H = 0.3 m, T = 2 s: foot path and cylinders (IK) ->
             # out/quadruped_swing_ik.csv; cylinders' lengths, rates, accelerations and forces ->
             # out/quadruped_swing.csv and out/quadruped_swing_{length,rate,acceleration,force}.svg
  feasible   # the same with the largest lift inside the strokes (H = 0.184 m) -> *_feasible*
  walking    # seed 003: examples/walking built as its own project (build-walking/), 3 s at 1 kHz ->
             # out/lecture_walking.csv; joint angles, leg angles, foot paths -> out/lecture_walking_*.svg
)

step_build() {
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
  cmake --build build -j "$jobs" --target mechgen
}

step_workspace() {
  "$mechgen" workspace "$leg" --samples "$samples" --out "$out/quadruped_leg"
  "$mechgen" workspace "$leg" --samples "$samples" --fix l3=0 --out "$out/quadruped_leg_plane"
}

# One swing: the pose-driven leg's sweep, the actuated leg following it, four plots.
# Cylinder lengths are the columns' q plus the reference lengths (models/quadruped_leg.yaml).
swing_run() {
  local name=$1 title=$2
  shift 2
  "$mechgen" sweep "$swing" --solver numeric "$@" --out "$out/${name}_ik.csv"
  "$mechgen" follow "$swing" --twin "$leg" "$@" --out "$out/$name.csv"
  local what unit
  for what in q:length:m qd:rate:m/s qdd:acceleration:m/s^2 effort:force:N; do
    IFS=: read -r col label unit <<<"$what"
    "$mechgen" plot "$out/$name.csv" --x t --y "l1.$col" --y "l2.$col" --y "l3.$col" \
      --out "$out/${name}_$label.svg" --title "$title: cylinder $label" \
      --ylabel "cylinder $label$([[ $col == q ]] && echo ' from the reference pose') [$unit]"
  done
}

step_swing() { swing_run quadruped_swing "seed 002 swing S = 0.5 m, H = 0.3 m"; }
step_feasible() {
  swing_run quadruped_swing_feasible "swing S = 0.5 m, H = 0.184 m (inside the strokes)" --set H=0.184
}

step_walking() {
  cmake -S examples/walking -B build-walking -G Ninja -DCMAKE_BUILD_TYPE=Release
  cmake --build build-walking
  build-walking/walking "$out/lecture_walking.csv"
  local csv=$out/lecture_walking.csv
  "$mechgen" plot "$csv" --x t --y right.q1 --y right.q2 --y right.q3 \
    --out "$out/lecture_walking_joints.svg" --ylabel "joint angle [rad]" \
    --title "seed 003 minimal walking function: right leg joint angles (abstract kinematics)"
  "$mechgen" plot "$csv" --x t --y right.theta_leg --y left.theta_leg --y right.eta --y left.eta \
    --out "$out/lecture_walking_pattern.svg" --ylabel "leg angle [rad], extension" \
    --title "seed 003 step pattern: leg angle and extension, legs in antiphase"
  "$mechgen" plot "$csv" --x right.toe.x --y right.toe.y --equal \
    --out "$out/lecture_walking_foot.svg" --xlabel "toe x from the hip [m]" \
    --ylabel "toe y from the hip [m]" --title "seed 003: toe path relative to the hip (generated FK)"
}

mkdir -p "$out"
selected=("$@")
[[ ${#selected[@]} -gt 0 ]] || selected=("${steps[@]}")
for step in "${selected[@]}"; do
  echo "== $step"
  "step_$step"
done
