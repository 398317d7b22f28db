#!/usr/bin/env bash
# The PASIBOT analysis, from a clean clone, into out/:
#   scripts/run.sh            every step below, in order
#   scripts/run.sh plot ...   only the named steps (each expects the earlier ones' files)
# To add an analysis: write a step_NAME function and append NAME to `steps`.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
jobs=${MECHGEN_JOBS:-2}
mechgen=build/mechgen
model=models/pasibot.yaml
out=out

steps=(
  deps     # Debian packages (scripts/deps.sh)
  build    # Release build in build/
  sweep    # one step of the biped: every named quantity over time -> out/pasibot_step.csv
  plot     # crank (motor) torque over the step -> out/pasibot_torque.svg
  summary  # motor and gait figures of the step -> out/pasibot_summary.txt, and on screen
  loads    # N, V, M and stress of every bar, critical link -> out/pasibot_link_loads{,_t}.csv, .svg
  zmp      # floor reaction on the support foot, ZMP and its margin -> out/pasibot_zmp.csv, .svg
  fig10    # seed Fig. 10: torque over a step for w8 = 1..5 rad/s -> out/pasibot_fig10_speed.*
  fig11    # seed Fig. 11: torque for hip loads 0..15 kg -> out/pasibot_fig11_load.*
  motor    # the seed's motor-gearbox selection -> out/pasibot_motor.txt
  walk     # 6 steps from rest (1.5 s motor ramp), world frame -> out/pasibot_walk.csv, *_torque.svg, *_hip.svg
  draw     # drawings: still out/pasibot.svg, animated step out/pasibot_step.svg, walk out/pasibot_walk.svg
)

step_deps() { bash scripts/deps.sh; }

step_build() {
  if [[ -f build/CMakeCache.txt ]] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' build/CMakeCache.txt; then
    rm -rf build/CMakeCache.txt build/CMakeFiles
  fi
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
  cmake --build build -j "$jobs" --target mechgen
}

# The generated kernel is the default solver; the numeric reference solver stands in only when
# the binary reports that this model's kernel is "not compiled in".
step_sweep() {
  local log=$out/pasibot_step.log
  local status=0
  "$mechgen" sweep "$model" --out "$out/pasibot_step.csv" 2>"$log" || status=$?
  cat "$log" >&2
  [[ $status -ne 0 ]] || return 0
  if grep -qi 'not compiled in' "$log"; then
    echo "run.sh: falling back to the numeric reference solver"
    "$mechgen" sweep "$model" --solver numeric --out "$out/pasibot_step.csv"
  else
    return 1
  fi
}

step_plot() {
  "$mechgen" plot "$out/pasibot_step.csv" --x t --y theta8.effort --out "$out/pasibot_torque.svg" \
    --title "PASIBOT: crank (motor) torque over one step" --ylabel "torque theta8.effort [N m]"
}

step_summary() {
  "$mechgen" summary "$out/pasibot_step.csv" --model "$model" | tee "$out/pasibot_summary.txt"
}

# A PNG next to an SVG when rsvg-convert is installed (optional: the SVG is the figure).
svg_to_png() {
  if command -v rsvg-convert >/dev/null; then
    rsvg-convert -o "${1%.svg}.png" "$1" && echo "png: ${1%.svg}.png"
  else
    echo "run.sh: rsvg-convert not found; no PNG next to $1"
  fi
}

step_fig10() {
  "$mechgen" grid "$model" --grid w8=1,2,3,4,5 --out "$out/pasibot_fig10_speed.csv" \
    --plot "$out/pasibot_fig10_speed.svg" --ylabel "crank (motor) torque theta8.effort [N m]" \
    --title "PASIBOT: motor torque over one step for several crank speeds (seed Fig. 10)"
  svg_to_png "$out/pasibot_fig10_speed.svg"
}

step_fig11() {
  "$mechgen" grid "$model" --grid m_load=0,5,10,15 --out "$out/pasibot_fig11_load.csv" \
    --plot "$out/pasibot_fig11_load.svg" --ylabel "crank (motor) torque theta8.effort [N m]" \
    --title "PASIBOT: motor torque over one step for several hip loads (seed Fig. 11)"
  svg_to_png "$out/pasibot_fig11_load.svg"
}

