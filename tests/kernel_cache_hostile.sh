#!/usr/bin/env bash
# The kernel cache under a hostile review (issues 26 and 29): one compile for 8 simultaneous first
# uses (a lock); a cached kernel loads from a read-only cache with no compiler; planted, truncated,
# symlinked and foreign libraries are never loaded but rebuilt; a folder writable by others or
# owned by another user is refused; a library replaced in the same run is loaded anew; a killed
# first use takes its compiler with it and its build folder is cleaned at the next use.
# usage: kernel_cache_hostile.sh MECHGEN SOURCE_DIR   (a copy of slider_crank: about 1 s a compile)
set -u
M=$1
SRC=$2
W=$(mktemp -d)
chmod 755 "$W"
trap 'chmod -R u+w "$W"; rm -rf "$W"' EXIT
fail() {
  echo "FAIL: $*"
  exit 1
}
# model NAME ROD_LENGTH: slider_crank renamed, with another rod length (another fingerprint).
model() {
  sed "s/name: slider_crank/name: $1/; s/L: {value: 0.2,/L: {value: $2,/" \
    "$SRC/models/slider_crank.yaml" >"$W/$1.yaml"
}
# A compiler that counts its compiles and checks that MECHGEN_CXX's words arrive one by one.
cat >"$W/cxx" <<SH
#!/bin/sh
[ "\$1" = "-Wno-unused" ] || { echo "arguments not split: \$1" >&2; exit 9; }
echo compile >>"$W/compiles"
exec c++ "\$@"
SH
chmod 755 "$W/cxx"
export MECHGEN_CXX="$W/cxx -Wno-unused"
unset CXX
model crank_h 0.25

# 1. Eight simultaneous first uses: one compiles, the others wait for its lock and load it.
pids=()
for i in 1 2 3 4 5 6 7 8; do
  "$M" sweep "$W/crank_h.yaml" --cache "$W/cache" --out "$W/run$i.csv" >/dev/null 2>"$W/run$i.err" &
  pids+=($!)
