#!/usr/bin/env bash
# Installs the Debian 12 packages dynid needs to build, test and benchmark, including the sanitizer
# and fuzz jobs (clang, its sanitizer and libFuzzer runtimes, llvm-symbolizer for their reports)
# and the Python module (pybind11, NumPy, pytest, and mypy for its type stubs, for Debian's
# python3; venv, setuptools and wheel for `pip install --no-build-isolation .`).
# zsh and groff check the generated shell completion and man pages.
# Idempotent: installs only what is missing, and does nothing (not even apt-get update) when all
# packages are present. Runs as root, or through sudo when not root.
#   scripts/install-deps.sh            build + test + bench dependencies
#   DYNID_WITH_PEERS=1 scripts/install-deps.sh   also the benchmark peers (Orocos KDL, MuJoCo)
set -euo pipefail

packages=(
  build-essential cmake ninja-build git pkg-config
  libeigen3-dev libceres-dev libsuitesparse-dev libnlopt-cxx-dev
  libboost-program-options-dev liburdfdom-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  gnuplot-nox clang-format universal-ctags
  zsh groff-base
  clang libclang-rt-14-dev llvm-14
  pybind11-dev python3-dev python3-numpy python3-pytest python3-mypy python3-distributed
  python3-venv python3-setuptools python3-wheel
  libsqlite3-dev libzstd-dev liblz4-dev libbz2-dev zlib1g-dev python3-rosbag python3-sensor-msgs python3-roslz4
)
if [[ "${DYNID_WITH_PEERS:-0}" == "1" ]]; then
  packages+=(liborocos-kdl-dev libmujoco-dev)
fi

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: not root and no sudo; install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
