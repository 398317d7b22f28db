#!/usr/bin/env bash
# The kernel size and compile budget (issue 26 item 2, issue 27 item 5; ondemand/kernel_budget.hpp):
# a header over MECHGEN_MAX_KERNEL_MB is refused before any compiler starts; a compiler past its
# time limit is killed with its children and is an error; the memory limit reaches the compiler
# (RLIMIT_AS) and running out of it is an error; `check` states the header's exact size and the
# model's expected cost; a terminal sees the compile's progress.
# usage: kernel_budget.sh MECHGEN SOURCE_DIR   (copies of slider_crank and chebyshev_spatial)
set -u
source "$(dirname "$0")/script_common.sh"
sed "s/name: slider_crank/name: crank_b/" "$SRC/models/slider_crank.yaml" >"$W/crank_b.yaml"
sed "s/name: chebyshev_spatial/name: cheb_b/" "$SRC/models/chebyshev_spatial.yaml" >"$W/cheb_b.yaml"
grep -q "name: cheb_b" "$W/cheb_b.yaml" || fail "the spatial copy was not renamed"
# A compiler that records each start, then compiles.
cat >"$W/cxx" <<SH
#!/bin/sh
echo compile >>"$W/compiles"
exec c++ "\$@"
SH
chmod 755 "$W/cxx"
export MECHGEN_CXX="$W/cxx"
unset CXX MECHGEN_MAX_KERNEL_MB MECHGEN_COMPILE_TIMEOUT MECHGEN_COMPILE_MEMORY_MB
no_build_left() {  # CACHE CASE: no build folder and no library in CACHE
  ! ls -d "$1"/.build-* >/dev/null 2>&1 || fail "$2: a build folder was left: $(ls -a "$1")"
  ! ls "$1"/*.so >/dev/null 2>&1 || fail "$2: a library was made"
}

# 1. check: the header's size is exact (what generate writes, and the first use compiles), the
# cost is the model's (2 s + 25 s/MB, 60 MB + 250 MB/MB), and no warning under the default limit.
for model in crank_b cheb_b; do
  "$M" check "$W/$model.yaml" >"$W/check.out" 2>"$W/check.err" || fail "check $model: $(cat "$W/check.err")"
  line=$(grep "kernel size:" "$W/check.out") || fail "check $model: no size line: $(cat "$W/check.out")"
  bytes=$(sed -E 's/.*kernel size: ([0-9]+) bytes of header.*/\1/' <<<"$line")
  "$M" generate "$W/$model.yaml" -o "$W/gen_$model" >/dev/null 2>&1 || fail "generate $model"
  actual=$(stat -c %s "$W/gen_$model/$model.hpp")
  [ "$bytes" = "$actual" ] || fail "check $model: $bytes bytes stated, the header has $actual"
  expected=$(awk -v b="$bytes" 'BEGIN { mb = b / 1e6; printf "%.2f MB header: about %.0f s and %.0f MB to compile", mb, 2 + 25 * mb, 60 + 250 * mb }')
  grep -qF "$expected" <<<"$line" || fail "check $model: not the model's cost ($expected): $line"
  grep -q "limit 8 MB" <<<"$line" || fail "check $model: default limit not 8 MB: $line"
  ! grep -q "over the limit" "$W/check.out" || fail "check $model: warned under the default limit"
  MECHGEN_MAX_KERNEL_MB=0.01 "$M" check "$W/$model.yaml" >"$W/check.out" 2>&1 || fail "check $model, small limit"
  grep -q "warning: the header is over the limit of 0.01 MB .*first use will be refused" "$W/check.out" ||
    fail "check $model: no warning over the limit: $(cat "$W/check.out")"
done

# 2. A header over the limit is refused before any compiler starts (the variable and the option).
for how in variable option; do
  rm -f "$W/compiles"
  if [ $how = variable ]; then
    MECHGEN_MAX_KERNEL_MB=0.01 "$M" sweep "$W/crank_b.yaml" --cache "$W/c1" --out "$W/o.csv" 2>"$W/err" &&
      fail "over the limit ($how): accepted"
  else
    "$M" sweep "$W/crank_b.yaml" --max-kernel-mb 0.01 --cache "$W/c1" --out "$W/o.csv" 2>"$W/err" &&
      fail "over the limit ($how): accepted"
  fi
  grep -q "error: the kernel of 'crank_b' is too large to compile: 0.05 MB header: about 3 s and [0-9]* MB to compile .*over the limit of 0.01 MB (--max-kernel-mb, MECHGEN_MAX_KERNEL_MB); no compiler was started. Use --solver numeric, or raise the limit (--max-kernel-mb 1)" "$W/err" ||
    fail "over the limit ($how): $(cat "$W/err")"
  [ ! -e "$W/compiles" ] || fail "over the limit ($how): the compiler ran"
  [ ! -e "$W/o.csv" ] || fail "over the limit ($how): an output was written"
  no_build_left "$W/c1" "over the limit ($how)"
done
MECHGEN_MAX_KERNEL_MB=lots "$M" sweep "$W/crank_b.yaml" --cache "$W/c1" --out "$W/o.csv" 2>"$W/err" &&
  fail "MECHGEN_MAX_KERNEL_MB=lots accepted"
grep -q "MECHGEN_MAX_KERNEL_MB='lots' is not a number of MB" "$W/err" || fail "bad limit: $(cat "$W/err")"

# The default limit (8 MB) refuses a Newton-sized kernel: a spatial serial chain of 128 revolutes,
# a 9.96 MB header (about 4 min and 2.5 GB to compile), before any compiler starts (96 revolutes
# were 14.86 MB before the entry points shared their stages, 5.86 MB since).
chain() {  # N: a spatial serial chain of N driven revolutes about z, x, y in turn
  echo "name: chain$1"
  printf 'dimension: spatial\ngravity: [0, 0, -9.81]\nparameters:\n  w: {value: 3}\nbodies:\n'
  printf '  - {name: base, ground: true, points: {P0: [0, 0, 0]}}\n'
  local i axes=("[0, 0, 1]" "[1, 0, 0]" "[0, 1, 0]")
  for ((i = 1; i <= $1; i++)); do
    echo "  - name: b$i"
    echo "    points: {P$((i - 1)): [0, 0, -0.05*$((i - 1))], P$i: [0, 0, -0.05*$i]}"
    echo "    mass: {mass: 0.1, com: [0.001, 0, -0.05*$i + 0.025], inertia: [[1e-4, 0, 0], [0, 1e-4, 0], [0, 0, 5e-5]]}"
  done
  echo "joints:"
  for ((i = 1; i <= $1; i++)); do
    echo "  - {name: j$i, type: revolute, first: $([ $i = 1 ] && echo base || echo b$((i - 1))), second: b$i, s: ${axes[$((i % 3))]}, s0: P$((i - 1))}"
  done
  echo "drivers:"
  for ((i = 1; i <= $1; i++)); do echo "  - {name: q$i, joint: j$i, kind: angle, value: 0.1*sin(w*t + 0.1*$i)}"; done
  echo "step: {t0: 0, t1: 2*pi/w, samples: 11}"
}
# Under the sanitizer build (MECHGEN_SANITIZE_BUILD set) the two long chains are left out: their
# in-memory generation is the instrumented GiNaC's (37 s for the 128 revolutes), and the plain
# build runs both. The limits themselves are checked on the small models above and below.
sanitized=${MECHGEN_SANITIZE_BUILD:-}
if [ -z "$sanitized" ]; then
  chain 128 >"$W/chain128.yaml"
  rm -f "$W/compiles"
  "$M" sweep "$W/chain128.yaml" --cache "$W/c1" --out "$W/o.csv" 2>"$W/err" && fail "chain128: accepted"
  grep -q "error: the kernel of 'chain128' is too large to compile: 9.9[0-9] MB header: about 4 min and 25[0-9][0-9] MB to compile .*over the limit of 8 MB" "$W/err" ||
    fail "chain128: $(cat "$W/err")"
  [ ! -e "$W/compiles" ] || fail "chain128: the compiler ran"
  no_build_left "$W/c1" "chain128"
fi

# 3. A compiler past its time limit: killed with its children, an error naming the model, the size
# and the limit; no build folder left, in about the limit's time.
cat >"$W/slow" <<SH
#!/bin/sh
sleep 300 &
echo \$! >"$W/sleep.pid"
wait
SH
chmod 755 "$W/slow"
start=$(date +%s)
MECHGEN_CXX="$W/slow" "$M" sweep "$W/crank_b.yaml" --compile-timeout 2 --cache "$W/c2" --out "$W/o.csv" \
  2>"$W/err" && fail "timeout: accepted"
took=$(($(date +%s) - start))
[ "$took" -le 20 ] || fail "timeout: took $took s for a 2 s limit"
grep -q "error: compiling the kernel of 'crank_b' failed (stopped at the time limit of 2 s (0.05 MB header, about 3 s expected; --compile-timeout, MECHGEN_COMPILE_TIMEOUT))" "$W/err" ||
  fail "timeout: $(cat "$W/err")"
[ -s "$W/sleep.pid" ] || fail "timeout: the slow compiler never ran"
n=0
while ps -o stat= -p "$(cat "$W/sleep.pid")" 2>/dev/null | grep -qv Z; do
  sleep 0.1
  n=$((n + 1))
  [ $n -lt 50 ] || { kill "$(cat "$W/sleep.pid")"; fail "timeout: the compiler's child outlived it"; }
done
no_build_left "$W/c2" "timeout"

# 4. The memory limit reaches the compiler as its address-space limit (ulimit -v, KiB), and a
# compiler out of memory is an error naming the model, the size and the limit: a compiler that says
# so, then the real one under 60 and 20 MB.
cat >"$W/oom" <<SH
#!/bin/sh
ulimit -v >"$W/ulimit"
echo "cc1plus: out of memory allocating 65536 bytes after a total of 52000000 bytes" >&2
exit 1
SH
chmod 755 "$W/oom"
MECHGEN_CXX="$W/oom" MECHGEN_COMPILE_MEMORY_MB=300 "$M" sweep "$W/crank_b.yaml" --cache "$W/c3" \
  --out "$W/o.csv" 2>"$W/err" && fail "memory: accepted"
[ "$(cat "$W/ulimit")" = $((300000000 / 1024)) ] || fail "memory: the compiler's ulimit -v is $(cat "$W/ulimit")"
grep -q "error: compiling the kernel of 'crank_b' failed (the compiler ran out of memory (0.05 MB header, about [0-9]* MB expected; limit 300 MB, --compile-memory-mb, MECHGEN_COMPILE_MEMORY_MB))" "$W/err" ||
  fail "memory: $(cat "$W/err")"
no_build_left "$W/c3" "memory"
rm -f "$W/compiles"
for mb in 60 20; do  # GCC says it (60 MB), or crashes as its stack cannot grow (20 MB)
  "$M" sweep "$W/crank_b.yaml" --compile-memory-mb $mb --cache "$W/c3" --out "$W/o.csv" 2>"$W/err" &&
    fail "real compiler in $mb MB: accepted"
  grep -qE "(the compiler ran out of memory|exit [0-9]+, a crash: out of memory\?) \(0.05 MB header, about [0-9]+ MB expected; limit $mb MB, --compile-memory-mb" "$W/err" ||
    fail "real compiler in $mb MB: $(cat "$W/err")"
  no_build_left "$W/c3" "real compiler in $mb MB"
done
[ "$(grep -c . "$W/compiles")" = 2 ] || fail "the real compiler did not run twice"

# 5. Under the default limits the first use works and says how long it took (no tty, a short
# compile: no announcement line).
"$M" sweep "$W/crank_b.yaml" --cache "$W/c4" --out "$W/o.csv" 2>"$W/err" >/dev/null || fail "default limits: $(cat "$W/err")"
[ "$(grep -c . "$W/err")" = 1 ] || fail "default limits: more than one line: $(cat "$W/err")"
grep -qE "^mechgen: compiling kernel for crank_b, first use: [0-9.]+ s \(cached in " "$W/err" ||
  fail "default limits: $(cat "$W/err")"

# A compile expected to take more than 30 s (a chain of 48 revolutes, 1.80 MB: about 47 s) says so in
# one line up front when stderr is no terminal (a compiler that fails at once: the line is what is
# tested).
if [ -z "$sanitized" ]; then
  chain 48 >"$W/chain48.yaml"
  printf '#!/bin/sh\nexit 1\n' >"$W/false_cxx"
  chmod 755 "$W/false_cxx"
  MECHGEN_CXX="$W/false_cxx" "$M" sweep "$W/chain48.yaml" --cache "$W/c6" --out "$W/o.csv" 2>"$W/err" &&
    fail "announce: accepted"
  head -1 "$W/err" | grep -qE "^mechgen: compiling kernel for chain48, first use: 1\.[0-9]{2} MB header: about [0-9]+ s and [0-9]+ MB to compile \(expected\)$" ||
    fail "announce: $(cat "$W/err")"
  grep -q "error: compiling the kernel of 'chain48' failed (.*exit 1)" "$W/err" || fail "announce: $(cat "$W/err")"
fi

# 6. On a terminal: the phase, and the elapsed and expected seconds every 2 s while compiling.
if command -v script >/dev/null; then
  cat >"$W/slow5" <<SH
#!/bin/sh
sleep 5
exec c++ "\$@"
SH
  chmod 755 "$W/slow5"
  MECHGEN_CXX="$W/slow5" script -qec "'$M' sweep '$W/cheb_b.yaml' --cache '$W/c5' --out '$W/o.csv'" \
    /dev/null >"$W/tty" 2>&1 || fail "terminal: $(cat "$W/tty")"
  grep -q "first use: generating" "$W/tty" || fail "terminal: no phase: $(cat -v "$W/tty")"
  ticks=$(grep -oE "first use: [0-9]+ s of about [0-9]+ s \([0-9.]+ MB header, compiling\)" "$W/tty" | wc -l)
  [ "$ticks" -ge 3 ] || fail "terminal: $ticks progress updates in 5 s: $(cat -v "$W/tty")"
  grep -qE "first use: [0-9.]+ s \(cached in " "$W/tty" || fail "terminal: no final line: $(cat -v "$W/tty")"
fi
echo "kernel budget: ok"
