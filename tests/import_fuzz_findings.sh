#!/usr/bin/env bash
# Regressions of import_fuzzer's findings (issue 26 item 5; tests/fuzz/import_fuzzer.cpp): each a
# source that `mechgen import` once turned into a description the reader rejects (garbage out),
# now a located error naming the source, exit 1, nothing written.
# usage: import_fuzz_findings.sh MECHGEN SOURCE_DIR
set -u
source "$(dirname "$0")/script_common.sh"
data=$SRC/tests/data
# expect SOURCE MESSAGE: import fails with exactly SOURCE:LINE: error: MESSAGE...
expect() {
  "$M" import "$1" -o "$W/out.yaml" >"$W/stdout" 2>"$W/err"
  local rc=$?
  [ "$rc" = 1 ] || fail "$1: exit $rc: $(cat "$W/stdout" "$W/err")"
  grep -q "^$1:[0-9][0-9]*: error: $2" "$W/err" || fail "$1: $(cat "$W/err")"
  [ ! -e "$W/out.yaml" ] || fail "$1: a description was written: $(cat "$W/out.yaml")"
}
# 1. An MJCF model without bodies (the fuzzer's reproducer, reduced): nothing moves.
expect "$data/mjcf_nothing_moves.xml" "nothing moves: every link of 'empty' is its root or fixed to it"
# 2. The same in URDF: two links welded by a fixed joint.
expect "$data/urdf_nothing_moves.urdf" "nothing moves: every link of 'welded' is its root or fixed to it"
# 3. A URDF inertia no rigid body has (the fuzzer's flipped bit): refused at its link.
expect "$data/urdf_inertia_not_rigid.urdf" "link 'arm': its inertia's principal moments 1e-07, 1e-07, 3e-07 kg m^2 are no rigid body's"
echo "import fuzz findings: ok"
