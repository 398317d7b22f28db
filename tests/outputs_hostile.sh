#!/usr/bin/env bash
# Outputs and messages under a hostile review (issues 26 and 29), through the command line:
# a sweep killed by SIGTERM or SIGINT mid-write leaves no temporary and the previous file; one
# killed by SIGKILL leaves one that the next run of the same output removes once old; a read-only
# target is refused, a symbolic link written through; a table larger than the free space is refused
# before computing; and the located messages of issue 29 item 6.
# usage: outputs_hostile.sh MECHGEN SOURCE_DIR
set -um  # job control: background runs get SIGINT as a terminal would send it
source "$(dirname "$0")/script_common.sh"
crank=$SRC/models/slider_crank.yaml
echo "previous" >"$W/out.csv"

# A long write (2 * 10^5 rows, about 200 MB), interrupted once its temporary exists.
interrupted() {  # SIGNAL
  "$M" sweep "$crank" --samples 200000 --out "$W/out.csv" >/dev/null 2>&1 &
  local pid=$! n=0
  until compgen -G "$W/.out.csv.??????" >/dev/null; do
    sleep 0.02
    n=$((n + 1))
    [ $n -lt 1500 ] || fail "no temporary appeared"
  done
  kill "-$1" $pid
  wait $pid
  local status=$?
  [ $status -gt 128 ] || fail "SIG$1: exit $status"
}
for signal in TERM INT; do
  interrupted $signal
  [ "$(cat "$W/out.csv")" = previous ] || fail "SIG$signal: the previous file changed"
  compgen -G "$W/.out.csv.*" >/dev/null && fail "SIG$signal left $(ls -a "$W")"
done
interrupted KILL
left=$(compgen -G "$W/.out.csv.??????")
[ -n "$left" ] || fail "SIGKILL left nothing (nothing tested)"
"$M" sweep "$crank" --out "$W/out.csv" >/dev/null || fail "next run"
[ -e "$left" ] || fail "a fresh temporary (maybe a live writer's) was removed"
touch -d '2 hours ago' "$left"
"$M" sweep "$crank" --out "$W/out.csv" >/dev/null || fail "next run"
[ ! -e "$left" ] || fail "the stale temporary of a SIGKILLed run stayed"

# Read-only targets are refused before computing; symbolic links are written through.
chmod 444 "$W/out.csv"
"$M" sweep "$crank" --out "$W/out.csv" >/dev/null 2>"$W/err" && fail "read-only file replaced"
grep -q "out.csv' is read-only (mode 0444): make it writable" "$W/err" || fail "$(cat "$W/err")"
mkdir "$W/real"
ln -s real/table.csv "$W/link.csv"
"$M" sweep "$crank" --out "$W/link.csv" >/dev/null || fail "symbolic link"
[ -L "$W/link.csv" ] && [ -s "$W/real/table.csv" ] || fail "symbolic link replaced"

# A table larger than the free space: refused at once (10^9 rows of 65 columns: about 1.4 TB, more than a test machine has free).
"$M" sweep "$crank" --samples 999999999 --out "$W/huge.csv" >/dev/null 2>"$W/err" &&
  fail "a terabyte fits?"
grep -q "cannot write '$W/huge.csv': it needs about [0-9.]* TB and only .* are free in '$W'" "$W/err" ||
  fail "free space: $(cat "$W/err")"

# Messages (issue 29 item 6): each located, none after a computation.
expect() {  # CASE FILE EXIT-1-COMMAND... ; the message is in $W/err
  local case=$1 message=$2
  shift 2
  "$@" >/dev/null 2>"$W/err" && fail "$case: accepted"
  grep -q -- "$message" "$W/err" || fail "$case: $(cat "$W/err")"
}
long=$(printf 'a%.0s' $(seq 129))
sed "s/name: slider_crank/name: $long/" "$crank" >"$W/long.yaml"
expect "long name" "long.yaml:13:7: error: model name is 129 characters long (at most 128" \
  "$M" check "$W/long.yaml"
sed 's/m_s: {value: 0.5,/m_s: {value: .inf,/' "$crank" >"$W/inf.yaml"
expect ".inf" "inf.yaml:25:16: error: parameter 'm_s' value '.inf' is YAML's infinity" \
  "$M" check "$W/inf.yaml"
sed 's/value: w\*t}/value: .nan}/' "$crank" >"$W/nan.yaml"
expect ".nan" "nan.yaml:58:68: error: driver value '.nan' is YAML's not-a-number" \
  "$M" check "$W/nan.yaml"
sed 's/m_s: {value: 0.5,/m_s: {value: 1e308,/' "$crank" >"$W/heavy.yaml"
expect "mass 1e308" "heavy.yaml:45:11: error: body 'slider': mass 1e+308 kg.*too large for the dynamics" \
  "$M" check "$W/heavy.yaml"
expect "rsur d=0" "a singular geometry divides by zero" \
  "$M" sweep "$SRC/models/rsur.yaml" --set d=0 --out "$W/rsur.csv"
start=$(date +%s%N)
expect "humanoid-gait --out" "cannot write '$W/missing/gait.csv': no folder '$W/missing'" \
  "$M" humanoid-gait "$SRC/models/bioloid.yaml" --out "$W/missing"
[ $(($(date +%s%N) - start)) -lt 2000000000 ] || fail "humanoid-gait computed before checking --out"
"$M" sweep -- "$crank" --out "$W/dashes.csv" >/dev/null 2>"$W/err" || fail "--: $(cat "$W/err")"
echo "outputs and messages: all cases pass"
