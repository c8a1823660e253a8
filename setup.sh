#!/usr/bin/env bash
# From a fresh Debian (bookworm) machine to results:
#   ./setup.sh run    install what is missing, build (Release), run parameters/die2d.prm
#   ./setup.sh test   install what is missing, build (Release), run the ctest suite
# Any further arguments of "run" are passed to the program instead of the default deck.
set -euo pipefail
cd "$(dirname "$0")"

packages=(libdeal.ii-dev libeigen3-dev nlohmann-json3-dev numdiff cmake libopenblas0-pthread gnuplot-nox g++ make perl python3 openmpi-bin)

install_missing() {
  local missing=()
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return
  echo "setup: installing ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

# "run" builds the program only; "test" also the test programs.
build() {
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build -j"$(nproc)" "$@"
}

case "${1:-}" in
  run)
    shift
    install_missing
    build --target dieflow
    if [ $# -eq 0 ]; then set -- parameters/die2d.prm; fi
    ./build/dieflow "$@"
    ;;
  test)
    install_missing
    build
    cd build && ctest -j"$(nproc)" --output-on-failure --timeout 300
    ;;
  *)
    echo "usage: ./setup.sh run [DECK.prm] | ./setup.sh test" >&2
    exit 1
    ;;
esac
