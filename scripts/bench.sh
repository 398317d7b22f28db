#!/usr/bin/env bash
# Performance of the generated kernels against the dense Newton-Euler solve (LU, explicit inverse)
# and the numeric reference solver, per sample (one instant of the model's default step):
#   1. Release build of mechgen_bench in build/ (MECHGEN_BUILD_BENCH=ON)
#   2. mechgen_bench with 5 repetitions: the median CPU time per sample of every variant, and the
#      ratios numeric/generated, dense_lu/generated, dense_inverse/generated,
#      generated/generated_float, generated/generated_batch (and numeric, dense_lu over
#      generated_v3, the kernel compiled for x86-64-v3, where the processor has it)
#   3. the targets of issue 5 met or missed, and the wall time of a 10^6-sample PASIBOT sweep
#      (`mechgen sweep models/pasibot.yaml --samples 1000000 --summary`)
#   4. when valgrind is installed: instructions per sample (callgrind) of pasibot's generated,
#      generated_batch, dense_lu and numeric variants, start-up removed by subtracting a run of 0
#      samples
# Writes out/bench.json (Google Benchmark's JSON) and out/bench.txt (the tables printed here).
#   MECHGEN_JOBS               build parallelism (default 2)
#   MECHGEN_BENCH_BUILD        build folder (default build)
#   MECHGEN_BENCH_SAMPLES      samples per callgrind run (default 1024: whole batch blocks)
#   MECHGEN_BENCH_CALLGRIND    variants counted by callgrind (default below); "" skips step 3
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
jobs=${MECHGEN_JOBS:-2}
build=${MECHGEN_BENCH_BUILD:-build}
samples=${MECHGEN_BENCH_SAMPLES:-1024}
callgrind_variants=${MECHGEN_BENCH_CALLGRIND-pasibot/generated pasibot/generated_batch pasibot/dense_lu pasibot/numeric}
bench=$build/bench/mechgen_bench
out=out

step() { printf '\n==> [%4ds] %s\n' "$SECONDS" "$*"; }

if ! [[ $samples =~ ^[1-9][0-9]*$ ]]; then
  echo "bench.sh: MECHGEN_BENCH_SAMPLES must be a positive integer, not '$samples'" >&2
  exit 1
fi

step "Release build of mechgen_bench ($build/)"
# A build folder configured by another generator cannot be reused: drop its cache.
if [[ -f $build/CMakeCache.txt ]] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$build/CMakeCache.txt"; then
  rm -rf "$build/CMakeCache.txt" "$build/CMakeFiles"
fi
if [[ -f $build/CMakeCache.txt ]] && grep -q '^MECHGEN_SANITIZE:BOOL=ON$' "$build/CMakeCache.txt"; then
  echo "bench.sh: $build is a sanitizer build; set MECHGEN_BENCH_BUILD to a Release build folder" >&2
  exit 1
fi
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMECHGEN_BUILD_BENCH=ON >/dev/null
cmake --build "$build" -j "$jobs" --target mechgen_bench mechgen

mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

step "mechgen_bench: 5 repetitions, medians"
# The console report goes to a log (shown on failure); 0.2 s of CPU time per repetition keeps the
# whole run near half a minute. The sanity check (every solver's driver effort) is shown first.
if ! "$bench" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_min_time=0.2 --benchmark_out="$out/bench.json" --benchmark_out_format=json \
  >"$tmp/console.txt" 2>&1; then
  cat "$tmp/console.txt" >&2
  echo "bench.sh: mechgen_bench failed" >&2
  exit 1
fi
grep '^sanity ' "$tmp/console.txt" || true
grep 'WARNING' "$tmp/console.txt" || true
if grep -q '"error_occurred": true' "$out/bench.json"; then
  grep -B3 -A2 '"error_occurred": true' "$out/bench.json" >&2
  echo "bench.sh: a benchmark reported an error" >&2
  exit 1
fi