done
for i in 0 1 2 3 4 5 6 7; do wait "${pids[$i]}" || fail "run $((i + 1)): $(cat "$W/run$((i + 1)).err")"; done
for i in 2 3 4 5 6 7 8; do cmp -s "$W/run1.csv" "$W/run$i.csv" || fail "run $i differs"; done
[ "$(wc -l <"$W/compiles")" -eq 1 ] || fail "$(wc -l <"$W/compiles") compiles for 8 first uses"
[ "$(cat "$W"/run*.err | grep -c 'compiling kernel for crank_h')" -eq 1 ] || fail "compiled twice"
[ "$(stat -c %a "$W/cache")" = 700 ] || fail "cache mode $(stat -c %a "$W/cache")"
# The builder's hash record is what coreutils computes.
(cd "$W/cache" && sha256sum --quiet -c ./*.sha256) || fail "hash record wrong"
lib=$(ls "$W"/cache/crank_h-*.so)

# 2. A read-only cache on a machine without a compiler (no c++ on PATH) loads the cached kernel
# and writes nothing; as root, run as another user (nobody) so that the folder is read-only indeed.
chmod -R a-w,a+rX "$W/cache"  # as an administrator shares a prebuilt cache
before=$(ls -lA --time-style=full-iso "$W/cache"; stat -c %y "$W/cache")
mkdir -m 777 "$W/ro"
as_other=()
[ "$(id -u)" = 0 ] && as_other=("$(command -v setpriv)" --reuid=65534 --regid=65534 --clear-groups)
PATH=/nonexistent "${as_other[@]}" "$M" sweep "$W/crank_h.yaml" \
  --cache "$W/cache" --out "$W/ro/out.csv" 2>"$W/ro.err" || fail "read-only cache: $(cat "$W/ro.err")"
cmp -s "$W/run1.csv" "$W/ro/out.csv" || fail "read-only cache: other rows"
after=$(ls -lA --time-style=full-iso "$W/cache"; stat -c %y "$W/cache")
[ "$before" = "$after" ] || fail "read-only cache was written: $before / $after"
[ ! -s "$W/ro.err" ] || fail "read-only cache: $(cat "$W/ro.err")"
chmod -R u+w,go-rx "$W/cache"

# 3. Libraries that must not be loaded: each is ignored with a warning and rebuilt.
cat >"$W/planted.cpp" <<'CPP'
#include <fcntl.h>
__attribute__((constructor)) static void planted() { creat("/tmp/mechgen_planted_ran", 0600); }
CPP
rm -f /tmp/mechgen_planted_ran
c++ -shared -fPIC "$W/planted.cpp" -o "$W/planted.so" || fail "cannot build the planted library"
rebuilt() {  # CASE: the next run ignores the library, rebuilds it and gives the same rows
  : >"$W/compiles"
  "$M" sweep "$W/crank_h.yaml" --cache "$W/cache" --out "$W/again.csv" 2>"$W/again.err" ||
    fail "$1: $(cat "$W/again.err")"
  grep -q "warning: ignoring the cached kernel .*($2" "$W/again.err" || fail "$1: $(cat "$W/again.err")"
  [ "$(wc -l <"$W/compiles")" -eq 1 ] || fail "$1: not rebuilt"
  cmp -s "$W/run1.csv" "$W/again.csv" || fail "$1: other rows"
  [ ! -e /tmp/mechgen_planted_ran ] || fail "$1: the planted library was executed"
  (cd "$W/cache" && sha256sum --quiet -c ./*.sha256) || fail "$1: hash record wrong"
}
cp "$W/planted.so" "$lib" && rm "$lib.sha256"
rebuilt "planted library" "no content hash recorded"
cp "$W/planted.so" "$lib"
rebuilt "replaced library" "its content is not what was built"
truncate -s 4096 "$lib"
rebuilt "truncated library" "its content is not what was built"
chmod o+w "$lib"
rebuilt "library writable by others" "it is writable by others"
cp "$lib" "$W/elsewhere.so" && ln -sf "$W/elsewhere.so" "$lib"
rebuilt "symbolic link as the library" "a symbolic link"
if [ "$(id -u)" = 0 ]; then
  chown 65534 "$lib"
  rebuilt "library of another user" "it is owned by another user"
fi

# 4. Folders that are refused (exit 1, the reason named) or resolved.
refused() {  # CASE CACHE MESSAGE
  if "$M" sweep "$W/crank_h.yaml" --cache "$2" --out "$W/x.csv" 2>"$W/x.err"; then fail "$1: accepted"; fi
  grep -q "$3" "$W/x.err" || fail "$1: $(cat "$W/x.err")"
}
chmod g+w "$W/cache"
refused "group-writable cache" "$W/cache" "the folder is writable by its group (mode 0720)"
chmod g-w "$W/cache"
if [ "$(id -u)" = 0 ]; then
  chown 65534 "$W/cache"
  refused "cache of another user" "$W/cache" "the folder is owned by another user (uid 65534)"
  chown 0 "$W/cache"
fi
mkdir -m 777 "$W/open"
ln -s "$W/open" "$W/to_open"
refused "symbolic link to a shared folder" "$W/to_open" "not safe to load kernels from"
ln -s "$W/missing" "$W/dangling"
refused "dangling symbolic link" "$W/dangling" "is a symbolic link to a missing folder"
ln -s "$W/cache" "$W/to_cache"
"$M" sweep "$W/crank_h.yaml" --cache "$W/to_cache" --out "$W/x.csv" 2>"$W/x.err" ||
  fail "symbolic link to the cache: $(cat "$W/x.err")"
[ ! -s "$W/x.err" ] || fail "symbolic link to the cache: $(cat "$W/x.err")"
MECHGEN_CXX="'g++'" "$M" sweep "$W/crank_h.yaml" --cache "$W/fresh" --out "$W/x.csv" 2>"$W/x.err" &&
  fail "quoted MECHGEN_CXX accepted"
grep -q "MECHGEN_CXX=''g++'' holds quotes" "$W/x.err" || fail "quoted MECHGEN_CXX: $(cat "$W/x.err")"

# 5. A library of another description under the right name, with a right hash record: loaded,
# rejected, rebuilt, and the new file (not the mapping of the rejected one) is loaded. CXX is
# honoured like MECHGEN_CXX (the same words: the same file names).
model crank_h 0.3
CXX="$MECHGEN_CXX" MECHGEN_CXX= "$M" sweep "$W/crank_h.yaml" --cache "$W/other" --out "$W/long.csv" \
  2>"$W/x.err" || fail "edited model: $(cat "$W/x.err")"
long=$(basename "$(ls "$W"/other/crank_h-*.so)")
[ "$W/cache/$long" != "$lib" ] || fail "same file name for two descriptions"
cp "$lib" "$W/cache/$long"
(cd "$W/cache" && sha256sum "$long" >"$long.sha256")
"$M" sweep "$W/crank_h.yaml" --cache "$W/cache" --out "$W/long2.csv" 2>"$W/x.err" ||
  fail "replaced in the same run: $(cat "$W/x.err")"
grep -q "not a kernel of this description" "$W/x.err" || fail "foreign kernel: $(cat "$W/x.err")"
cmp -s "$W/long.csv" "$W/long2.csv" || fail "replaced in the same run: other rows"

# 6. A first use killed with SIGKILL takes its compiler (and the compiler's children) with it; its
# build folder, once old, is removed by the next build; SIGTERM removes it at once.
cat >"$W/slow" <<SH
#!/bin/sh
sleep 300 &
echo \$! >"$W/sleep.pid"
wait
SH
chmod 755 "$W/slow"
model crank_k 0.27
killed_first_use() {  # SIGNAL: the compiler's child is gone once mechgen died of SIGNAL
  rm -f "$W/sleep.pid"
  MECHGEN_CXX="$W/slow" "$M" sweep "$W/crank_k.yaml" --cache "$W/kcache" --out "$W/k.csv" 2>/dev/null &
  local pid=$! n=0
  while [ ! -s "$W/sleep.pid" ]; do
    sleep 0.1
    n=$((n + 1))
    [ $n -lt 300 ] || fail "the slow compiler never ran"
  done
  kill "-$1" $pid
  wait $pid 2>/dev/null
  local child n=0
  child=$(cat "$W/sleep.pid")
  while ps -o stat= -p "$child" 2>/dev/null | grep -qv Z; do
    sleep 0.1
    n=$((n + 1))
    [ $n -lt 50 ] || { kill "$child"; fail "the compiler outlived mechgen killed with SIG$1"; }
  done
}
killed_first_use KILL
stale=$(ls -d "$W"/kcache/.build-crank_k-* 2>/dev/null)
[ -n "$stale" ] || fail "no build folder after SIGKILL (nothing tested)"
touch -d '2 hours ago' "$stale" "$stale/owner.lock"
killed_first_use TERM
ls -d "$W"/kcache/.build-* 2>/dev/null && fail "build folders left after SIGTERM and a stale one"

# 7. A lock held too long: a clear error naming it, after MECHGEN_CACHE_LOCK_TIMEOUT seconds.
lock=$(ls "$W"/kcache/crank_k-*.lock)
flock "$lock" sleep 10 &
holder=$!
sleep 0.3
MECHGEN_CXX="$W/slow" MECHGEN_CACHE_LOCK_TIMEOUT=1 "$M" sweep "$W/crank_k.yaml" --cache "$W/kcache" --out "$W/k.csv" \
  2>"$W/x.err" && fail "lock timeout: accepted"
kill $holder
grep -q "gave up after 1 s waiting for another process building the kernel of crank_k" "$W/x.err" ||
  fail "lock timeout: $(cat "$W/x.err")"
echo "kernel cache: all cases pass"
