#!/usr/bin/env bash
# Cache and branch profile of mechgen_bench benchmarks, per iteration of the timed loop (issue 25):
# callgrind with its cache and branch simulators, told this CPU's L1i, L1d and L2 geometry (read
# from sysfs; callgrind simulates two levels, so the L2 stands for its "LL"), collecting only
# inside Google Benchmark's LambdaBenchmark<...>::Run, the timed loop (start-up, samples, sanity
# checks and reporting excluded). Iterations: the fewest calls the loop makes to any one function
# other than Google Benchmark's (the kernel's stages, mj_rne), printed beside the costs.
#
#   scripts/cache_profile.sh NAME...   e.g. bioloid_support/generated_control bioloid_support/mujoco
#
# Environment: MECHGEN_BENCH (default build/bench/mechgen_bench), MECHGEN_CACHE_MIN_TIME (seconds
# of the slowed run per benchmark, default 0.5), MECHGEN_CACHE_OUT (default out/cache: one
# callgrind.out and log per benchmark, for callgrind_annotate --inclusive=yes).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bench=${MECHGEN_BENCH:-build/bench/mechgen_bench}
min_time=${MECHGEN_CACHE_MIN_TIME:-0.5}
out=${MECHGEN_CACHE_OUT:-out/cache}
[[ $# -ge 1 ]] || { echo "usage: scripts/cache_profile.sh BENCHMARK_NAME..." >&2; exit 2; }
command -v valgrind >/dev/null || { echo "cache_profile.sh: valgrind not found" >&2; exit 1; }
[[ -x $bench ]] || { echo "cache_profile.sh: no benchmark binary $bench" >&2; exit 1; }
mkdir -p "$out"

# SIZE,WAYS,LINE of the cache at sysfs index $1 (0: L1d, 1: L1i, 2: L2 on x86).
geometry() {
  local d=/sys/devices/system/cpu/cpu0/cache/index$1 size
  size=$(<"$d/size")
  echo "$((${size%K} * 1024)),$(<"$d/ways_of_associativity"),$(<"$d/coherency_line_size")"
}
I1=$(geometry 1) D1=$(geometry 0) LL=$(geometry 2)
echo "simulated: I1 $I1, D1 $D1, LL (the L2) $LL (size,ways,line); min_time $min_time s"
printf '%-38s %10s %9s %8s %9s %9s %9s %8s %9s\n' benchmark iterations Ir I1mr ILmr D1mr D1mw DLmr mispred

for name in "$@"; do
  file=$out/callgrind.out.${name//\//_}
  if ! valgrind --tool=callgrind --cache-sim=yes --branch-sim=yes \
    --I1="$I1" --D1="$D1" --LL="$LL" --collect-atstart=no \
    --toggle-collect='benchmark::internal::LambdaBenchmark<*>::Run(benchmark::State)' \
    --compress-strings=no --compress-pos=no --callgrind-out-file="$file" \
    "$bench" --benchmark_filter="^${name}\$" --benchmark_min_time="$min_time" \
    >"$file.log" 2>&1; then
    echo "cache_profile.sh: callgrind run of $name failed (log: $file.log)" >&2
    exit 1
  fi
  # Events: Ir Dr Dw I1mr D1mr D1mw ILmr DLmr DLmw Bc Bcm Bi Bim; calls per caller -> callee.
  awk -v name="$name" '
    /^events:/ { for (i = 2; i <= NF; i++) col[$i] = i }
    /^fn=/ { fn = substr($0, 4) }
    /^cfn=/ { cfn = substr($0, 5) }
    /^calls=/ {
      split($1, a, "=")
      if ((fn ~ /lambda\(benchmark::State&\)|^benchmark::internal::LambdaBenchmark</) &&
          cfn !~ /^benchmark::|lambda\(benchmark::State&\)|^_dl_/)
        calls[cfn] += a[2]
    }
    /^totals:/ { for (e in col) t[e] = $(col[e]) }
    END {
      n = 0
      for (c in calls) if (n == 0 || calls[c] < n) n = calls[c]
      if (n == 0) { print name ": no per-iteration call found" > "/dev/stderr"; exit 1 }
      printf "%-38s %10d %9.0f %8.1f %9.2f %9.1f %9.1f %8.2f %9.1f\n", name, n, t["Ir"] / n,
             t["I1mr"] / n, t["ILmr"] / n, t["D1mr"] / n, t["D1mw"] / n, t["DLmr"] / n,
             (t["Bcm"] + t["Bim"]) / n
    }' "$file" || true  # a benchmark whose loop calls nothing per iteration (KDL's, inlined): the
  # reason is printed, the others go on
done
