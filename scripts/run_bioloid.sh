#!/usr/bin/env bash
# The Bioloid humanoid of seed 001 (issue 13), from a clean clone, into out/bioloid/:
#   scripts/run_bioloid.sh            every step below, in order
#   scripts/run_bioloid.sh gait ...   only the named steps (each expects the earlier ones' files)
# The whole-body kinematics run on the numeric reference solver; the single-support torques and
# floor wrench on the generated kernels bioloid_support_r_foot / _l_foot (compiled into mechgen;
# `--solver numeric` in step_gait for the numeric tree dynamics).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
jobs=${MECHGEN_JOBS:-2}
mechgen=build/mechgen
model=models/bioloid.yaml
out=out/bioloid

steps=(
  build  # Release build of build/mechgen
  check  # the whole-body mechanism: 4 circuits, N 24 x 54, 30 primary / 24 secondary -> check.txt
  gait   # LIP walk, 6 steps: gait.csv, Figs. 7-8, torques, ZMP two ways, walk.svg -> gait.txt
)

step_build() {
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
  cmake --build build -j "$jobs" --target mechgen
}

step_check() {
  "$mechgen" check "$model" > "$out/check.txt"
  grep -A8 "^structure" "$out/check.txt"
}

step_gait() {
  "$mechgen" humanoid-gait "$model" --out "$out" --samples-per-step 50 --stall-torque 1.5 |
    tee "$out/gait.txt"
}

mkdir -p "$out"
selected=("$@")
[[ ${#selected[@]} -gt 0 ]] || selected=("${steps[@]}")
for step in "${selected[@]}"; do
  declare -F "step_$step" > /dev/null || { echo "unknown step '$step' (steps: ${steps[*]})" >&2; exit 1; }
  echo "== $step"
  "step_$step"
done
