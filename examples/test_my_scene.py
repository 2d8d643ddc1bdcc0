"""A pytest file to copy into your own project: render your scene and check it against a
stored reference, and run a `veil regress` suite as one pytest case per suite case.

    PYTHONPATH=build/release/python /usr/bin/python3 -m pytest examples/test_my_scene.py

The first run with VEIL_UPDATE_REFERENCES=1 writes the references; a failing check writes
the render, the reference and a heat map into veil-failures/ beside this file.
"""

import pathlib

import pytest

import veil
from veil.testing import assert_image_close, regress_cases, run_regress_case

pytest_plugins = ["veil.pytest_plugin"]  # the `renderer` fixture: one GL context per session

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent  # this checkout; point these at your own files
SCENE = ROOT / "datasets" / "scenes" / "oit-smoke-glass.json"
SUITE = ROOT / "tests" / "regression" / "suite.json"


@pytest.mark.parametrize("oit", ["moment-p6", "wboit"])
def test_technique_close_to_reference(renderer, oit):
    # An approximation against the exact composite of the same frame: 99% of the values
    # within 0.25 (these two techniques approximate the order of the smoke layers).
    scene = veil.Scene.load(SCENE)
    frame = renderer.render(scene, width=64, height=36, oit=oit)
    exact = renderer.render(scene, width=64, height=36, oit="reference")
    assert_image_close(frame, exact.rgb, metric="p99", tol=0.25)


def test_brighter_light_is_brighter(renderer):
    scene = veil.Scene.load(SCENE)
    dim = renderer.render(scene, width=48, height=27)
    scene.set("lights.0.intensity", 120)
    bright = renderer.render(scene, width=48, height=27)
    assert bright.rgb.mean() > dim.rgb.mean()


# One case of the project's own suite; regress_cases(SUITE) gives all of them.
CASES = [c for c in regress_cases(SUITE) if c.id == "golden-blend"]


@pytest.mark.parametrize("case", CASES)
def test_regression_suite(case, renderer, tmp_path):
    run_regress_case(case, renderer, tmp_path)
