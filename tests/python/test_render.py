"""veil with a GL context: Renderer, techniques, voxelize, regression suites, veil.testing."""

import json
import os
import subprocess
import threading
import time

import numpy as np
import pytest

import veil
from conftest import ROOT, cli_error
from veil.testing import (assert_image_close, failure_folder, regress_cases,
                          run_regress_case)

DEFAULT = ROOT / "datasets" / "scenes" / "default.json"
SMOKE_GLASS = ROOT / "datasets" / "scenes" / "oit-smoke-glass.json"
TEAPOT = ROOT / "datasets" / "third_party" / "utah-teapot" / "teapot.obj"
SUITE = ROOT / "tests" / "regression" / "suite.json"


def test_default_scene_equals_veil_render_bit_for_bit(renderer, veil_exe, tmp_path):
    # 96 x 64 keeps CI cheap: default.json at its 480 x 270 takes about 9 s on llvmpipe.
    exr = tmp_path / "cli.exr"
    subprocess.run([veil_exe, "render", str(DEFAULT), "-o", str(exr), "--width", "96",
                    "--height", "64"], check=True, capture_output=True)
    cli = veil.read_image(exr)  # R, G, B, A, Z
    frame = renderer.render(DEFAULT, width=96, height=64)
    assert frame.rgb.shape == (64, 96, 3) and frame.rgb.dtype == np.float32
    assert np.array_equal(frame.rgb, cli[..., :3])
    # Z where a surface is hit; where none is, the frame holds +inf and the EXR its background
    # depth (the far plane or +inf: either lies beyond every hit).
    hit = np.isfinite(frame.depth)
    assert np.array_equal(frame.depth[hit], cli[..., 4][hit])
    assert np.all(cli[..., 4][~hit] >= frame.depth[hit].max())
    assert np.all(frame.alpha == 1.0) and np.array_equal(cli[..., 3], frame.alpha)
    assert np.isinf(frame.depth).any() and np.isfinite(frame.depth).any()
    # The frame's arrays share one read-back buffer: rgb and alpha are views of rgba.
    assert frame.rgb.base is not None and np.shares_memory(frame.rgb, frame.rgba)
    r = frame.report
    assert (r["width"], r["height"], r["oit"]) == (96, 64, "reference")
    assert r["scene_values"]["render"]["width"] == 96
    names = [p["name"] for p in r["passes"]]
    assert "opaque" in names and "tonemap" in names and "fog" in names
    assert r["total_ms"] == pytest.approx(sum(p["ms"] for p in r["passes"]))
    assert r["renderer"] == renderer.gl_renderer and r["seconds"] > 0


def test_render_releases_the_gil(renderer):
    scene = veil.Scene.load(SMOKE_GLASS)
    renderer.render(scene, width=64, height=48)  # programs compiled, caches warm
    stamps = []
    stop = threading.Event()

    def spin():
        i = 0
        while not stop.is_set():
            i += 1
            if i % 200 == 0:
                stamps.append(time.perf_counter())

    thread = threading.Thread(target=spin)
    thread.start()
    try:
        time.sleep(0.02)
        t0 = time.perf_counter()
        renderer.render(scene, width=64, height=48)
        t1 = time.perf_counter()
    finally:
        stop.set()
        thread.join()
    # Holding the GIL, the spinning thread could run only before render() enters C++ and
    # after it returns, never in the middle third of the call.
    lo, hi = t0 + (t1 - t0) / 3, t0 + 2 * (t1 - t0) / 3
    inside = sum(1 for t in stamps if lo < t < hi)
    assert t1 - t0 > 0.03 and inside >= 5, (inside, t1 - t0)


def test_render_options(renderer):
    scene = veil.Scene.load(SMOKE_GLASS)
    scene.set("render.oit.type", "moment-p6")
    a = renderer.render(scene, width=40, height=24)
    assert a.report["oit"] == "moment-p6" and a.rgb.shape == (24, 40, 3)
    b = renderer.render(scene, width=40, height=24, oit="blend", shadows="opaque")
    assert b.report["oit"] == "blend" and b.report["shadows"] == "opaque"
    assert not np.array_equal(a.rgb, b.rgb)
    assert a.ldr.shape == (24, 40, 4) and 0.0 <= a.ldr.min() and a.ldr.max() <= 1.0
    # A dict and a path render the same frame as the Scene.
    doc = scene.to_dict()
    c = renderer.render(veil.Scene(doc, base_dir=SMOKE_GLASS.parent), width=40, height=24)
    assert np.array_equal(a.rgb, c.rgb)
    d = renderer.render(str(SMOKE_GLASS), width=40, height=24, oit="moment-p6")
    assert np.array_equal(a.rgb, d.rgb)
    fog = renderer.render(DEFAULT, width=32, height=18, aovs=["fog"])
    assert fog.aovs["fog"].shape == (18, 32, 3) and fog.aovs["fog.transmittance"].shape == (18, 32)
    t = fog.aovs["fog.transmittance"]
    assert t.min() >= 0.0 and t.max() <= 1.0 and t.min() < 1.0 and fog.aovs["fog"].max() > 0
    vdb = renderer.render(ROOT / "datasets" / "third_party" / "vdb-torus-fog" / "torus01.vdb",
                          width=24, height=24)
    assert vdb.rgb.max() > 0


