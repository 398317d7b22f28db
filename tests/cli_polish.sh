#!/usr/bin/env bash
# The command line's polish and figures that cannot mislead (issue 24, items 4 and 5):
#   --version; the top-level help names planar and spatial mechanisms; a misspelled command or
#   option suggests the nearest; spatial sweep --summary; spatial draw --trace / --labels (an
#   unknown point is an error naming the points); views chosen from the extent (lecture_leg lies
#   in the x-z plane); every SVG figure has a viewBox; the located errors quoted in README.md and
#   docs/*.md are what mechgen prints.
#   bash tests/cli_polish.sh MECHGEN ROOT VERSION OUTDIR
set -uo pipefail
mechgen=$1 root=$2 version=$3 dir=$4
rm -rf "$dir" && mkdir -p "$dir" || exit 1
cd "$root" || exit 1
status=0
fail() { echo "FAIL: $*" >&2; status=1; }
# fails PATTERN COMMAND...: exit 1 and one stderr line matching the (extended) regex PATTERN.
fails() {
  local pattern=$1; shift
  local err rc
  err=$("$mechgen" "$@" 2>&1 >/dev/null); rc=$?
  echo "mechgen $*: exit $rc: $err"
  [[ $rc -eq 1 && $(printf '%s\n' "$err" | wc -l) -eq 1 && $err =~ $pattern ]] ||
    fail "mechgen $*: wanted exit 1 and /$pattern/"
}

# --version and version: the project's VERSION, exit 0.
for word in --version version; do
  out=$("$mechgen" $word) || fail "mechgen $word exits $?"
  [[ $out == "mechgen $version" ]] || fail "mechgen $word printed '$out', not 'mechgen $version'"
done
help=$("$mechgen" --help)
[[ $help == *"Planar and spatial mechanisms"* && $help != *"Planar mechanisms from"* ]] ||
  fail "the top-level help does not name planar and spatial mechanisms"

# Misspellings: the nearest command or option; nothing suggested for a word far from all.
fails "^mechgen: error: unknown command 'swep'; did you mean 'sweep'\?" swep
fails "^mechgen: error: unknown command 'darw'; did you mean 'draw'\?" darw
fails "^mechgen: error: unknown option '--verison'; did you mean '--version'\?" --verison
fails "^mechgen: error: unknown command 'frobnicate' \(see mechgen --help\)$" frobnicate
fails "^mechgen: error: unknown command 'swep'; did you mean 'sweep'\?" help swep
fails "^mechgen sweep: error: unknown option '--sumary'; did you mean '--summary'\? \(see mechgen sweep --help\)$" \
  sweep models/slider_crank.yaml --sumary
fails "^mechgen draw: error: unknown option '--trcae'; did you mean '--trace'\?" \
  draw models/rsur.yaml --at 0 --trcae C --out "$dir/x.svg"
fails "^mechgen draw: error: unknown option '--zzzzzz' \(see" draw models/rsur.yaml --zzzzzz

# Spatial sweep --summary: a table of every column's range, exit 0.
out=$("$mechgen" sweep models/leg6.yaml --samples 5 --summary) || fail "spatial sweep --summary exits $?"
grep -Eq '^ +q1\.q +-0\.1 +0\.1( |$)' <<<"$out" || fail "spatial sweep --summary: no q1.q range"

# Spatial draw: --trace of an unknown point names the points; a known one is drawn, with labels.
err=$("$mechgen" draw models/rsur.yaml --at 0 --trace NOSUCH --out "$dir/x.svg" 2>&1)
unknown="^mechgen draw: error: --trace: model 'rsur' has no point 'NOSUCH' \(points: [A-Za-z_0-9, ]*, ([A-Za-z_0-9]+)\) \(see"
[[ $err =~ $unknown ]] ||
  fail "draw --trace NOSUCH: $err"
[[ ! -e $dir/x.svg ]] || fail "draw --trace NOSUCH wrote its file"
point=${BASH_REMATCH[1]:-none}
fails "^mechgen draw: error: --solver: a spatial model is drawn by the numeric solver" \
  draw models/rsur.yaml --at 0 --solver generated --out "$dir/x.svg"
"$mechgen" draw models/rsur.yaml --at 0.1 --trace "$point" --labels --out "$dir/rsur.svg" >/dev/null ||
  fail "spatial draw --trace $point --labels exits $?"
vertices=$(grep -o "id=\"side-trace-$point\"[^>]*" "$dir/rsur.svg" | sed 's/.* points="\([^"]*\)".*/\1/' | wc -w)
distinct=$(grep -o "id=\"front-trace-$point\"[^>]*" "$dir/rsur.svg" | sed 's/.* points="\([^"]*\)".*/\1/' | tr ' ' '\n' | sort -u | wc -l)
echo "rsur: the trace of $point has $vertices vertices in the sagittal view, $distinct distinct in the frontal"
[[ $vertices -eq 120 && $distinct -ge 20 ]] || fail "spatial draw --trace $point: not the path over the step"
[[ $(grep -c 'class="label"' "$dir/rsur.svg") -ge 2 ]] || fail "spatial draw --labels: no labels"
"$mechgen" draw models/rsur.yaml --animate --trace "$point" --out "$dir/rsur_animated.svg" >/dev/null ||
  fail "spatial draw --animate --trace exits $?"
