#!/usr/bin/env bash
# Installs exactly the Debian (bookworm) packages ViSP SelfCalib needs, and nothing
# when they are all present already (idempotent: safe to run before every build).
#   cmake/install-deps.sh            install what is missing (needs root or sudo)
#   cmake/install-deps.sh --check    only list what is missing; exit 1 if anything is
set -euo pipefail

PACKAGES=(
  cmake g++ make pkg-config
  libvisp-dev visp-images-data
  libeigen3-dev libopencv-dev libnlopt-cxx-dev libceres-dev libyaml-cpp-dev libgtest-dev libcli11-dev liburdfdom-dev
  gnuplot-nox
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi
if [[ "${1:-}" == "--check" ]]; then
  echo "install-deps: missing: ${missing[*]}"
  exit 1
fi

SUDO=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
