#!/usr/bin/env bash
# The project cites files outside it (the shared notes, the seed papers) by paths relative to the
# repository root (../shared/...), never by one machine's absolute path: every text file of the
# project is searched for an absolute path under a home or work folder.
#   bash tests/no_machine_paths.sh [ROOT]
set -uo pipefail
root=${1:-$(dirname "${BASH_SOURCE[0]}")/..}
cd "$root" || exit 1
# Built from pieces so that this file does not match itself.
slash=/
pattern="(^|[^.A-Za-z0-9_~$-])${slash}(work|home|Users|root|mnt)${slash}[A-Za-z0-9_.-]"
mapfile -d '' files < <(find README.md .ci bench docs generated generator models runtime scripts \
  templates tests CMakeLists.txt -type f \
  \( -name '*.md' -o -name '*.yaml' -o -name '*.py' -o -name '*.sh' -o -name '*.cpp' \
     -o -name '*.hpp' -o -name '*.in' -o -name '*.txt' -o -name '*.csv' -o -name 'run' \) \
  -print0 2>/dev/null | sort -z)
[[ ${#files[@]} -gt 50 ]] || { echo "no_machine_paths.sh: only ${#files[@]} files found" >&2; exit 1; }
if grep -nE "$pattern" "${files[@]}"; then
  echo "no_machine_paths.sh: absolute machine paths above; cite ../shared/... from the repository root" >&2
  exit 1
fi
echo "no_machine_paths.sh: ${#files[@]} files, no absolute machine path"