def test_render_into_a_callers_array(renderer):
    scene = veil.Scene.load(SMOKE_GLASS)
    plain = renderer.render(scene, width=40, height=24)
    stack = np.full((2, 24, 40, 4), np.nan, dtype=np.float32)
    into = renderer.render(scene, width=40, height=24, out=stack[1])
    # The read-back went into the caller's memory, and equals the frame rendered without it.
    assert np.shares_memory(into.rgba, stack[1]) and into.rgb.base is not None
    assert np.array_equal(stack[1], plain.rgba)
    assert np.isnan(stack[0]).all()
    # The scene's own size when width/height are not given.
    small = scene.copy()
    small.set("render.width", 32)
    small.set("render.height", 16)
    full = np.empty((16, 32, 4), dtype=np.float32)
    assert np.shares_memory(renderer.render(small, out=full).rgba, full)
    bad = [(np.empty((24, 40, 3), np.float32), "shape (24, 40, 3), expected (24, 40, 4)"),
           (np.empty((40, 24, 4), np.float32), "expected (24, 40, 4)"),
           (np.empty((24, 40, 4), np.float64), "dtype float64, expected float32"),
           (np.empty((24, 80, 4), np.float32)[:, ::2], "not C-contiguous"),
           ([[0.0]], "expected a numpy array, got list")]
    readonly = np.empty((24, 40, 4), np.float32)
    readonly.flags.writeable = False
    bad.append((readonly, "read-only"))
    for array, message in bad:
        with pytest.raises(veil.Error, match=message.replace("(", r"\(").replace(")", r"\)")):
            renderer.render(scene, width=40, height=24, out=array)
    assert np.array_equal(renderer.render(scene, width=40, height=24).rgba, plain.rgba)


def test_render_errors(renderer, veil_exe, tmp_path):
    scene = veil.Scene.load(SMOKE_GLASS)
    with pytest.raises(veil.Error, match="unknown OIT technique 'bogus'"):
        renderer.render(scene, oit="bogus")
    with pytest.raises(veil.Error, match="bogus"):
        renderer.render(scene, shadows="bogus")
    with pytest.raises(veil.Error, match=r"not in range \[1, 16384\]"):
        renderer.render(scene, width=-2)
    with pytest.raises(veil.ValueError, match=r"aovs=\['depth'\]: unknown AOV 'depth'"):
        renderer.render(scene, aovs=["depth"])
    with pytest.raises(veil.Error):
        renderer.render(scene, width=16, height=16, aovs="fog")  # the scene has no fog
    with pytest.raises(veil.Error, match="nope"):
        renderer.render(scene, width=16, height=16, camera="nope")
    with pytest.raises(veil.TypeError, match="expected a veil.Scene, a path"):
        renderer.render(42)
    # A bad technique property: the command line's message.
    message, _ = cli_error(veil_exe, "render", SMOKE_GLASS, "-o", tmp_path / "x.png", "--set",
                           "render.oit.bogus=1")
    with pytest.raises(veil.Error) as e:
        scene.set("render.oit.bogus", 1)
    assert str(e.value) == message
    # A scene document that names an unknown technique fails when it is made.
    doc = veil.Scene.load(SMOKE_GLASS).to_dict()
    doc["render"]["oit"] = "bogus"
    with pytest.raises(veil.Error, match="unknown OIT technique 'bogus'"):
        veil.Scene(doc)
    # The renderer still works after each error.
    assert renderer.render(SMOKE_GLASS, width=16, height=16).rgb.shape == (16, 16, 3)


def test_techniques_equal_the_command(renderer, veil_exe):
    cli = json.loads(subprocess.run([veil_exe, "techniques", "--json"], capture_output=True,
                                    text=True, check=True).stdout)
    assert veil.techniques(renderer) == cli
    listed = veil.techniques()
    assert listed == cli
    reference = next(t for t in listed if t["name"] == "reference" and t["kind"] == "oit")
    assert reference["available"] == "yes"
    kinds = {t["kind"] for t in listed}
    assert kinds == {"oit", "shadows", "integrator"}


