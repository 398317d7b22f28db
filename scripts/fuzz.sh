#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz/, clang++-14 with -fsanitize=fuzzer,address,undefined) in
# build-fuzz/ and runs each for a bounded time:
#   scripts/fuzz.sh [SECONDS_PER_TARGET]     (default 60; CI runs scripts/fuzz.sh 10)
# Seeds: models/*.yaml for the reader; the corpus grows in build-fuzz/corpus/. A finding (crash,
# sanitizer report, timeout, out of memory) stops with the reproducer in build-fuzz/ and exit 1.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
root=$PWD
seconds=${1:-60}
bash scripts/deps.sh
launcher=()
if command -v ccache >/dev/null 2>&1; then  # as scripts/test.sh: reruns rebuild what changed
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR=$root CCACHE_NOHASHDIR=1
fi
cmake -S tests/fuzz -B build-fuzz -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=None \
  "${launcher[@]}" >/dev/null
cmake --build build-fuzz -j "${MECHGEN_JOBS:-2}"
mkdir -p build-fuzz/corpus/reader build-fuzz/corpus/kernel build-fuzz/corpus/spatial_kernel
cp -n models/*.yaml build-fuzz/corpus/reader/
export ASAN_OPTIONS="detect_leaks=0:allocator_may_return_null=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
cd build-fuzz
for target in model_reader_fuzzer kernel_fuzzer spatial_kernel_fuzzer; do
  corpus=corpus/reader
  [[ $target == kernel_fuzzer ]] && corpus=corpus/kernel
  [[ $target == spatial_kernel_fuzzer ]] && corpus=corpus/spatial_kernel
  echo "==> $target for ${seconds} s"
  # -rss_limit_mb and -timeout: a memory blow-up or a hang is a finding too; -max_len covers the
  # largest shipped model.
  rc=0
  ./"$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
    -print_final_stats=1 "$corpus" >"$target.log" 2>&1 || rc=$?
  grep -E "^(stat::number_of_executed_units|SUMMARY|==[0-9]+==ERROR|artifact_prefix|Test unit)" \
    "$target.log" || true
  [[ $rc -eq 0 ]] || { tail -40 "$target.log"; echo "fuzz.sh: $target found a problem"; exit 1; }
done
echo "fuzz.sh: no findings in ${seconds} s per target"
