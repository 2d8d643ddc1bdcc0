"""Shared set-up of the Python module's tests (ctest label `python`, tests/CMakeLists.txt):
the checkout's root, the veil command of the same build, one Renderer per test file."""

import os
import pathlib
import subprocess

import pytest

import veil

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def veil_exe():
    exe = os.environ.get("VEIL_EXE") or str(ROOT / "build" / "release" / "src" / "veil")
    if not os.path.exists(exe):
        pytest.skip(f"the veil command is not built ({exe})")
    return exe


@pytest.fixture(scope="module")
def renderer():
    return veil.Renderer()


def cli_error(exe, *args):
    """The one-line message `veil ARGS` prints (without "veil: error: ") and its exit status."""
    run = subprocess.run([exe, *map(str, args)], capture_output=True, text=True, timeout=120)
    lines = [l for l in run.stderr.splitlines() if l.startswith("veil: error: ")]
    assert run.returncode != 0 and len(lines) == 1, (run.returncode, run.stderr)
    return lines[0][len("veil: error: "):], run.returncode
