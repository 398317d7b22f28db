#!/usr/bin/env bash
# The numeric reference solver gives the same bytes in every process (issue 27 item 3): GiNaC
# orders the operands of sums by type_info addresses, which address-space randomisation moves, so
# an evaluation that follows GiNaC's order differs in the last bits from run to run. leg3 showed it
# (driver accelerations and joint forces differing by 1e-14 between runs). Runs each model's
# numeric sweep in several processes and compares the files byte for byte.
#   bash tests/numeric_deterministic.sh MECHGEN ROOT
set -uo pipefail
mechgen=$1 root=$2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
status=0
for model in leg3 lecture_leg chebyshev_spatial; do
  for run in 1 2 3 4 5 6; do
    if ! "$mechgen" sweep "$root/models/$model.yaml" --solver numeric --samples 100 \
      --out "$out/$model.$run.csv" >/dev/null 2>"$out/err"; then
      echo "$model: numeric sweep failed: $(cat "$out/err")" >&2
      exit 1
    fi
  done
  distinct=$(md5sum "$out/$model".*.csv | awk '{print $1}' | sort -u | wc -l)
  if [[ $distinct -ne 1 ]]; then
    echo "$model: 6 runs of the numeric sweep gave $distinct different files" >&2
    status=1
  else
    echo "$model: 6 runs, identical bytes"
  fi
done
exit $status
