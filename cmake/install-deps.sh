#!/usr/bin/env bash
# Installs exactly the Debian (bookworm) packages ViSP SelfCalib needs, and nothing
# when they are all present already (idempotent: safe to run before every build).
#   cmake/install-deps.sh            install what is missing (needs root or sudo)
#   cmake/install-deps.sh --check    only list what is missing; exit 1 if anything is
#   cmake/install-deps.sh --docs     also doxygen, for the API reference (cmake --build build --target doc);
#                                    combines with --check
set -euo pipefail

CHECK=0
DOCS=0
for arg in "$@"; do
  case "$arg" in
    --check) CHECK=1 ;;
    --docs) DOCS=1 ;;
    *) echo "install-deps: unknown option '$arg' (--check, --docs)" >&2; exit 2 ;;
  esac
done

PACKAGES=(
  cmake g++ make pkg-config
  libvisp-dev visp-images-data
  libeigen3-dev libopencv-dev libnlopt-cxx-dev libceres-dev libyaml-cpp-dev libgtest-dev libcli11-dev liburdfdom-dev
  gnuplot-nox
)
if [[ $DOCS -eq 1 ]]; then
  PACKAGES+=(doxygen)
fi

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
if [[ $CHECK -eq 1 ]]; then
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
