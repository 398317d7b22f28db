#!/usr/bin/env bash
# The whole suite, from a clean clone:
#   1. dependencies (scripts/deps.sh)
#   2. Release build in build/ and every ctest test (unit, equivalence, regenerate-and-diff, format)
#   3. AddressSanitizer + UndefinedBehaviorSanitizer build in build-asan/ and every test again
#   4. the libFuzzer targets (tests/fuzz/) for 10 s each (scripts/fuzz.sh)
# Exits non-zero at the first failure. MECHGEN_JOBS sets the parallelism (default 2).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
root=$PWD
jobs=${MECHGEN_JOBS:-2}

step() { printf '\n==> [%4ds] %s\n' "$SECONDS" "$*"; }

# A build folder configured by another generator cannot be reused: drop its cache.
configure() {
  local dir=$1
  shift
  if [[ -f $dir/CMakeCache.txt ]] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$dir/CMakeCache.txt"; then
    rm -rf "$dir/CMakeCache.txt" "$dir/CMakeFiles"
  fi
  cmake -S "$root" -B "$dir" -G Ninja $launcher "$@"
}

step "dependencies"
bash scripts/deps.sh

# ccache (scripts/deps.sh installs it) makes a rerun of the suite rebuild only what changed. No
# CCACHE_BASEDIR: with it ccache writes the dependency files' paths relative to the build folder
# ("../generated/leg6/leg6.hpp"), which Ninja does not match with the generator's output (the
# absolute path), so a build that regenerated a kernel left the objects including it stale until
# the next build (found when bench_sanity compared two versions of one kernel).
launcher=
if command -v ccache >/dev/null 2>&1; then
  launcher=-DCMAKE_CXX_COMPILER_LAUNCHER=ccache
fi

step "Release build (build/)"
configure build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$jobs"

step "tests, Release"
ctest --test-dir build --output-on-failure -j "$jobs"

step "sanitizer settings"
# LeakSanitizer needs ptrace-like rights that some containers withhold: probe it on a program
# that does not leak, and fall back to detect_leaks=0 (saying so) when it cannot run.
probe_dir=$(mktemp -d)
trap 'rm -rf "$probe_dir"' EXIT
printf 'int main() { return 0; }\n' >"$probe_dir/probe.cpp"
g++ -fsanitize=address,undefined "$probe_dir/probe.cpp" -o "$probe_dir/probe"
if ASAN_OPTIONS=detect_leaks=1 "$probe_dir/probe" >"$probe_dir/out" 2>&1; then
  leaks=1
else
  leaks=0
  echo "LeakSanitizer does not work here; running with detect_leaks=0:"
  sed 's/^/  /' "$probe_dir/out"
fi
# The fast frame-pointer unwinder at every allocation (ASan's default): the full unwinder
# (fast_unwind_on_malloc=0) made GiNaC-heavy tests 4x slower. Our code keeps its frame pointers,
# so its leaks come with their call chain; scripts/lsan.supp names the libraries (by module: the
# fast unwinder stops at their first frame) whose own leaks it suppresses.
export ASAN_OPTIONS="detect_leaks=$leaks"
export LSAN_OPTIONS="suppressions=$root/scripts/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
echo "ASAN_OPTIONS=$ASAN_OPTIONS"
echo "UBSAN_OPTIONS=$UBSAN_OPTIONS"

# -O1 keeps sanitized tests fast; Debug keeps assert() on.
step "AddressSanitizer + UndefinedBehaviorSanitizer build (build-asan/)"
configure build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-g -O1" \
  -DMECHGEN_SANITIZE=ON -DMECHGEN_BUILD_BENCH=OFF
cmake --build build-asan -j "$jobs"

step "tests, sanitizers"
ctest --test-dir build-asan --output-on-failure -j "$jobs"

# libFuzzer on the model reader and a kernel (clang, sanitizers), a short budget per change;
# scripts/fuzz.sh SECONDS runs longer campaigns.
step "fuzzing (scripts/fuzz.sh 10: 10 s per target)"
bash scripts/fuzz.sh 10

step "all tests passed"
