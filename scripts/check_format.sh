#!/usr/bin/env bash
# clang-format over the project's own hand-written C++ (runtime/ generator/ tests/ bench/; generated/
# keeps the layout the generator prints, so regeneration stays byte-identical).
#   bash scripts/check_format.sh         fails listing every file that is not formatted
#   bash scripts/check_format.sh --fix   formats them in place
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

mapfile -d '' files < <(find runtime generator tests bench -type f \
  \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' -o -name '*.cc' \) -print0 2>/dev/null | sort -z)
if [[ ${#files[@]} -eq 0 ]]; then
  echo "check_format.sh: no C++ files found" >&2
  exit 1
fi

if [[ ${1:-} == --fix ]]; then
  clang-format -i "${files[@]}"
  exit 0
fi

bad=()
for f in "${files[@]}"; do
  clang-format --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if [[ ${#bad[@]} -gt 0 ]]; then
  echo "Not formatted ($(clang-format --version | head -n 1)):" >&2
  printf '  %s\n' "${bad[@]}" >&2
  echo "Fix with: bash scripts/check_format.sh --fix  (or clang-format -i FILE)" >&2
  exit 1
fi
echo "${#files[@]} files formatted"