# Google Benchmark writes one JSON key per line: collect "<model>/<variant>" -> median CPU time.
# Repetitions already give the median; units are normalised to ns.
awk '
  /"name":/ { name = $2; gsub(/[",]/, "", name) }
  /"aggregate_name":/ { aggregate = $2; gsub(/[",]/, "", aggregate) }
  /"cpu_time":/ { cpu = $2; gsub(/,/, "", cpu) }
  /"time_unit":/ {
    unit = $2; gsub(/[",]/, "", unit)
    scale = unit == "us" ? 1e3 : unit == "ms" ? 1e6 : unit == "s" ? 1e9 : 1
    if (aggregate == "median") { sub(/_median$/, "", name); print name, cpu * scale }
    aggregate = ""
  }
' "$out/bench.json" >"$tmp/medians.txt"
if [[ ! -s $tmp/medians.txt ]]; then
  echo "bench.sh: no medians in $out/bench.json" >&2
  exit 1
fi

{
  echo "Median CPU time per sample (5 repetitions; $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg)):"
  awk '{ split($1, part, "/"); printf "  %-10s %-16s %12.1f ns %14.3f us\n", part[1], part[2], $2, $2 / 1e3 }' \
    "$tmp/medians.txt"
  echo
  echo "Ratios of median times per sample:"
  awk '
    { split($1, part, "/"); time[part[1], part[2]] = $2; if (!(part[1] in seen)) { seen[part[1]] = 1; models[++n] = part[1] } }
    function ratio(m, a, b) {
      if (((m, a) in time) && ((m, b) in time) && time[m, b] > 0)
        printf "  %-10s %-26s %10.2f\n", m, a "/" b, time[m, a] / time[m, b]
    }
    END {
      for (i = 1; i <= n; ++i) {
        ratio(models[i], "numeric", "generated")
        ratio(models[i], "dense_lu", "generated")
        ratio(models[i], "dense_inverse", "generated")
        ratio(models[i], "generated", "generated_float")
        ratio(models[i], "generated", "generated_batch")
        ratio(models[i], "numeric", "generated_v3")
        ratio(models[i], "dense_lu", "generated_v3")
      }
    }
  ' "$tmp/medians.txt"
  echo
  echo "Targets (issue 5), PASIBOT, this run:"
  awk '
    { time[$1] = $2 }
    function check(what, value, unit, limit, ok) {
      printf "  %-34s %10.2f %-6s target %s %-8s %s\n", what, value, unit, (ok ? "met" : "MISSED"), limit, ""
    }
    END {
      g = time["pasibot/generated"]; b = time["pasibot/generated_batch"]
      n = time["pasibot/numeric"]; l = time["pasibot/dense_lu"]
      if (g > 0) check("generated per sample", g / 1e3, "us", "<= 1 us", g <= 1000)
      if (b > 0) check("generated_batch per sample", b / 1e3, "us", "<= 0.25 us", b <= 250)
      if (g > 0 && n > 0) check("numeric / generated", n / g, "x", ">= 150x", n / g >= 150)
      if (g > 0 && l > 0) check("dense_lu / generated", l / g, "x", ">= 25x", l / g >= 25)
      # The same kernel compiled for x86-64-v3 (AVX2, FMA), where the processor has it.
      v = time["pasibot/generated_v3"]
      if (v > 0) check("generated_v3 per sample (x86-64-v3)", v / 1e3, "us", "<= 1 us", v <= 1000)
      if (v > 0 && n > 0) check("numeric / generated_v3", n / v, "x", ">= 150x", n / v >= 150)
      if (v > 0 && l > 0) check("dense_lu / generated_v3", l / v, "x", ">= 25x", l / v >= 25)
    }
  ' "$tmp/medians.txt"
} | tee "$out/bench.txt"

step "mechgen sweep: 10^6 PASIBOT samples, summary only"
# Wall time of the whole command (model reading included), against the 1 s target.
start=$(date +%s.%N)
"$build/mechgen" sweep models/pasibot.yaml --samples 1000000 --summary >"$tmp/sweep.txt"
end=$(date +%s.%N)
head -1 "$tmp/sweep.txt"
awk -v s="$start" -v e="$end" -v cpus="$(nproc)" -v load="$(cut -d' ' -f1 /proc/loadavg)" 'BEGIN {
  w = e - s
  printf "  %-34s %10.2f %-6s target %s %-8s (%s CPUs, load %s)\n", "sweep 10^6 samples --summary", w, "s",
    (w < 1 ? "met" : "MISSED"), "< 1 s", cpus, load
}' | tee -a "$out/bench.txt"

if [[ -z $callgrind_variants ]]; then
  echo "bench.sh: MECHGEN_BENCH_CALLGRIND is empty: no instruction counts"
  exit 0
fi
if ! command -v valgrind >/dev/null; then
  echo "bench.sh: valgrind not found: no instruction counts (apt-get install valgrind)"
  exit 0
fi

step "callgrind: instructions per sample ($samples samples, minus a run of 0)"
# Instructions executed by the whole program ("Collected" in callgrind's summary).
instructions() {
  local variant=$1 n=$2 log=$tmp/callgrind.log
  if ! valgrind --tool=callgrind --callgrind-out-file="$tmp/callgrind.out" \
    "$bench" --instructions "$variant" "$n" >"$log" 2>&1; then
    cat "$log" >&2
    echo "bench.sh: callgrind run of $variant ($n samples) failed" >&2
    return 1
  fi
  local count
  count=$(sed -n 's/^==[0-9]*== Collected : \([0-9]*\)$/\1/p' "$log")
  if [[ -z $count ]]; then
    cat "$log" >&2
    echo "bench.sh: no instruction count in callgrind's output" >&2
    return 1
  fi
  echo "$count"
}
{
  echo
  echo "Instructions per sample (callgrind, $samples samples minus start-up):"
  declare -A per_sample=()
  for variant in $callgrind_variants; do
    base=$(instructions "$variant" 0)
    total=$(instructions "$variant" "$samples")
    per_sample[$variant]=$(awk -v b="$base" -v t="$total" -v n="$samples" \
      'BEGIN { printf "%.0f", (t - b) / n }')
    printf '  %-38s %14s\n' "$variant" "${per_sample[$variant]}"
  done
  # Against the same model's generated kernel, when it was counted.
  for variant in $callgrind_variants; do
    generated=${variant%%/*}/generated
    [[ $variant != "$generated" && -n ${per_sample[$generated]:-} ]] || continue
    awk -v v="$variant" -v g="$generated" -v a="${per_sample[$variant]}" \
      -v b="${per_sample[$generated]}" \
      'BEGIN { if (b > 0) printf "  %-38s %14.2f\n", v " / " g, a / b }'
  done
} | tee -a "$out/bench.txt"
step "done: $out/bench.txt, $out/bench.json"
