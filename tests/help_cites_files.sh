#!/usr/bin/env bash
# Every file a help text cites (mechgen --help and mechgen COMMAND --help) is in the repository:
# tokens like docs/link_loads.md or README.md; placeholders in capitals (FILE.csv, MODEL.yaml) are
# arguments, not files.
#   bash tests/help_cites_files.sh MECHGEN ROOT
set -uo pipefail
mechgen=$1 root=$2
commands=$("$mechgen" --help | awk '/^commands:/{on=1; next} on && NF {print $1}')
[[ $(wc -w <<<"$commands") -ge 10 ]] || { echo "no command list in mechgen --help" >&2; exit 1; }
status=0 cited=0
for command in "" $commands; do
  text=$("$mechgen" $command --help 2>&1)
  for file in $(grep -oE '[A-Za-z0-9_./-]+\.(md|yaml|csv|txt|py|sh|svg|hpp|cpp)\b' <<<"$text" | sort -u); do
    stem=$(basename "$file"); stem=${stem%%.*}
    [[ $stem =~ ^[A-Z0-9_]+$ && $file != *.md ]] && continue  # FILE.csv, MODEL.yaml: arguments
    [[ $file == out/* || $file == /* ]] && continue  # outputs the command writes
    [[ $file =~ ^[A-Z][A-Z0-9]*[_./] ]] && continue    # PREFIX_frontal.svg, DIR/...: placeholders
    # A bare name that is not a document (gait.csv, walk.svg): a file the command writes into the
    # folder it is given; files of the repository are cited with their folder (docs/..., models/...).
    [[ $file != */* && $file != *.md ]] && continue
    cited=$((cited + 1))
    if [[ ! -e $root/$file ]]; then
      echo "mechgen ${command:-} --help cites '$file', which is not in the repository" >&2
      status=1
    fi
  done
done
echo "help texts cite $cited files"
exit $status
