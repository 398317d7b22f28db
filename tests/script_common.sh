# Sourced by the command-line test scripts (usage: SCRIPT MECHGEN SOURCE_DIR): M, the mechgen
# binary; SRC, the source tree; W, a private work folder removed on exit; fail MESSAGE.
M=$1
SRC=$2
W=$(mktemp -d)
trap 'rm -rf "$W"' EXIT
fail() {
  echo "FAIL: $*"
  exit 1
}
