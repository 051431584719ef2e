#!/usr/bin/env bash
# Installs the Debian packages the project builds and tests with. Safe to run again: apt-get skips
# what is already there. Needs root (as on a fresh Debian 12 machine).
set -euo pipefail
packages=(build-essential cmake libopencv-dev libgtest-dev libgmock-dev libbenchmark-dev
          libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri python3
          python3-matplotlib python3-numpy
          valgrind  # CTest Valgrind: a tiny synthesis under memcheck (Test/RunUnderValgrind.cmake)
          slurmctld slurmd slurm-client munge)  # the Slurm test's single-node cluster (scripts/slurm-local.sh)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "Installing: ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
