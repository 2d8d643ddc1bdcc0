#!/usr/bin/env bash
# Installs the Debian 12 packages Veil needs, if any is missing. Idempotent: a machine that
# has them all is left alone (no apt-get update, no network).
#   scripts/install-deps.sh          what building and rendering need (`make run`, `make install`)
#   scripts/install-deps.sh --test   that, plus what the tests need (`make test`, CI): pytest,
#                                    Matplotlib, Xvfb, Chromium, Slurm and munge, the
#                                    OpenImageIO and OpenVDB command-line tools, and VTK
#   scripts/install-deps.sh --list [--test]   prints the package names and installs nothing
# Packages are installed without their recommendations. No service is started or left
# enabled: during the install a temporary /usr/sbin/policy-rc.d (exit 101) tells the
# packages' scripts not to start anything, and afterwards every systemd unit that came with a
# newly installed package and is enabled is disabled again (munge, slurmctld, slurmd). A
# service the machine had before is not touched. CI starts its own Slurm
# (scripts/slurm/ci-test.sh).
# VTK (libvtk9-dev) is a test package: Debian 12's depends on a JDK (default-jdk,
# libvtk9-java) and Open MPI, about 1 GB, and Veil uses it only for .vti files (`veil export`,
# `veil voxelize --vti`, the 3D textures of --dump), which a build without it refuses with a
# message saying how to get them. The test suites read .vti files, so --test installs it.
set -euo pipefail

build_packages=(
  build-essential cmake ninja-build pkg-config git
  libfmt-dev libglm-dev nlohmann-json3-dev libcli11-dev libgtest-dev
  libepoxy-dev libegl-dev libegl1 libegl-mesa0 libgl1-mesa-dri libglfw3-dev
  libassimp-dev
  libopenvdb-dev libboost-iostreams-dev libtbb-dev
  libopenimageio-dev
  libimgui-dev libspdlog-dev
  pybind11-dev python3-dev python3-numpy
  fonts-dejavu-core
)
test_packages=(
  python3-pytest python3-matplotlib
  xvfb xauth
  chromium
  munge slurmctld slurmd slurm-client
  openimageio-tools libopenvdb-tools
  libvtk9-dev
)

test=0 list=0
for arg in "$@"; do
  case $arg in
    --test) test=1 ;;
    --list) list=1 ;;
    -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    *) echo "install-deps: unknown option '$arg' (--test, --list)" >&2; exit 2 ;;
  esac
done
packages=("${build_packages[@]}")
((test)) && packages+=("${test_packages[@]}")
if ((list)); then
  printf '%s\n' "${packages[@]}"
  exit 0
fi

installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
missing=()
for p in "${packages[@]}"; do
  installed "$p" || missing+=("$p")
done
what="building and rendering"
((test)) && what="building, rendering and the tests"
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages for $what present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo=()
if [ "$(id -u)" -ne 0 ]; then sudo=(sudo); fi
export DEBIAN_FRONTEND=noninteractive

# No service starts while installing: a policy-rc.d of our own (an existing one is kept, and
# put back afterwards if we moved it).
policy=/usr/sbin/policy-rc.d saved=""
restore_policy() {
  if [[ -n $saved ]]; then
    "${sudo[@]}" mv -f "$saved" "$policy"
  else
    "${sudo[@]}" rm -f "$policy"
  fi
}
if [[ -e $policy ]]; then
  saved=$("${sudo[@]}" mktemp /usr/sbin/policy-rc.d.veil-saved.XXXXXX)
  "${sudo[@]}" cp -p "$policy" "$saved"
fi
before=$(dpkg-query -W -f='${Package}\n' 2>/dev/null | sort)
trap restore_policy EXIT
printf '#!/bin/sh\n# scripts/install-deps.sh: no service starts during its install\nexit 101\n' |
  "${sudo[@]}" tee "$policy" >/dev/null
"${sudo[@]}" chmod 755 "$policy"
"${sudo[@]}" apt-get update -q
"${sudo[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
restore_policy
trap - EXIT

# Units of the packages this run installed that their scripts enabled: disabled again
# (systemctl works on the unit files without a running systemd).
new=$(comm -13 <(echo "$before") <(dpkg-query -W -f='${Package}\n' 2>/dev/null | sort))
if command -v systemctl >/dev/null && [[ -n $new ]]; then
  units=()
  while read -r p; do
    while read -r f; do
      [[ $f =~ ^(/usr)?/lib/systemd/system/[^/]+\.(service|socket|timer)$ ]] && units+=("${f##*/}")
    done < <(dpkg-query -L "$p" 2>/dev/null)
  done <<<"$new"
  for u in "${units[@]}"; do
    if [[ $(systemctl is-enabled "$u" 2>/dev/null) == enabled ]]; then
      "${sudo[@]}" systemctl --no-reload disable "$u" >/dev/null 2>&1 &&
        echo "install-deps: disabled $u (installed by this run; Veil needs no service)"
    fi
  done
fi
echo "install-deps: done (${#missing[@]} packages for $what, with their dependencies)"
