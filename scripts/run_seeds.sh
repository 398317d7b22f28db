#!/usr/bin/env bash
# Seed 002 (the hybrid serial-parallel quadruped leg, issue 12) and seed 003's walking example
# from a clean clone, into out/:
#   scripts/run_seeds.sh             every step below, in order
#   scripts/run_seeds.sh swing ...   only the named steps (each expects the earlier ones' files)
# The workspace and the swing's inverse kinematics run on the generated kernels (quadruped_leg's
# positions batch; quadruped_leg_swing's closed-form IK); MECHGEN_SOLVER=numeric runs the swing's
# IK on the numeric reference solver instead. The cylinder forces (follow) come from the numeric
# twin. MECHGEN_SAMPLES sets the workspace draws (default 100000).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
jobs=${MECHGEN_JOBS:-2}
samples=${MECHGEN_SAMPLES:-100000}
solver=${MECHGEN_SOLVER:-generated}
mechgen=build/mechgen
leg=models/quadruped_leg.yaml
swing=models/quadruped_leg_swing.yaml
out=out

steps=(
  build      # Release build of build/mechgen
  workspace  # Monte Carlo over the strokes -> out/quadruped_leg{_sagittal,_frontal}.svg, .csv;
             # the leg's own plane (l3 held at theta10 = 0) -> out/quadruped_leg_plane*
  swing      # the seed's swing S = 0.5 m, H = 0.3 m, T = 2 s: foot path and cylinders (IK) ->
             # out/quadruped_swing_ik.csv; absolute cylinder lengths with the strokes ->
             # out/quadruped_swing_stroke.{csv,svg}; cylinders' coordinates, rates, accelerations
             # and forces -> out/quadruped_swing.csv, out/quadruped_swing_{length,rate,...}.svg
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

# Absolute cylinder lengths |G - H|, |C - F|, |N - M| from the IK sweep's pin positions, with the
# seed's strokes (350..500 mm for l1, l2; 280..340 mm for l3) as constant columns to draw.
stroke_lengths() {
  awk -F, '
    function coord(p, a) { return $(c[p "." a]) }
    function dist(p, q,   x, y, z) {
      x = coord(p, "x") - coord(q, "x"); y = coord(p, "y") - coord(q, "y")
      z = coord(p, "z") - coord(q, "z"); return sqrt(x * x + y * y + z * z)
    }
    NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i
              print "t,l1,l2,l3,l12_min,l12_max,l3_min,l3_max"; next }
    { printf "%s,%.9g,%.9g,%.9g,0.35,0.5,0.28,0.34\n", $(c["t"]), dist("G", "H"), dist("C", "F"),
             dist("N", "M") }' "$1"
}

# One swing: the pose-driven leg's sweep, the actuated leg following it, five plots.
# Cylinder lengths are the columns' q plus the reference lengths (models/quadruped_leg.yaml).
swing_run() {
  local name=$1 title=$2
  shift 2
  "$mechgen" sweep "$swing" --solver "$solver" "$@" --out "$out/${name}_ik.csv"
  stroke_lengths "$out/${name}_ik.csv" >"$out/${name}_stroke.csv"
  # The strokes as limits (dashed): above 0.5 m and below 0.28 m every cylinder is out of stroke
  # (shaded); 0.34 m (l3's end) and 0.35 m (l1's and l2's start) as lines only, since between
  # them a shading would cover lengths in stroke for some cylinders.
  "$mechgen" plot "$out/${name}_stroke.csv" --x t --y l1,l2,l3 \
    --out "$out/${name}_stroke.svg" --title "$title: cylinder lengths and strokes" \
    --ylabel "cylinder length [m]" --limit "max:0.5,stroke end of l1, l2: 0.5 m" \
    --limit "min:0.28,stroke start of l3: 0.28 m" --limit "0.35,stroke start of l1, l2: 0.35 m" \
    --limit "0.34,stroke end of l3: 0.34 m"
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
