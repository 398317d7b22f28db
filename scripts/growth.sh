#!/usr/bin/env bash
# Growth with size (issue 26 item 1): time and peak memory of whole commands against the model's
# size, and the growth exponent fitted to them (log-log least squares).
#   scripts/growth.sh [--quick] [--timeout S] [MECHGEN]     (default build/mechgen)
# Families (scripts/growth_models.sh): spatial serial chains and binary trees of 10, 100, 1000
# driven revolutes with masses; N RSUR loops chained in series, N = 1, 2, 4, ..., 64. Commands:
#   check     reads, checks, assembles, and plans the kernel in memory (its header size)
#   info      the structure and the bodies' table
#   numeric   sweep --solver numeric --samples 11
#   generate  the kernel's header written (the generator; no compiler)
# Each run under `timeout` (default 300 s): a run past it is "timeout" in the table, never a hang.
# Prints one Markdown table per family (wall s / max RSS MB; exit code when not 0) and the fitted
# exponent of time and of memory per command, over the sizes that finished (time fitted where it
# is at least 0.05 s, below that the process start dominates). --quick: 10, 100 bodies; N <= 16.
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/growth_models.sh
quick=0
limit=300
mechgen=build/mechgen
while [[ $# -gt 0 ]]; do
  case $1 in
    --quick) quick=1 ;;
    --timeout) limit=$2; shift ;;
    *) mechgen=$1 ;;
  esac
  shift
done
[[ -x $mechgen ]] || { echo "growth.sh: no mechgen binary at $mechgen (build it, or pass its path)" >&2; exit 2; }
mechgen=$(realpath "$mechgen")
[[ -x /usr/bin/time ]] || { echo "${0##*/}: needs /usr/bin/time (Debian package 'time')" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export MECHGEN_CACHE=$work/cache

# run NAME COMMAND...: one timed run; prints "wall rss_mb rc" (rc 124: timeout)
run() {
  local name=$1
  shift
  /usr/bin/time -f "%e %M" -o "$work/$name.time" timeout "$limit" "$@" >"$work/$name.out" 2>"$work/$name.err"
  local rc=$?
  read -r wall rss <"$work/$name.time" 2>/dev/null || { wall=nan rss=0; }
  # /usr/bin/time writes "Command exited with non-zero status N" first when rc != 0
  if [[ $rc -ne 0 ]]; then read -r wall rss < <(tail -1 "$work/$name.time"); fi
  awk -v w="$wall" -v r="$rss" -v c="$rc" 'BEGIN { printf "%s %.1f %d\n", w, r / 1024, c }'
}

commands=(check info numeric generate)
# family SIZES...: measures every command at every size; the table and the fits
family() {
  local kind=$1
  shift
  local sizes=("$@") n c
  : >"$work/$kind.rows"
  for n in "${sizes[@]}"; do
    "growth_$kind" "$n" >"$work/$kind$n.yaml"
    local model=$work/$kind$n.yaml bodies joints row="$n"
    for c in "${commands[@]}"; do
      case $c in
        check) r=$(run "$kind$n.$c" "$mechgen" check "$model") ;;
        info) r=$(run "$kind$n.$c" "$mechgen" info "$model") ;;
        numeric) r=$(run "$kind$n.$c" "$mechgen" sweep "$model" --solver numeric --samples 11 --out "$work/$kind$n.csv") ;;
        generate) r=$(run "$kind$n.$c" "$mechgen" generate "$model" -o "$work/gen_$kind$n") ;;
      esac
      row+=" $c:${r// /:}"
    done
    echo "$row" >>"$work/$kind.rows"
    echo "  $kind $n done" >&2
  done
  awk -v kind="$kind" -v cmds="${commands[*]}" '
    function cell(s,   p) {  # wall:rss:rc
      split(s, p, ":")
      if (p[3] == 124) return "timeout"
      return sprintf("%.2f s / %.0f MB%s", p[1], p[2], p[3] ? " (exit " p[3] ")" : "")
    }
    BEGIN { nc = split(cmds, cmd, " ") }
    {
      size[NR] = $1
      for (i = 2; i <= NF; i++) { split($i, kv, ":"); v[NR, kv[1]] = kv[2] ":" kv[3] ":" kv[4] }
    }
    END {
      printf "\n%s | ", kind
      for (i = 1; i <= nc; i++) printf "%s%s", cmd[i], i < nc ? " | " : "\n"
      printf "---"; for (i = 1; i <= nc; i++) printf "|---"; print ""
      for (r = 1; r <= NR; r++) {
        printf "%s | ", size[r]
        for (i = 1; i <= nc; i++) printf "%s%s", cell(v[r, cmd[i]]), i < nc ? " | " : "\n"
      }
      printf "fitted exponent (time; memory above the first size) |"
      for (i = 1; i <= nc; i++) {
        tn = 0; sx = sy = sxx = sxy = 0; mn = 0; mx = my = mxx = mxy = 0; late = 0
        for (r = 1; r <= NR; r++) {
          split(v[r, cmd[i]], p, ":")
          if (p[3] != 0) { late = 1; continue }
          x = log(size[r])
          if (p[1] >= 0.05) { tn++; sx += x; sy += log(p[1]); sxx += x * x; sxy += x * log(p[1]) }
          if (r == 1) base = p[2]
          else if (p[2] > base) { mn++; mx += x; my += log(p[2] - base); mxx += x * x; mxy += x * log(p[2] - base) }
        }
        t = tn >= 2 ? sprintf("N^%.2f", (tn * sxy - sx * sy) / (tn * sxx - sx * sx)) : "-"
        m = mn >= 2 ? sprintf("N^%.2f", (mn * mxy - mx * my) / (mn * mxx - mx * mx)) : "-"
        printf " time %s, memory %s%s%s", t, m, late ? " (finished sizes only)" : "", i < nc ? " |" : "\n"
      }
    }' "$work/$kind.rows"
}

echo "mechgen growth family: $("$mechgen" --version 2>/dev/null | head -1), timeout ${limit} s per run"
echo "cells: wall time / peak resident memory (max RSS) of the whole command"
if [[ $quick -eq 1 ]]; then
  family chain 10 100
  family tree 10 100
  family chain_nojac 10 100
  family loops 1 2 4 8 16
else
  family chain 10 100 1000
  family tree 10 100 1000
  family chain_nojac 10 100 1000
  family tree_nojac 10 100 1000
  family loops 1 2 4 8 16 32 64
fi
