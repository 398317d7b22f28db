#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz/, clang++-14 with -fsanitize=fuzzer,address,undefined) in
# build-fuzz/ and runs each for a bounded time:
#   scripts/fuzz.sh [SECONDS_PER_TARGET]     (default 60; CI runs scripts/fuzz.sh 10)
# Seeds (the corpus grows in build-fuzz/corpus/): models/*.yaml (the spatial bioloid, quadruped_leg,
# rsur among them) and chains of loops (scripts/growth_models.sh) for the reader; rsur's parameters
# as `--set NAME=VALUE` would change them (halved, doubled, zero, negated; scripts/fuzz_seeds.py)
# for the spatial kernel; tests/data/ URDF (+ closures) and MJCF files and ../shared/robots/*/
# robot.urdf + robot.yaml (when that folder is there, and SECONDS >= 60) for the import. A finding (crash, sanitizer
# report, timeout, out of memory) stops with the reproducer in build-fuzz/ and exit 1.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
root=$PWD
seconds=${1:-60}
bash scripts/deps.sh
launcher=()
if command -v ccache >/dev/null 2>&1; then  # as scripts/test.sh (no CCACHE_BASEDIR: see there)
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S tests/fuzz -B build-fuzz -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=None \
  "${launcher[@]}" >/dev/null
cmake --build build-fuzz -j "${MECHGEN_JOBS:-2}"
mkdir -p build-fuzz/corpus/reader build-fuzz/corpus/kernel build-fuzz/corpus/spatial_kernel \
  build-fuzz/corpus/import
cp -n models/*.yaml build-fuzz/corpus/reader/
source scripts/growth_models.sh
for n in 1 2 3; do growth_loops $n >build-fuzz/corpus/reader/growth_loops$n.yaml; done
growth_tree 7 >build-fuzz/corpus/reader/growth_tree7.yaml
robots=()  # the shared robots' imports take 9 to 26 s each under the sanitizers: long runs only
[[ $seconds -ge 60 ]] && robots=(--robots)
python3 scripts/fuzz_seeds.py "$root" build-fuzz/corpus "${robots[@]}"
export ASAN_OPTIONS="detect_leaks=0:allocator_may_return_null=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
cd build-fuzz
for target in model_reader_fuzzer kernel_fuzzer spatial_kernel_fuzzer import_fuzzer; do
  corpus=corpus/reader
  [[ $target == kernel_fuzzer ]] && corpus=corpus/kernel
  [[ $target == spatial_kernel_fuzzer ]] && corpus=corpus/spatial_kernel
  [[ $target == import_fuzzer ]] && corpus=corpus/import
  echo "==> $target for ${seconds} s"
  # -rss_limit_mb and -timeout: a memory blow-up or a hang is a finding too; -max_len covers the
  # largest shipped model.
  rc=0
  limit=10  # per input; an import assembles its loops from 16 starts: up to 8 s for tests/data's
  [[ $target == import_fuzzer ]] && limit=30
  ./"$target" -max_total_time="$seconds" -timeout="$limit" -rss_limit_mb=2048 -max_len=65536 \
    -print_final_stats=1 "$corpus" >"$target.log" 2>&1 || rc=$?
  grep -E "^(stat::number_of_executed_units|SUMMARY|==[0-9]+==ERROR|artifact_prefix|Test unit)" \
    "$target.log" || true
  [[ $rc -eq 0 ]] || { tail -40 "$target.log"; echo "fuzz.sh: $target found a problem"; exit 1; }
done
echo "fuzz.sh: no findings in ${seconds} s per target"
