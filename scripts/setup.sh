#!/usr/bin/env bash
# Installs every build, test and benchmark dependency of Unison from Debian packages.
# Safe to run again: apt-get skips what is already installed.
# Usage: scripts/setup.sh [--determinism | --sanitize]   (--determinism adds clang, the aarch64 cross compiler and
# qemu-user for scripts/determinism.sh; --sanitize adds clang and its sanitizer and libFuzzer runtimes for
# scripts/sanitize.sh, scripts/tsan.sh and scripts/fuzz.sh; --tsan is the same as --sanitize)
set -euo pipefail
packages=(cmake gcc g++ make dpkg-dev libeigen3-dev doctest-dev libbox2d-dev nlohmann-json3-dev libcli11-dev libxxhash-dev
          libsiconos-numerics-dev libbullet-dev pkg-config libenet-dev zlib1g-dev chromium)
# Node and npm drive the browser tests (scripts/browser_test.sh); a machine may already have them from elsewhere.
command -v node >/dev/null || packages+=(nodejs)
command -v npm >/dev/null || packages+=(npm)
if [ "${1:-}" = "--determinism" ]; then
  packages+=(clang g++-aarch64-linux-gnu qemu-user)
fi
if [ "${1:-}" = "--sanitize" ] || [ "${1:-}" = "--tsan" ]; then
  packages+=(clang libclang-rt-14-dev)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update
  $SUDO apt-get install -y "${missing[@]}"
fi
