#!/usr/bin/env bash
# Set everything up on a fresh Debian machine (as root) and
#   bash quickstart.sh example   build in Release (build/) and run prm/block-adaptive.prm
#   bash quickstart.sh test      the bad-input test in Release (build/), then
#                                the whole test suite in Debug (build-debug/)
set -euo pipefail
cd "$(dirname "$0")"
what=${1:-}
jobs=$(nproc)

install_dependencies() {
  local packages="cmake make g++ perl openmpi-bin libdeal.ii-dev libgmsh-dev numdiff libopenblas0 python3"
  local missing=""
  for p in $packages; do
    dpkg -s "$p" > /dev/null 2>&1 || missing="$missing $p"
  done
  if [ -n "$missing" ]; then
    echo "installing:$missing"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -q
    apt-get install -y -q $missing
  fi
}

build() { # build DIRECTORY BUILD_TYPE
  cmake -S . -B "$1" -DCMAKE_BUILD_TYPE="$2" > /dev/null
  cmake --build "$1" -j "$jobs"
}

case "$what" in
  example)
    install_dependencies
    build build Release
    ./build/signorini prm/block-adaptive.prm
    echo "results in output-block-adaptive/ (open solution.pvd in ParaView)"
    ;;
  test)
    install_dependencies
    build build Release
    (cd build && ctest -R bad_input --output-on-failure)
    build build-debug Debug
    (cd build-debug && ctest -j "$jobs" --output-on-failure)
    ;;
  *)
    echo "usage: bash quickstart.sh example|test" >&2
    exit 1
    ;;
esac
