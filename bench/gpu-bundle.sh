#!/usr/bin/env bash
# Packs the benchmark programs, the shared libraries they load and the GL/EGL loader packages
# (glvnd) into .gpu/ of this checkout, for a run on a GPU machine that has the NVIDIA driver
# but none of the project's libraries (bench/README.md).
#
#   bench/gpu-bundle.sh [BUILD_DIR] [extra programs, files or folders...]
#
# BUILD_DIR defaults to build/release; it must hold bench/veil-bench and bench/veil-voxbench
# (cmake --build --preset release --target veil-bench veil-voxbench). Extra programs are
# bundled with their libraries, other files and folders arrive under $GPU_FILES.
# Then, on the GPU machine, from the root of a copy of this checkout that has .gpu/:
#   source .gpu/env.sh && python3 bench/run.py SET...
# env.sh unpacks the loaders and libraries and puts the programs on PATH. Needs apt-get (the
# loader packages are downloaded for amd64, without installing them), ldd, file, tar and xz.
set -euo pipefail
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-$top/build/release}
[ $# -ge 1 ] && shift
progs=("$build/bench/veil-bench" "$build/bench/veil-voxbench")
for p in "${progs[@]}"; do
  [ -x "$p" ] || { echo "gpu-bundle: $p not built (cmake --build --preset release --target veil-bench veil-voxbench)" >&2; exit 2; }
done
out="$top/.gpu"
rm -rf "$out"
mkdir -p "$out/debs" "$out/stage/bin" "$out/stage/lib" "$out/stage/files"
# GL/EGL/Vulkan loaders (glvnd): the NVIDIA driver there supplies the vendor libraries.
lists=${TMPDIR:-/tmp}/veil-gpu-bundle-lists
mkdir -p "$lists/partial"
o="-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=$lists"
[ -n "$(ls -A "$lists" 2>/dev/null | grep -v partial)" ] || apt-get $o update >/dev/null
(cd "$out/debs" && apt-get $o download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 \
  libgles2 >/dev/null)
# Libraries the machine has (libc, the GL dispatch that the loaders above provide) stay out.
skip='^(linux-vdso|libc\.so|libm\.so|libdl\.so|libpthread\.so|librt\.so|ld-linux|libEGL\.so|libGL\.so|libOpenGL\.so|libGLX\.so|libGLdispatch\.so|libGLESv2\.so|libvulkan\.so)'
for f in "${progs[@]}" "$@"; do
  if [ -f "$f" ] && [ -x "$f" ] && file -L "$f" | grep -q ELF; then
    cp -L "$f" "$out/stage/bin/"
    ldd "$f" | awk '/=>/ {print $1, $3}' | while read -r name path; do
      [[ "$name" =~ $skip ]] && continue
      [ -f "$path" ] && cp -Ln "$path" "$out/stage/lib/" 2>/dev/null || true
    done
  else
    cp -rL "$f" "$out/stage/files/"
  fi
done
tar -C "$out/stage" -cJf "$out/payload.tar.xz" . && rm -rf "$out/stage"
# The commit the programs were built from (the GPU machine's copy of the tree has no git).
commit=$(git -C "$top" rev-parse HEAD 2>/dev/null || echo unknown)
dirty=false
[ -n "$(git -C "$top" status --porcelain --untracked-files=no 2>/dev/null)" ] && dirty=true
printf '{"commit": "%s", "dirty": %s, "bundled": "%s"}\n' "$commit" "$dirty" \
  "$(date -u +%Y-%m-%dT%H:%M:%SZ)" > "$out/commit.json"
cat > "$out/env.sh" <<'ENV'
# Sourced on the GPU machine from the checkout root: unpacks the loaders and the programs.
for d in .gpu/debs/*.deb; do dpkg -x "$d" /; done
ldconfig
mkdir -p /tmp/gpu && tar -C /tmp/gpu -xJf .gpu/payload.tar.xz
export PATH=/tmp/gpu/bin:$PATH LD_LIBRARY_PATH=/tmp/gpu/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export GPU_FILES=/tmp/gpu/files VEIL_SHADER_DIR=${VEIL_SHADER_DIR:-$PWD/shaders}
vendor=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
[ -f $vendor ] && export __EGL_VENDOR_LIBRARY_FILENAMES=$vendor
unset vendor
ENV
du -sh "$out" | awk '{print "gpu-bundle: " $1 " in .gpu/ (carry it to the GPU machine)"}'