grep -q "id=\"side-tracer-$point\".*<animate attributeName=\"cx\"" "$dir/rsur_animated.svg" ||
  fail "spatial draw --animate --trace: no moving dot"

# lecture_leg lies in the x-y plane: the top view alone, and the drawing says so.
out=$("$mechgen" draw models/lecture_leg.yaml --at 0 --out "$dir/lecture_leg.svg") || fail "draw lecture_leg exits $?"
echo "$out"
[[ $out == *"views: top)"* ]] || fail "lecture_leg: views not chosen from the extent: $out"
grep -Eq 'id="(side|front)-' "$dir/lecture_leg.svg" && fail "lecture_leg: an edge-on view is drawn"
grep -q "sagittal and frontal view left out: the mechanism is edge-on there" "$dir/lecture_leg.svg" ||
  fail "lecture_leg: the drawing does not say which views"

# A drawing's title says what was drawn (it said "4 steps" over a 6-step walk).
"$mechgen" draw models/pasibot.yaml --animate --steps 2 --title "PASIBOT walking" \
  --out "$dir/walk.svg" >/dev/null || fail "draw --steps 2"
grep -q ">PASIBOT walking (2 steps walking, world frame)</text>" "$dir/walk.svg" ||
  fail "draw --steps 2: the title does not say what was drawn"
"$mechgen" draw models/rsur.yaml --at 0.25 --title "RSUR" --out "$dir/rsur_titled.svg" >/dev/null &&
  grep -q ">RSUR (t = 0.25 s)</text>" "$dir/rsur_titled.svg" || fail "spatial draw: the title does not say the time"

# Stresses in MPa as loads prints them, with the yield as a limit line.
"$mechgen" loads models/pasibot.yaml --samples 21 --over-time "$dir/loads_t.csv" >/dev/null || fail "loads"
"$mechgen" plot "$dir/loads_t.csv" --x t --y l7.sigma --limit "max:276,yield 276 MPa" --out "$dir/stress.svg" >/dev/null ||
  fail "plot --limit"
grep -q ">l7.sigma \[MPa\]</text>" "$dir/stress.svg" && grep -q 'class="limit"' "$dir/stress.svg" &&
  grep -q ">yield 276 MPa</text>" "$dir/stress.svg" && grep -q 'class="beyond-limit"' "$dir/stress.svg" || fail "stress plot: not in MPa or no yield line"
fails "^mechgen plot: error: --limit: 'abc' is not a number" plot "$dir/loads_t.csv" --x t --y l7.sigma \
  --limit abc --out "$dir/y.svg"

# Every SVG figure has a viewBox the size of its canvas.
"$mechgen" draw models/chebyshev.yaml --at 0 --out "$dir/chebyshev.svg" >/dev/null || fail "planar draw"
"$mechgen" sweep models/slider_crank.yaml --samples 11 --out "$dir/crank.csv" >/dev/null || fail "sweep"
"$mechgen" plot "$dir/crank.csv" --x t --y crank_angle.effort --out "$dir/plot.svg" >/dev/null || fail "plot"
"$mechgen" workspace models/quadruped_leg.yaml --samples 2000 --threads 1 --fix l3=0 \
  --out "$dir/plane" >/dev/null || fail "workspace"
for svg in "$dir"/*.svg; do
  read -r width height < <(grep -m1 -o '<svg[^>]*' "$svg" | sed -E 's/.* width="([0-9.]+)" height="([0-9.]+)".*/\1 \2/')
  grep -m1 -o '<svg[^>]*' "$svg" | grep -q "viewBox=\"0 0 $width $height\"" ||
    fail "$(basename "$svg") has no viewBox of its ${width:-?} x ${height:-?} canvas"
  echo "$(basename "$svg"): $width x $height"
  awk -v w="$width" -v h="$height" 'BEGIN { exit !(w >= 300 && h >= 100) }' ||
    fail "$(basename "$svg"): a degenerate $width x $height canvas"
done

# The located errors the documentation quotes ("models/M.yaml:L:C: error: ... (with P = V)")
# are what `mechgen sweep models/M.yaml --set P=V` prints, to the letter.
quoted=$(grep -ohE '`models/[a-z0-9_]+\.yaml:[0-9]+:[0-9]+: error: [^`]*\(with [a-z0-9_]+ = [^)`]+\)`' \
  README.md docs/*.md | tr -d '`' | sort -u)
[[ -n $quoted ]] || fail "no located error quoted in README.md or docs/*.md"
while IFS= read -r line; do
  [[ -z $line ]] && continue
  model=${line%%:*}
  set_to=$(sed -E 's/.*\(with ([a-z0-9_]+) = ([^)]+)\)$/\1=\2/' <<<"$line")
  got=$("$mechgen" sweep "$model" --set "$set_to" --samples 2 --summary 2>&1 >/dev/null)
  echo "quoted: $line"
  [[ $got == "$line" ]] || fail "the documentation quotes '$line'; mechgen prints '$got'"
done <<<"$quoted"
exit $status