def test_voxelize_sphere_against_point_in_sphere(renderer, tmp_path):
    r = 0.7
    doc = {"cameras": [{"name": "c", "position": [0, 0, 4]}],
           "materials": {"m": {"base_color": [1, 1, 1]}},
           "objects": [{"shape": {"type": "sphere", "radius": r, "segments": 96, "rings": 48},
                        "material": "m"}]}
    res = 32
    out = tmp_path / "sphere.vdb"
    mask = veil.voxelize(veil.Scene(doc), res=res, solid=True, output=out, renderer=renderer)
    assert mask.dtype == np.bool_ and mask.shape == (res, res, res)
    # The grid: the bounds [-r, r]^3 with a 3% margin per side; cell centres inside the exact
    # sphere must be set and outside clear, except within the polygon's deviation from the
    # sphere (r (1 - cos(pi / 48)) = 0.0015) plus the bounds' of it, 0.01 in all.
    h = r * 1.06
    c = -h + (np.arange(res) + 0.5) * (2 * h / res)
    z, y, x = np.meshgrid(c, c, c, indexing="ij")
    dist = np.sqrt(x * x + y * y + z * z)
    wrong = mask != (dist < r)
    assert np.all(np.abs(dist[wrong] - r) < 0.01), np.abs(dist[wrong] - r).max()
    assert wrong.sum() < 0.01 * mask.sum()
    info = veil.vdb_info(out)
    assert {g["name"] for g in info} == {"density", "mask"}
    assert next(g for g in info if g["name"] == "mask")["active_voxels"] == mask.sum()
    teapot = veil.voxelize(TEAPOT, res=16)
    assert teapot.shape[1:] == (teapot.shape[1], 16) and teapot.any()


def test_voxelize_errors(tmp_path):
    with pytest.raises(veil.Error, match="bogus"):
        veil.voxelize(SMOKE_GLASS, method="bogus")
    with pytest.raises(veil.Error, match="res 0"):
        veil.voxelize(SMOKE_GLASS, res=0)
    with pytest.raises(veil.Error, match="must end in .vdb"):
        veil.voxelize(SMOKE_GLASS, output=tmp_path / "x.vti")
    with pytest.raises(veil.Error, match="perspective needs a scene"):
        veil.voxelize(TEAPOT, perspective=True)
    with pytest.raises(veil.Error, match="no such file"):
        veil.voxelize(tmp_path / "none.obj")
    with pytest.raises(veil.Error, match="expected a veil.Renderer"):
        veil.voxelize(TEAPOT, res=4, renderer="no")
    assert not list(tmp_path.iterdir())


CASES = [c for c in regress_cases(SUITE) if c.id in ("golden-blend", "glass-moment-p6")]


@pytest.mark.parametrize("case", CASES)
def test_regress_suite_cases(case, renderer, tmp_path):
    result = run_regress_case(case, renderer, tmp_path)
    assert result["passed"] and result["metrics"]


def test_regress_failure_names_the_metric(renderer, tmp_path):
    suite = {"name": "tight", "cases": [{
        "name": "tight", "scene": str(SMOKE_GLASS), "technique": "blend",
        "reference": "reference", "width": 32, "height": 18, "metrics": {"rmse": 1e-9}}]}
    (tmp_path / "s.json").write_text(json.dumps(suite))
    (case,) = regress_cases(tmp_path / "s.json")
    with pytest.raises(AssertionError, match=r"tight: rmse .* \(threshold 1e-09\)"):
        run_regress_case(case.values[0], renderer, tmp_path / "out")
    with pytest.raises(veil.Error, match="no case 'x'"):
        veil.Suite(tmp_path / "s.json").run("x", renderer, tmp_path)


def test_assert_image_close(renderer, tmp_path, monkeypatch):
    frame = renderer.render(SMOKE_GLASS, width=32, height=18)
    reference = tmp_path / "ref.exr"
    monkeypatch.setenv("VEIL_UPDATE_REFERENCES", "1")
    assert_image_close(frame, reference)  # missing: written
    monkeypatch.delenv("VEIL_UPDATE_REFERENCES")
    assert_image_close(frame, reference, metric="maxabs", tol=0.0)
    assert_image_close(frame.rgb, reference, metric="psnr", tol=1e9)  # identical: inf
    other = renderer.render(SMOKE_GLASS, width=32, height=18, oit="blend")
    out = tmp_path / "failures"
    monkeypatch.setenv("VEIL_TEST_OUTPUT", str(out))
    with pytest.raises(AssertionError, match=r"p99 .* > tolerance 1e-06"):
        assert_image_close(other, reference, tol=1e-6)
    name = "test_assert_image_close"
    for suffix in (".render.exr", ".reference.exr", ".heat.png", ".render.png"):
        assert (out / (name + suffix)).exists(), suffix
    assert np.array_equal(veil.read_image(out / (name + ".render.exr")), other.rgb)
    heat = veil.read_image(out / (name + ".heat.png"))
    assert heat.shape == (18, 32, 3) and heat.max() == 1.0
    with pytest.raises(AssertionError, match="does not exist"):
        assert_image_close(frame, tmp_path / "none.exr")
    with pytest.raises(AssertionError, match="is 16x16 but reference is 32x18"):
        assert_image_close(np.zeros((16, 16, 3)), reference)
    monkeypatch.delenv("VEIL_TEST_OUTPUT", raising=False)
    assert failure_folder() == os.path.join(os.path.dirname(__file__), "veil-failures")
