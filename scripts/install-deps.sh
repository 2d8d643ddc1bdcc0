#!/usr/bin/env bash
# Installs the Debian packages Veil builds and runs with, if any is missing. Idempotent:
# a machine that has them all is left alone (no apt-get update, no network).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libfmt-dev libglm-dev nlohmann-json3-dev libcli11-dev libgtest-dev
  libepoxy-dev libegl-dev libegl1 libegl-mesa0 libgl1-mesa-dri libglfw3-dev
  libassimp-dev
  libopenvdb-dev libboost-iostreams-dev libtbb-dev libopenvdb-tools
  libopenimageio-dev openimageio-tools
  libvtk9-dev
  libimgui-dev libspdlog-dev
  xvfb xauth
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib
  munge slurmctld slurmd slurm-client
  fonts-dejavu-core
  chromium
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
