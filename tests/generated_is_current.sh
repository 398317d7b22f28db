#!/usr/bin/env bash
# generated_is_current.sh GENERATOR SOURCE_DIR MODEL...: regenerates each model into a temporary
# folder and compares it byte for byte with the committed generated/<model>/; in a git checkout
# also requires generated/ to match the committed files (the build regenerates in place).
# MODEL:BODY is a single-support kernel, generated/MODEL_support_BODY/.
set -euo pipefail
generator=$1 source=$2
shift 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0
for entry in "$@"; do
  if [[ $entry == *:* ]]; then
    model=${entry%%:*}_support_${entry#*:}
    "$generator" "$source/models/${entry%%:*}.yaml" "$tmp/$model" "$source/templates" "${entry#*:}"
  else
    model=$entry
    "$generator" "$source/models/$model.yaml" "$tmp/$model" "$source/templates"
  fi
  if ! diff -r "$source/generated/$model" "$tmp/$model" >"$tmp/$model.diff"; then
    echo "generated/$model differs from a fresh regeneration:"; head -20 "$tmp/$model.diff"; status=1
  fi
done
if git -C "$source" rev-parse --is-inside-work-tree >/dev/null 2>&1 &&
   git -C "$source" ls-files --error-unmatch generated >/dev/null 2>&1; then
  if ! git -C "$source" diff --quiet -- generated; then
    echo "generated/ differs from the committed files: regenerate (build) and commit"
    git -C "$source" diff --stat -- generated; status=1
  fi
fi
[[ $status -eq 0 ]] && echo "generated/ is current for: $*"
exit $status
