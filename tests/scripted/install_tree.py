#!/usr/bin/env python3
"""An installed veil works without the source and build trees (cmake/install.cmake,
src/gpu/shader.cpp). Installs the build into a temporary prefix, moves the prefix elsewhere
(nothing in it may point back at where it was installed), and from an empty working folder,
with VEIL_SHADER_DIR unset:

  1. the installed veil renders the installed default scene at 64x36, and the image equals
     the build tree's veil rendering the source tree's scene (maxabs 0);
  2. the same installed tree with one shader deleted fails naming the installed shader
     folder: the program reads the installed shaders, not the source tree's (which still has
     the file);
  3. VEIL_SHADER_DIR still overrides it (a folder without shaders is refused, naming it);
  4. the program resolves no shared library inside the build tree (ldd);
  5. with the Python module built, the installed package imports from the prefix and points
     VEIL_SHADER_DIR at its own shaders.

Usage: install_tree.py BUILD_DIR SOURCE_DIR VEIL_EXE [PYTHON_MODULE_BUILT(0|1)]
"""
import os
import shutil
import subprocess
import sys
import tempfile

build, source, build_veil = (os.path.abspath(a) for a in sys.argv[1:4])
with_python = len(sys.argv) > 4 and sys.argv[4] in ("1", "ON", "TRUE")
failures = []


def check(ok, what, detail=""):
    print(("ok   " if ok else "FAIL ") + what + ("" if ok else f": {detail}"))
    if not ok:
        failures.append(what)


work = tempfile.mkdtemp(prefix="veil-install-test.")
try:
    env = {k: v for k, v in os.environ.items() if k not in ("VEIL_SHADER_DIR", "PYTHONPATH")}
    first = os.path.join(work, "first")
    components = [] if with_python else ["--component", "veil"]
    p = subprocess.run(["cmake", "--install", build, "--prefix", first, *components],
                       capture_output=True, text=True, env=env, timeout=120)
    check(p.returncode == 0, "cmake --install into a temporary prefix", p.stderr[-2000:])
    if p.returncode:
        sys.exit(1)
    # Moved: the tree must not depend on the prefix it was installed into.
    prefix = os.path.join(work, "moved")
    os.rename(first, prefix)
    veil = os.path.join(prefix, "bin", "veil")
    shaders = os.path.join(prefix, "share", "veil", "shaders")
    scene = os.path.join(prefix, "share", "veil", "datasets", "scenes", "default.json")
    for path in (veil, os.path.join(shaders, "frame", "opaque.frag"), scene):
        check(os.path.exists(path), f"installed {os.path.relpath(path, prefix)}")
    cwd = os.path.join(work, "cwd")
    os.makedirs(cwd)

    def render(exe, scene_file, out, extra_env=None):
        e = dict(env, **(extra_env or {}))
        return subprocess.run([exe, "render", scene_file, "--width", "64", "--height", "36",
                               "-o", out], cwd=cwd, env=e, capture_output=True, text=True,
                              timeout=120)

    # 1. The installed program renders; the image is the build tree's.
    r = render(veil, scene, os.path.join(cwd, "installed.exr"))
    check(r.returncode == 0, "the installed veil renders the installed default scene", r.stderr)
    r = render(build_veil, os.path.join(source, "datasets", "scenes", "default.json"),
               os.path.join(cwd, "build.exr"))
    check(r.returncode == 0, "the build tree's veil renders the default scene", r.stderr)
    c = subprocess.run([veil, "compare", "installed.exr", "build.exr", "--metric", "maxabs",
                        "--fail", "0"], cwd=cwd, env=env, capture_output=True, text=True,
                       timeout=60)
    check(c.returncode == 0, "installed and build-tree images are equal (maxabs 0)",
          c.stdout + c.stderr)

    # 2. A copy of the installed tree without one shader fails naming its own shader folder.
    broken = os.path.join(work, "broken")
    for part in ("bin", os.path.join("share", "veil", "shaders")):
        shutil.copytree(os.path.join(prefix, part), os.path.join(broken, part), symlinks=True)
    os.remove(os.path.join(broken, "share", "veil", "shaders", "frame", "opaque.frag"))
    r = render(os.path.join(broken, "bin", "veil"), scene, os.path.join(cwd, "broken.exr"))
    lines = r.stderr.strip().splitlines()
    check(r.returncode == 1 and any(os.path.join(broken, "share", "veil", "shaders") in l
                                    and "opaque.frag" in l for l in lines)
          and not os.path.exists(os.path.join(cwd, "broken.exr")),
          "an installed tree missing frame/opaque.frag fails naming its own shader folder "
          "(the source tree's shaders are not used)", r.stderr)

    # 3. VEIL_SHADER_DIR overrides the installed folder.
    empty = os.path.join(work, "no-shaders")
    os.makedirs(empty)
    r = render(veil, scene, os.path.join(cwd, "env.exr"), {"VEIL_SHADER_DIR": empty})
    check(r.returncode == 1 and empty in r.stderr,
          "VEIL_SHADER_DIR pointing at a folder without shaders is refused naming it", r.stderr)

    # 4. No shared library from the build tree.
    l = subprocess.run(["ldd", veil], capture_output=True, text=True, timeout=60)
    check(l.returncode == 0 and build not in l.stdout and "not found" not in l.stdout,
          "ldd: every library found, none inside the build tree", l.stdout)

    # 5. The Python package.
    if with_python:
        site = [os.path.join(root) for root, dirs, files in os.walk(prefix)
                if os.path.basename(root) == "veil" and "__init__.py" in files]
        check(len(site) == 1, "one installed Python package veil", str(site))
        if site:
            code = ("import os, veil; print(veil.__file__); print(os.environ['VEIL_SHADER_DIR'])")
            py = subprocess.run([sys.executable, "-c", code], cwd=cwd, capture_output=True,
                                text=True, timeout=60,
                                env=dict(env, PYTHONPATH=os.path.dirname(site[0])))
            out = py.stdout.split()
            check(py.returncode == 0 and len(out) == 2 and out[0].startswith(prefix)
                  and out[1].startswith(prefix) and os.path.isfile(
                      os.path.join(out[1], "frame", "opaque.frag")),
                  "the installed package imports from the prefix with its own shaders",
                  py.stdout + py.stderr)
finally:
    shutil.rmtree(work, ignore_errors=True)

if failures:
    print(f"{len(failures)} check(s) failed", file=sys.stderr)
    sys.exit(1)
print("all checks passed")