step_motor() {
  "$mechgen" size-motor "$model" --catalogue models/motor_catalogue.csv --safety 1.5 |
    tee "$out/pasibot_motor.txt"
}

step_walk() {
  "$mechgen" walk "$model" --steps 6 --ramp 1.5 --out "$out/pasibot_walk.csv" | tee "$out/pasibot_walk.txt"
  "$mechgen" plot "$out/pasibot_walk.csv" --x t --y theta8.effort --out "$out/pasibot_walk_torque.svg" \
    --title "PASIBOT walking from rest: motor torque over 6 steps (1.5 s speed ramp)" \
    --ylabel "torque theta8.effort [N m]"
  "$mechgen" plot "$out/pasibot_walk.csv" --x l13.x --y l13.y --out "$out/pasibot_walk_hip.svg" \
    --title "PASIBOT walking: hip centre of mass in the world frame" \
    --xlabel "l13.x [m]" --ylabel "l13.y [m]"
}

step_draw() {
  "$mechgen" draw "$model" --at 0.5 --labels --out "$out/pasibot.svg" \
    --title "PASIBOT, support foot l1 on the floor, flying leg blue"
  "$mechgen" draw "$model" --animate --out "$out/pasibot_step.svg" --title "PASIBOT"
  "$mechgen" draw "$model" --animate --steps 6 --ramp 1.5 --out "$out/pasibot_walk.svg" \
    --title "PASIBOT walking from rest"
}

step_loads() {
  "$mechgen" loads "$model" --csv "$out/pasibot_step.csv" --out "$out/pasibot_link_loads.csv" \
    --over-time "$out/pasibot_link_loads_t.csv" | tee "$out/pasibot_link_loads.txt"
  # In MPa as the table above; the bars' yield strength (the safety factor's numerator) as a limit.
  local yield
  yield=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "yield") c = i; next }
                   $1 == "l7" { print $c / 1e6 }' "$out/pasibot_link_loads.csv")
  "$mechgen" plot "$out/pasibot_link_loads_t.csv" --x t --y l7.sigma,l2.sigma,l3.sigma,l8.sigma \
    --out "$out/pasibot_link_stress.svg" --title "PASIBOT: largest stress along the most loaded bars" \
    --ylabel "sigma = |N|/A + |M|c/I [MPa]" --limit "max:$yield,yield strength $yield MPa"
  # The bending moment along the critical link at its most stressed sample.
  local critical
  critical=$(sed -n 's/^critical link: \([A-Za-z0-9_]*\),.*/\1/p' "$out/pasibot_link_loads.txt")
  "$mechgen" loads "$model" --csv "$out/pasibot_step.csv" --diagram "$critical" \
    --diagram-out "$out/pasibot_critical_link.csv" | tail -n 1
  "$mechgen" plot "$out/pasibot_critical_link.csv" --x s --y M \
    --out "$out/pasibot_critical_link_moment.svg" \
    --title "PASIBOT: bending moment along the critical link $critical at its peak stress" \
    --xlabel "s along the bar from its first axis point [m]" --ylabel "M [N m]"
}

step_zmp() {
  "$mechgen" zmp "$model" --csv "$out/pasibot_step.csv" --out "$out/pasibot_zmp.csv" |
    tee "$out/pasibot_zmp.txt"
  "$mechgen" plot "$out/pasibot_zmp.csv" --x t --y zmp,heel,toe --out "$out/pasibot_zmp.svg" \
    --title "PASIBOT: ZMP on the support foot (heel E at 0, toe F at 0.126 m)" \
    --ylabel "distance from the heel along the sole [m]"
}

mkdir -p "$out"
selected=("$@")
[[ ${#selected[@]} -gt 0 ]] || selected=("${steps[@]}")
for s in "${selected[@]}"; do
  if ! declare -F "step_$s" >/dev/null; then
    echo "run.sh: unknown step '$s' (steps: ${steps[*]})" >&2
    exit 2
  fi
  printf '\n==> [%4ds] %s\n' "$SECONDS" "$s"
  "step_$s"
done
printf '\n==> [%4ds] done; results in %s/\n' "$SECONDS" "$out"
ls -l "$out"
