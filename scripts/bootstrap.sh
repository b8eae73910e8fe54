#!/usr/bin/env bash
# Installs the Debian packages Freeform needs to build, test and benchmark. Idempotent: when
# everything is present it does nothing. Needs root (or sudo) only when something is missing.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config git ccache
  libeigen3-dev libsuitesparse-dev libopenblas-dev libopenblas0-pthread
  libgtest-dev libgmock-dev libbenchmark-dev
  nlohmann-json3-dev libcli11-dev libfmt-dev libstb-dev
  libcgal-dev libcgal-demo assimp-testmodels
  clang libclang-rt-14-dev
  libgl-dev libopengl-dev libegl-dev libegl-mesa0 libgl1-mesa-dri
  libglfw3-dev libimgui-dev xvfb xauth xdotool x11-utils
  python3-dev pybind11-dev python3-numpy python3-pytest
  python3-venv python3-setuptools python3-wheel python3-build patchelf mypy
  blender
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then missing+=("$p"); fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "bootstrap: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null; then SUDO="sudo"; else
    echo "bootstrap: missing packages (${missing[*]}) and not root; run as root or install sudo" >&2
    exit 1
  fi
fi
echo "bootstrap: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
if ! $SUDO apt-get update -q; then
  echo "bootstrap: 'apt-get update' failed: check the network and /etc/apt/sources.list" >&2
  exit 1
fi
if ! $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"; then
  echo "bootstrap: 'apt-get install' failed for: ${missing[*]}" >&2
  echo "bootstrap: on Debian 12 (bookworm) all of them are in the main archive" >&2
  exit 1
fi
# CHOLMOD is ~2.5x faster with OpenBLAS than with the reference BLAS (measured, issue 3).
if command -v update-alternatives >/dev/null; then
  lib=$(update-alternatives --list libblas.so.3-x86_64-linux-gnu 2>/dev/null | grep openblas-pthread | head -n1 || true)
  [ -n "$lib" ] && $SUDO update-alternatives --set libblas.so.3-x86_64-linux-gnu "$lib" >/dev/null || true
fi
echo "bootstrap: done"
