#!/usr/bin/env bash
# The generated kernels against the model's size (issue 25 item 5): generation time, header size,
# compile time and time per sample, and the growth exponent fitted to each (log-log least squares).
#   scripts/growth_kernels.sh [--quick] [--timeout S] [BUILD]     (default build/)
# Families (scripts/growth_models.sh), N = 1, 2, 4, ..., 64 (--quick: up to 16):
#   fourbars  N planar four-bars in series, each rocker driving the next loop (one driver)
#   chain     a spatial serial chain of N revolutes, every joint driven
# Per size:
#   generate  `mechgen generate` (the generator alone, no compiler): wall s / max RSS MB
#   header    the header it wrote
#   compile   the on-demand build's compiler run (its own command: -O2 -march=native -shared, in a
#             fresh kernel cache), timed by a wrapper given as MECHGEN_CXX: wall s / max RSS MB
#   sample    growth/<model>/generated (bench/growth_bench.cpp), every size in one run of
#             mechgen_bench (medians of 3): the kernel's row entry at the model's step times in
#             order, as a sweep calls it; the same run builds the kernels (the compile column)
# Generation runs under `timeout` and each compile under MECHGEN_COMPILE_TIMEOUT (default 300 s
# each): past it the cell says so, never a hang.
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/growth_models.sh
quick=0
limit=300
build=build
while [[ $# -gt 0 ]]; do
  case $1 in
    --quick) quick=1 ;;
    --timeout) limit=$2; shift ;;
    *) build=$1 ;;
  esac
  shift
done
mechgen=$build/mechgen
bench=$build/bench/mechgen_bench
for binary in "$mechgen" "$bench"; do
  [[ -x $binary ]] || { echo "growth_kernels.sh: no $binary (build it, or pass the build folder)" >&2; exit 2; }
done
mechgen=$(realpath "$mechgen")
[[ -x /usr/bin/time ]] || { echo "${0##*/}: needs /usr/bin/time (Debian package 'time')" >&2; exit 2; }
bench=$(realpath "$bench")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export MECHGEN_CACHE=$work/cache MECHGEN_COMPILE_TIMEOUT=$limit
# The compiler the on-demand build runs, timed: "<library> wall rss_kB rc" per run into compiles.
cat >"$work/cxx" <<'WRAPPER'
#!/bin/sh
out=
previous=
for word in "$@"; do
  [ "$previous" = -o ] && out=$word
  previous=$word
done
/usr/bin/time -f "%e %M" -o "$out.time" "$MECHGEN_GROWTH_CXX" "$@"
rc=$?
echo "$(basename "$out") $(tail -1 "$out.time") $rc" >>"$MECHGEN_GROWTH_LOG"
exit $rc
WRAPPER
chmod +x "$work/cxx"
export MECHGEN_GROWTH_CXX=${MECHGEN_CXX:-${CXX:-c++}} MECHGEN_GROWTH_LOG=$work/compiles
export MECHGEN_CXX=$work/cxx
: >"$work/compiles"

sizes=(1 2 4 8 16 32 64)
[[ $quick -eq 1 ]] && sizes=(1 2 4 8 16)
families=(fourbars chain)
models=
for kind in "${families[@]}"; do
  : >"$work/$kind.rows"
  for n in "${sizes[@]}"; do
    name=$kind$n
    "growth_$kind" "$n" >"$work/$name.yaml"
    models+="$work/$name.yaml:"
    /usr/bin/time -f "%e %M" -o "$work/$name.t" timeout "$limit" \
      "$mechgen" generate "$work/$name.yaml" -o "$work/gen_$name" >/dev/null 2>"$work/$name.err"
    rc=$?
    bytes=$(stat -c %s "$work/gen_$name/$name.hpp" 2>/dev/null || echo 0)
    echo "$n $bytes $(tail -1 "$work/$name.t") $rc" >>"$work/$kind.rows"
    echo "  $name generated" >&2
  done
done

# First use (the compile column) and time per sample: every size of every family in one run.
MECHGEN_BENCH_MODELS=$models "$bench" --benchmark_filter='^growth/' --benchmark_repetitions=3 \
  --benchmark_report_aggregates_only=true --benchmark_format=csv 2>"$work/bench.err" |
  awk -F, '$1 ~ /_median"$/ { split($1, p, "/"); print p[2], $3 }' >"$work/samples"
grep "not timed" "$work/bench.err" >&2
# "<model>.so wall rss rc" (the build folder's library) -> "<model> wall rss rc"
sed 's/\.so / /' "$work/compiles" >"$work/compiled"

echo "mechgen kernels against size: $("$mechgen" --version 2>/dev/null | head -1), load $(cut -d' ' -f1 /proc/loadavg)"
for kind in "${families[@]}"; do
  awk -v kind="$kind" -v limit="$limit" '
    FILENAME ~ /samples$/ { ns[$1] = $2; next }
    FILENAME ~ /compiled$/ { cw[$1] = $2; cm[$1] = $3; crc[$1] = $4; next }
    {
      n[++rows] = $1; header[rows] = $2; gw[rows] = $3; gm[rows] = $4; grc[rows] = $5
      m = kind $1; ts[rows] = ns[m]; c_w[rows] = cw[m]; c_m[rows] = cm[m]; c_rc[rows] = crc[m]
    }
    function fit(col,   r, k, sx, sy, sxx, sxy, x, y) {
      k = sx = sy = sxx = sxy = 0
      for (r = 1; r <= rows; r++) {
        y = col == "g" ? gw[r] : col == "h" ? header[r] : col == "c" ? c_w[r] : ts[r]
        if (y == "" || y + 0 <= 0 || (col == "g" && grc[r]) || (col == "c" && c_rc[r])) continue
        if ((col == "g" || col == "c") && y < 0.05) continue  # process start dominates
        x = log(n[r]); y = log(y); k++; sx += x; sy += y; sxx += x * x; sxy += x * y
      }
      return k >= 2 ? sprintf("N^%.2f", (k * sxy - sx * sy) / (k * sxx - sx * sx)) : "-"
    }
    END {
      printf "\n| %s N | generate | header | compile (first use) | time per sample |\n", kind
      print "|---|---|---|---|---|"
      for (r = 1; r <= rows; r++) {
        g = grc[r] == 124 ? "timeout (" limit " s)" : sprintf("%.2f s / %.0f MB%s", gw[r], gm[r] / 1024, grc[r] ? " (exit " grc[r] ")" : "")
        c = c_w[r] == "" ? "not compiled (see above)" : c_rc[r] ? "failed (exit " c_rc[r] ")" : sprintf("%.1f s / %.0f MB", c_w[r], c_m[r] / 1024)
        t = ts[r] == "" ? "-" : sprintf("%.0f ns", ts[r])
        printf "| %d | %s | %.0f kB | %s | %s |\n", n[r], g, header[r] / 1000, c, t
      }
      printf "| fitted | %s | %s | %s | %s |\n", fit("g"), fit("h"), fit("c"), fit("t")
    }' "$work/samples" "$work/compiled" "$work/$kind.rows"
done
