#!/usr/bin/env bash
# The growth family (issue 26 item 1; scripts/growth.sh measures it) at small sizes: its models
# (scripts/growth_models.sh) pass check, info, the numeric sweep and generate, and what they compute
# is right:
#   - trees (serial chains and binary trees of 10 and 40 driven revolutes): check's structure (N
#     coordinates, no circuit, N primary); over the sweep every joint follows its driver's law and
#     every body keeps its length (the distance between its two points, from the reference pose);
#   - N chained RSUR loops (N = 1, 2, 4): check's structure (N circuits, N 6N x (6N + 1), one
#     primary, 6N secondary, unique reactions: mobility 1); the sweep closes every loop (each loop's
#     points B_j and C_j, carried by the two bodies that share them, coincide at every sample) and
#     loop 1 moves as models/rsur.yaml alone (its bodies' and joints' kinematic columns equal);
#   - N planar four-bars in series (N = 1, 3): see below.
# Under the sanitizer build (MECHGEN_SANITIZE_BUILD set) only the smallest sizes.
# usage: growth.sh MECHGEN SOURCE_DIR
set -u
source "$(dirname "$0")/script_common.sh"
source "$SRC/scripts/growth_models.sh"
tree_sizes=(10 40)
loop_counts=(1 2 4)
fourbar_counts=(1 3)
if [ -n "${MECHGEN_SANITIZE_BUILD:-}" ]; then
  tree_sizes=(10)
  loop_counts=(1 2)
  fourbar_counts=(2)
fi

# value NAME FILE: the value column of check's structure row NAME
value() {
  awk -v name="$1" 'index($0, "  " name " ") == 1 { v = substr($0, length(name) + 3); sub(/^ +/, "", v); print v; exit }' "$2"
}

# run NAME COMMAND...: the command must succeed within 60 s
run() {
  local name=$1
  shift
  timeout 60 "$@" >"$W/$name.out" 2>"$W/$name.err" || fail "$name: exit $?: $(head -5 "$W/$name.err")"
}

# An awk program over a sweep CSV's rows: c[NAME] the column of NAME, h[I] the name of column I.
csv_check() {  # FILE AWK_BODY
  awk -F, "NR == 1 { for (i = 1; i <= NF; i++) { c[\$i] = i; h[i] = \$i }; next } $2" "$1"
}

