"""veil.testing as a user's test file meets it: VEIL_UPDATE_REFERENCES making a missing
reference folder inside the test's folder only, refusing a .png reference for linear data,
and failures that show the test's line rather than the helper's (__tracebackhide__). Each
case runs pytest on a small test file in a temporary folder, as a user's suite would."""

import os
import subprocess
import sys
import textwrap

import veil

USER_TESTS = '''
import numpy as np
from veil.testing import assert_image_close

IMAGE = np.linspace(0.0, 4.0, 8 * 6 * 3, dtype=np.float32).reshape(8, 6, 3)  # HDR values

def test_new_folder():
    assert_image_close(IMAGE, "refs/sub/new.exr")

def test_png_reference():
    assert_image_close(IMAGE, "refs/linear.png")

def test_outside():
    assert_image_close(IMAGE, "{outside}/refs/x.exr")

def test_mismatch():
    assert_image_close(IMAGE + 1.0, "refs/sub/new.exr", metric="maxabs", tol=0.0)  # CALLER
'''


def run_pytest(folder, env_update, *tests):
    env = dict(os.environ, **env_update)
    env.pop("VEIL_TEST_OUTPUT", None)
    # The package this test imported, found from any folder.
    package = os.path.dirname(os.path.dirname(os.path.abspath(veil.__file__)))
    env["PYTHONPATH"] = os.pathsep.join([package, env.get("PYTHONPATH", "")])
    args = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--tb=short"]
    args += [f"test_user.py::{t}" for t in tests]
    return subprocess.run(args, cwd=folder, env=env, capture_output=True, text=True,
                          timeout=120)


def test_update_references(tmp_path):
    folder = tmp_path / "suite"
    folder.mkdir()
    outside = tmp_path / "elsewhere"
    (folder / "test_user.py").write_text(USER_TESTS.replace("{outside}", str(outside)))
    update = {"VEIL_UPDATE_REFERENCES": "1"}

    # A missing folder inside the test's folder is made and the reference written.
    run = run_pytest(folder, update, "test_new_folder")
    assert run.returncode == 0, run.stdout + run.stderr
    assert (folder / "refs" / "sub" / "new.exr").is_file()
    # The reference written is what the comparison reads back: it passes without updating.
    run = run_pytest(folder, {}, "test_new_folder")
    assert run.returncode == 0, run.stdout + run.stderr

    # A .png reference would hold 8-bit display values of linear data: refused, not written.
    run = run_pytest(folder, update, "test_png_reference")
    assert run.returncode == 1 and "ValueError" in run.stdout
    assert "refs/linear.png" in run.stdout and "only an .exr reference holds" in run.stdout
    assert not (folder / "refs" / "linear.png").exists()

    # A folder outside the test's folder is not made.
    run = run_pytest(folder, update, "test_outside")
    assert run.returncode == 1 and "outside the test's folder" in run.stdout, run.stdout
    assert not outside.exists()


def test_failures_show_the_callers_line(tmp_path):
    (tmp_path / "test_user.py").write_text(textwrap.dedent(USER_TESTS.replace("{outside}", "x")))
    assert run_pytest(tmp_path, {"VEIL_UPDATE_REFERENCES": "1"}, "test_new_folder").returncode == 0
    run = run_pytest(tmp_path, {}, "test_mismatch")
    assert run.returncode == 1
    out = run.stdout
    assert "# CALLER" in out and "maxabs" in out and "tolerance 0" in out, out
    # The helper's own lines (its raise) are hidden.
    assert "raise AssertionError" not in out and "testing.py" not in out, out


def test_update_references_of_a_regress_suite(tmp_path, monkeypatch):
    # A new suite whose stored reference and its folders do not exist yet:
    # VEIL_UPDATE_REFERENCES=1 reads it (the reference may be missing), makes the folders
    # and writes the render as the reference; without it the suite then passes against it.
    import json

    import pytest

    import veil
    from veil.testing import regress_cases, run_regress_case

    scene = os.path.join(os.path.dirname(__file__), "..", "..", "datasets", "scenes",
                         "oit-smoke-glass.json")
    suite = {"name": "new", "cases": [{
        "name": "golden", "scene": os.path.abspath(scene), "technique": "blend",
        "reference": "refs/new/golden.exr", "width": 24, "height": 16, "metrics": {"maxabs": 0.0}}]}
    (tmp_path / "suite.json").write_text(json.dumps(suite))
    with pytest.raises(veil.Error, match="refs/new/golden.exr"):
        regress_cases(tmp_path / "suite.json")
    monkeypatch.setenv("VEIL_UPDATE_REFERENCES", "1")
    renderer = veil.Renderer()
    (case,) = regress_cases(tmp_path / "suite.json")
    run_regress_case(case.values[0], renderer, tmp_path / "out1")
    assert (tmp_path / "refs" / "new" / "golden.exr").is_file()  # the folders made
    monkeypatch.delenv("VEIL_UPDATE_REFERENCES")
    (case,) = regress_cases(tmp_path / "suite.json")
    result = run_regress_case(case.values[0], renderer, tmp_path / "out2")
    assert result["passed"]
