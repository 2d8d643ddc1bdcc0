"""Image assertions and regression suites for pytest (docs/python.md, "Testing").

    from veil.testing import assert_image_close
    def test_glass(renderer):                  # fixture of veil.pytest_plugin
        frame = renderer.render("my_scene.json", width=160, height=120)
        assert_image_close(frame, "refs/glass.exr", metric="p99", tol=0.02)

On failure the render, the reference and a heat map of |render - reference| are written
beside the failing test (its folder's veil-failures/, or $VEIL_TEST_OUTPUT) and named in the
assertion message. A missing reference file is an error unless VEIL_UPDATE_REFERENCES=1,
which writes the render as the reference (an .exr: a PNG cannot hold linear radiance), making
its folder when that folder lies inside the test's folder.
"""

import inspect
import os
import re

import numpy as np

from . import _veil

# Metrics whose value must be at least the tolerance (the others at most).
_HIGHER_IS_BETTER = {"psnr", "ssim"}


def _as_image(value, what):
    __tracebackhide__ = True
    if hasattr(value, "rgb") and hasattr(value, "report"):  # a veil.Frame
        return np.ascontiguousarray(value.rgb)
    if isinstance(value, (str, os.PathLike)):
        return _veil.read_image(value)
    array = np.asarray(value, dtype=np.float32)
    if array.ndim != 3 or array.shape[2] not in (3, 4):
        raise _veil.ValueError(f"{what}: expected an H x W x 3 or 4 image, got shape "
                               f"{array.shape}")
    return array


def _test_name_and_folder():
    """The running test's name (from pytest) and the folder of its file (the caller's)."""
    current = os.environ.get("PYTEST_CURRENT_TEST", "")
    name = current.split("::")[-1].split(" ")[0] if current else ""
    folder = None
    for frame in inspect.stack()[2:]:
        if os.path.basename(frame.filename).startswith("test") or frame.function.startswith("test"):
            folder = os.path.dirname(os.path.abspath(frame.filename))
            name = name or frame.function
            break
    if folder is None:
        folder = os.getcwd()
    return re.sub(r"[^A-Za-z0-9._-]+", "_", name or "image"), folder


def failure_folder():
    """Where assert_image_close writes a failure's images: $VEIL_TEST_OUTPUT, else
    veil-failures/ beside the running test's file."""
    override = os.environ.get("VEIL_TEST_OUTPUT")
    if override:
        return override
    return os.path.join(_test_name_and_folder()[1], "veil-failures")


def assert_image_close(image, reference, metric: str = "p99", tol: float = 1e-3,
                       name: "str | None" = None, exposure: float = 1.0) -> None:
    """Assert that `image` is within `tol` of `reference` by `metric` (veil.compare's names:
    rmse, maxabs, relmse, p99, psnr, ssim, nrmse; psnr and ssim are lower bounds).

    image: a veil.Frame (its rgb), an H x W x 3|4 array or an image file; reference: an image
    file (EXR for radiance) or an array. On failure writes NAME.render.exr, NAME.reference.exr,
    NAME.heat.png (white = the largest error) and NAME.render.png into failure_folder() and
    raises AssertionError naming them and the value. NAME defaults to the test's name.
    """
    __tracebackhide__ = True  # pytest shows the caller's line, not this helper's
    test_name, folder = _test_name_and_folder()
    name = re.sub(r"[^A-Za-z0-9._-]+", "_", name or test_name)
    img = _as_image(image, "image")
    if isinstance(reference, (str, os.PathLike)) and not os.path.exists(reference):
        if _updating():
            _write_reference(os.fspath(reference), img, folder)
            return
        raise AssertionError(f"reference '{os.fspath(reference)}' does not exist (run with "
                             f"VEIL_UPDATE_REFERENCES=1 to write the render as the reference)")
    ref = _as_image(reference, "reference")
    if img.shape[:2] != ref.shape[:2]:
        raise AssertionError(f"image is {img.shape[1]}x{img.shape[0]} but reference is "
                             f"{ref.shape[1]}x{ref.shape[0]}")
    value = _veil.compare(img, ref, metric=metric, exposure=exposure)
    ok = value >= tol if metric in _HIGHER_IS_BETTER else value <= tol
    if ok:
        return
    out = os.environ.get("VEIL_TEST_OUTPUT") or os.path.join(folder, "veil-failures")
    os.makedirs(out, exist_ok=True)
    base = os.path.join(out, name)
    _veil.write_image(base + ".render.exr", img[..., :3])
    _veil.write_image(base + ".reference.exr", ref[..., :3])
    _veil.write_image(base + ".heat.png", _veil.heat_map(img, ref))
    _veil.write_image(base + ".render.png", _veil.tonemap(img, exposure))
    relation = "<" if metric in _HIGHER_IS_BETTER else ">"
    raise AssertionError(f"{name}: {metric} {value:.6g} {relation} tolerance {tol:g}; wrote "
                         f"{base}.render.exr, .reference.exr, .heat.png, .render.png")


def _updating():
    return os.environ.get("VEIL_UPDATE_REFERENCES") == "1"


def _write_reference(path, img, test_folder):
    """VEIL_UPDATE_REFERENCES=1: the render as the reference `path`. Only an .exr holds the
    linear float values the comparison reads back; a missing folder is made when it lies
    inside the test's folder (never elsewhere)."""
    __tracebackhide__ = True
    if os.path.splitext(path)[1].lower() != ".exr":
        raise _veil.ValueError(
            f"reference '{path}': VEIL_UPDATE_REFERENCES writes linear radiance, which only "
            f"an .exr reference holds (a PNG stores 8-bit display values and would never "
            f"match the render again); name the reference .exr")
    parent = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(parent):
        inside = os.path.realpath(test_folder)
        target = os.path.realpath(parent)
        if os.path.commonpath([inside, target]) != inside:
            raise _veil.FileNotFoundError(
                f"reference '{path}': folder '{parent}' does not exist and is outside the "
                f"test's folder '{test_folder}' (VEIL_UPDATE_REFERENCES makes folders only "
                f"inside it; create it first)")
        os.makedirs(parent, exist_ok=True)
    _veil.write_image(path, img)


def regress_cases(suite_path):
    """The cases of a `veil regress` suite as pytest parameters:

        @pytest.mark.parametrize("case", regress_cases("tests/my-suite.json"))
        def test_suite(case, renderer, tmp_path):
            run_regress_case(case, renderer, tmp_path)
    """
    import pytest

    suite = _veil.Suite(suite_path, update=_updating())
    return [pytest.param((suite, name), id=name) for name in suite.names]


def run_regress_case(case, renderer, output):
    """Runs one parameter of regress_cases() and fails with its metrics when it does not pass.
    Returns the case's result dict (the `veil regress` report's entry). With
    VEIL_UPDATE_REFERENCES=1 a case with a stored (.exr) reference writes its render as the
    new reference, as `veil regress --update` does."""
    __tracebackhide__ = True
    suite, name = case
    result = suite.run(name, renderer, os.fspath(output), update=_updating())
    if not result.get("passed"):
        if result.get("error"):
            raise AssertionError(f"{name}: {result['error']}")
        failed = [f"{m['name']} {m['value']} (threshold {m['threshold']})"
                  for m in result.get("metrics", []) if not m.get("passed")]
        raise AssertionError(f"{name}: " + ", ".join(failed) +
                             f"; images in {os.fspath(output)}")
    return result
