#!/usr/bin/env bash
# Checks the Debian packages mechgen needs and installs the missing ones.
#   bash scripts/deps.sh [PACKAGE...]   (extra PACKAGEs are checked too, e.g. valgrind)
# As root: apt-get installs what is missing. Otherwise: prints the exact sudo line and fails.
# Prints nothing when everything is present. May also be sourced; it then returns the status.
# MECHGEN_DEPS_AS_USER=1 behaves as a non-root user would (for testing this script).

mechgen_deps() {
  local -a wanted=(
    g++ cmake ninja-build pkg-config ccache                    # toolchain (ccache: faster reruns)
    libginac-dev libcln-dev libeigen3-dev libyaml-cpp-dev      # libraries
    libgtest-dev libbenchmark-dev clang-format                 # tests, benchmarks, format check
    clang-14 libclang-rt-14-dev                                # libFuzzer (scripts/fuzz.sh)
    liborocos-kdl-dev                                          # spatial checks against KDL (tests, bench)
    libjs-three                                                # mechgen view: three.js, inlined into each page
    chromium libpng-dev nlohmann-json3-dev                     # view_test: headless browser, PNG, JSON
    liburdfdom-dev libmujoco-dev                               # mechgen import: URDF, MJCF (MuJoCo)
    libsimbody-dev                                             # bench peers (leg6/simbody; MuJoCo above)
    pybind11-dev python3-dev python3-numpy python3-pytest      # the Python module and its tests
    python3-scipy python3-matplotlib                           # examples/python
    procps                                                     # ps: cache and budget tests check a killed compiler's children
    "$@"
  )
  if ! command -v dpkg-query >/dev/null 2>&1; then
    echo "deps.sh: no dpkg-query: not a Debian system; install the equivalents of:" \
      "${wanted[*]}" >&2
    return 0
  fi

  local -a missing=()
  local pkg status
  for pkg in "${wanted[@]}"; do
    status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
    [[ $status == *" ok installed" ]] || missing+=("$pkg")
  done
  [[ ${#missing[@]} -eq 0 ]] && return 0

  if [[ $(id -u) -ne 0 || ${MECHGEN_DEPS_AS_USER:-0} == 1 ]]; then
    echo "deps.sh: missing packages: ${missing[*]}" >&2
    echo "Install them with:" >&2
    echo "  sudo apt-get install -y ${missing[*]}" >&2
    return 1
  fi

  echo "deps.sh: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq || return 1
  apt-get install -y -qq --no-install-recommends "${missing[@]}" </dev/null || return 1

  local -a still=()
  for pkg in "${missing[@]}"; do
    status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
    [[ $status == *" ok installed" ]] || still+=("$pkg")
  done
  if [[ ${#still[@]} -gt 0 ]]; then
    echo "deps.sh: still missing after apt-get install: ${still[*]}" >&2
    return 1
  fi
}

if [[ ${BASH_SOURCE[0]} == "$0" ]]; then
  mechgen_deps "$@"
  exit $?
fi
mechgen_deps "$@"