for kind in chain tree; do
  for n in "${tree_sizes[@]}"; do
    m=$kind$n
    "growth_$kind" "$n" >"$W/$m.yaml"
    run "$m check" "$M" check "$W/$m.yaml"
    f="$W/$m check.out"
    [ "$(value "joint coordinates" "$f")" = "$n" ] || fail "$m: coordinates: $(cat "$f")"
    [ "$(value "independent circuits" "$f")" = 0 ] || fail "$m: circuits: $(cat "$f")"
    [ "$(value "primary (driven)" "$f")" = "$n (0 virtual)" ] || fail "$m: primary: $(cat "$f")"
    [ "$(value "secondary" "$f")" = 0 ] || fail "$m: secondary: $(cat "$f")"
    grep -q "generated kernel: tree, $n bodies" "$f" || fail "$m: kernel plan: $(grep "generated kernel" "$f")"
    run "$m info" "$M" info "$W/$m.yaml"
    grep -q "^$m (spatial): $((n + 1)) bodies, $n joints, 0 circuits" "$W/$m info.out" ||
      fail "$m info: $(head -3 "$W/$m info.out")"
    run "$m sweep" "$M" sweep "$W/$m.yaml" --solver numeric --samples 13 --out "$W/$m.csv"
    [ "$(wc -l <"$W/$m.csv")" = 14 ] || fail "$m: $(wc -l <"$W/$m.csv") lines in the table"
    # Every joint follows its law 0.1 sin(w t + 0.1 i), w = 3; every body b_i keeps the distance
    # between P_parent and P_i (the reference pose's: the first row is t = 0, all coordinates 0).
    worst=$(csv_check "$W/$m.csv" "
      NR == 2 { for (i = 1; i <= $n; i++) { p = \"$kind\" == \"chain\" ? i - 1 : int((i - 1) / 2); par[i] = p
                  len[i] = sqrt((\$c[\"P\" i \".x\"] - \$c[\"P\" p \".x\"])^2 + (\$c[\"P\" i \".y\"] - \$c[\"P\" p \".y\"])^2 + (\$c[\"P\" i \".z\"] - \$c[\"P\" p \".z\"])^2) } }
      { t = \$c[\"t\"]
        for (i = 1; i <= $n; i++) {
          e = \$c[\"j\" i \".q\"] - 0.1 * sin(3 * t + 0.1 * i); if (e < 0) e = -e; if (e > w) w = e
          p = par[i]
          l = sqrt((\$c[\"P\" i \".x\"] - \$c[\"P\" p \".x\"])^2 + (\$c[\"P\" i \".y\"] - \$c[\"P\" p \".y\"])^2 + (\$c[\"P\" i \".z\"] - \$c[\"P\" p \".z\"])^2)
          e = l - len[i]; if (e < 0) e = -e; if (e > w) w = e
          if (len[i] < 0.04) { w = 1; bad = \"P\" i }  # the reference lengths are 0.05 and 0.054
        } }
      END { printf \"%.3g %s\\n\", w, bad }")
    awk -v w="$worst" 'BEGIN { exit !(w + 0 < 1e-9) }' || fail "$m: joints off their laws or bodies stretched by $worst"
    # The efforts (the sparse Newton-Euler solve above 200 unknowns: tree40's 280) against the power
    # balance: sum effort q' = dK/dt + dV/dt, K and V from the bodies' columns (m = 0.1 kg, inertia
    # diag(1e-4, 1e-4, 5e-5) in the body frame, the ground's at the reference pose; g = 9.81).
    worst=$(csv_check "$W/$m.csv" "
      function back(b, x, y, z, k,   qw, qx, qy, qz, tx, ty, tz) {  # (x, y, z) into body b's frame: axis k
        qw = \$c[b \".qw\"]; qx = -\$c[b \".qx\"]; qy = -\$c[b \".qy\"]; qz = -\$c[b \".qz\"]
        tx = 2 * (qy * z - qz * y); ty = 2 * (qz * x - qx * z); tz = 2 * (qx * y - qy * x)
        if (k == 1) return x + qw * tx + (qy * tz - qz * ty)
        if (k == 2) return y + qw * ty + (qz * tx - qx * tz)
        return z + qw * tz + (qx * ty - qy * tx)
      }
      { power = 0; rate = 0
        for (i = 1; i <= $n; i++) {
          power += \$c[\"q\" i \".effort\"] * \$c[\"q\" i \".qd\"]
          b = \"b\" i
          rate += 0.1 * (\$c[b \".vx\"] * \$c[b \".ax\"] + \$c[b \".vy\"] * \$c[b \".ay\"] + \$c[b \".vz\"] * \$c[b \".az\"] + 9.81 * \$c[b \".vz\"])
          for (k = 1; k <= 3; k++) {
            wk = back(b, \$c[b \".wx\"], \$c[b \".wy\"], \$c[b \".wz\"], k)
            ak = back(b, \$c[b \".alx\"], \$c[b \".aly\"], \$c[b \".alz\"], k)
            rate += (k < 3 ? 1e-4 : 5e-5) * wk * ak
          } }
        e = power - rate; if (e < 0) e = -e; if (e > w) w = e
        if (power > most) most = power }
      END { printf \"%.3g %.3g\\n\", w, most }")
    awk -v w="$worst" 'BEGIN { split(w, v, " "); exit !(v[1] < 1e-10 && v[2] > 1e-4) }' ||
      fail "$m: efforts off the power balance (largest gap, largest power): $worst"
  done
done

# rsur alone: loop 1's reference
run "rsur sweep" "$M" sweep "$SRC/models/rsur.yaml" --solver numeric --samples 37 --out "$W/rsur.csv"
for n in "${loop_counts[@]}"; do
  m=loops$n
  growth_loops "$n" >"$W/$m.yaml"
  run "$m check" "$M" check "$W/$m.yaml"
  f="$W/$m check.out"
  [ "$(value "joint coordinates" "$f")" = $((6 * n + 1)) ] || fail "$m: coordinates: $(cat "$f")"
  [ "$(value "independent circuits" "$f")" = "$n" ] || fail "$m: circuits: $(cat "$f")"
  [ "$(value "network matrix N" "$f")" = "$((6 * n)) x $((6 * n + 1))" ] || fail "$m: N: $(cat "$f")"
  [ "$(value "primary (driven)" "$f")" = "1 (0 virtual)" ] || fail "$m: primary: $(cat "$f")"
  [ "$(value "secondary" "$f")" = $((6 * n)) ] || fail "$m: secondary: $(cat "$f")"
  grep -q "^Newton-Euler: reactions and efforts unique" "$f" || fail "$m: redundant: $(cat "$f")"
  grep -q "generated kernel: closed chain, $((6 * n)) secondary coordinates" "$f" ||
    fail "$m: kernel plan: $(grep "generated kernel" "$f")"
  run "$m info" "$M" info "$W/$m.yaml"
  grep -q "^$m (spatial): $((2 * n + 2)) bodies, $((3 * n + 1)) joints, $n circuits" "$W/$m info.out" ||
    fail "$m info: $(head -3 "$W/$m info.out")"
  run "$m sweep" "$M" sweep "$W/$m.yaml" --solver numeric --samples 37 --out "$W/$m.csv"
  # Closure: a point shared by two bodies, carried by each (centre of mass + rotation of its
  # offset at the reference pose, the row t = 0), lands at the same place; q at t = 0 is identity.
  worst=$(csv_check "$W/$m.csv" "
    function at(b, p, k,   qw, qx, qy, qz, rx, ry, rz, tx, ty, tz) {  # point p carried by body b: axis k
      qw = \$c[b \".qw\"]; qx = \$c[b \".qx\"]; qy = \$c[b \".qy\"]; qz = \$c[b \".qz\"]
      rx = ref[p \".x\"] - ref[b \".x\"]; ry = ref[p \".y\"] - ref[b \".y\"]; rz = ref[p \".z\"] - ref[b \".z\"]
      tx = 2 * (qy * rz - qz * ry); ty = 2 * (qz * rx - qx * rz); tz = 2 * (qx * ry - qy * rx)
      if (k == 1) return \$c[b \".x\"] + rx + qw * tx + (qy * tz - qz * ty)
      if (k == 2) return \$c[b \".y\"] + ry + qw * ty + (qz * tx - qx * tz)
      return \$c[b \".z\"] + rz + qw * tz + (qx * ty - qy * tx)
    }
    function gap(b1, b2, p,   k, e) {
      for (k = 1; k <= 3; k++) { e = at(b1, p, k) - at(b2, p, k); if (e < 0) e = -e; if (e > w) { w = e; where = p \" at t = \" \$c[\"t\"] } }
    }
    NR == 2 { for (i = 1; i <= NF; i++) ref[h[i]] = \$i
              for (j = 1; j <= $n; j++) if (\$c[\"rocker\" j \".qw\"] != 1) { w = 1; where = \"rocker\" j \" not at the reference\" } }
    { for (j = 1; j <= $n; j++) {
        gap(j == 1 ? \"crank\" : \"rocker\" (j - 1), \"coupler\" j, \"B\" j)
        gap(\"coupler\" j, \"rocker\" j, \"C\" j)
        if (\$c[\"jD\" j \".q\"] > most[j]) most[j] = \$c[\"jD\" j \".q\"] } }
    END { for (j = 1; j <= $n; j++) if (most[j] < 1e-6) { w = 1; where = \"rocker\" j \" never moves\" }
          printf \"%.3g %s\\n\", w, where }")
  awk -v w="$worst" 'BEGIN { exit !(w + 0 < 1e-9) }' || fail "$m: loops not closed: $worst"
  # Loop 1 as rsur alone: bodies and joint coordinates (dynamics differ: the chain loads loop 1).
  paste -d, "$W/rsur.csv" "$W/$m.csv" | awk -F, -v n_rsur="$(head -1 "$W/rsur.csv" | tr , '\n' | wc -l)" '
    NR == 1 { for (i = 1; i <= NF; i++) if (i <= n_rsur) a[$i] = i; else b[$i] = i
              for (name in a) {
                other = name; sub(/^coupler\./, "coupler1.", other); sub(/^rocker\./, "rocker1.", other)
                if (name ~ /^j[BCD]\./) other = substr(name, 1, 2) "1" substr(name, 3)
                if (name ~ /\.(effort|fx|fy|fz|mx|my|mz)$/ || name ~ /^[ABCD]\./ || !(other in b)) continue
                pair[name] = other; count++
              }
              if (count < 70) { print "only " count " columns paired"; exit 1 }
              next }
    { for (name in pair) { e = $a[name] - $b[pair[name]]; if (e < 0) e = -e
                           if (e > w) { w = e; at = name " at t = " $1 } } }
    END { if (w > 1e-9) { print "loop 1 differs from rsur by " w " (" at ")"; exit 1 } }' >"$W/pair.out" ||
    fail "$m: $(cat "$W/pair.out")"
  [ "$n" -le 2 ] && { run "$m generate" "$M" generate "$W/$m.yaml" -o "$W/gen_$m"; }
done
# N planar four-bars in series (issue 25 item 5; scripts/growth_kernels.sh): every loop in closed
# form, the crank on its law, every bar keeps its length at every sample (l = 0.02: input pin 1 l
# from its pivot, coupler 3 l, rocker 2.5 l), every rocker moves, and the generated kernel (built
# on first use, in a cache of this test's own) gives the numeric solver's table.
for n in "${fourbar_counts[@]}"; do
  m=fourbars$n
  growth_fourbars "$n" >"$W/$m.yaml"
  run "$m check" "$M" check "$W/$m.yaml"
  grep -q "closed form: yes, every body located in $((n + 1)) groups" "$W/$m check.out" ||
    fail "$m: plan: $(grep "closed form" "$W/$m check.out")"
  run "$m numeric" "$M" sweep "$W/$m.yaml" --solver numeric --samples 37 --out "$W/$m.csv"
  worst=$(csv_check "$W/$m.csv" "
    function gap(p, q, bar,   e) {
      e = sqrt((\$c[p \".x\"] - \$c[q \".x\"])^2 + (\$c[p \".y\"] - \$c[q \".y\"])^2) - bar * 0.02
      if (e < 0) e = -e; if (e > w) { w = e; where = p q \" at t = \" \$c[\"t\"] }
    }
    function off(a, b,   e) { e = a - b; e = atan2(sin(e), cos(e)); return e < 0 ? -e : e }  # mod 2 pi
    { e = off(\$c[\"theta.q\"], atan2(1, 0) + 2 * \$c[\"t\"]); if (e > w) { w = e; where = \"theta\" }
      for (j = 1; j <= $n; j++) {
        gap(\"P\" j, \"C\" j, 3); gap(\"B\" j, \"C\" j, 2.5); gap(j == 1 ? \"A1\" : \"B\" (j - 1), \"P\" j, 1)
        if (j < $n) gap(\"B\" j, \"P\" (j + 1), 1)
        if (NR == 2) first[j] = \$c[\"rocker\" j \".th\"]
        e = off(\$c[\"rocker\" j \".th\"], first[j]); if (e > swing[j]) swing[j] = e } }
    END { for (j = 1; j <= $n; j++) if (swing[j] < 0.1) { w = 1; where = \"rocker\" j \" hardly moves\" }
          printf \"%.3g %s\\n\", w, where }")
  awk -v w="$worst" 'BEGIN { exit !(w ~ /^[0-9]/ && w + 0 < 1e-12) }' ||
    fail "$m: a bar stretched or a law missed by $worst"
  run "$m generated" "$M" sweep "$W/$m.yaml" --samples 37 --cache "$W/cache" --out "$W/$m.gen.csv"
  paste -d, "$W/$m.csv" "$W/$m.gen.csv" | awk -F, '
    NR == 1 { half = NF / 2; next }
    { for (i = 1; i <= half; i++) { e = $i - $(i + half); if (e < 0) e = -e; a = $i < 0 ? -$i : $i
                                    if (e > 1e-9 * (a > 1 ? a : 1)) { print "column " i " at t = " $1 ": " $i " against " $(i + half); exit 1 } } }' \
    >"$W/pair.out" || fail "$m: generated differs from numeric: $(cat "$W/pair.out")"
done
echo "growth family: ok"
