"""veil without a GL context: Scene, images, compare, vdb_info, export_vti, errors."""

import json
import pathlib

import numpy as np
import pytest

import veil
from conftest import ROOT, cli_error

DEFAULT = ROOT / "datasets" / "scenes" / "default.json"
SMOKE_GLASS = ROOT / "datasets" / "scenes" / "oit-smoke-glass.json"
TORUS = ROOT / "datasets" / "third_party" / "vdb-torus-fog" / "torus01.vdb"


def test_version():
    assert veil.__version__.count(".") == 2
    assert issubclass(veil.Error, Exception)


def test_docstrings():
    for name in veil.__all__:
        assert getattr(veil, name).__doc__, name
    assert "moment-p6" in veil.Scene.set.__doc__


def test_scene_load_set_to_dict():
    scene = veil.Scene.load(SMOKE_GLASS)
    assert scene.path == SMOKE_GLASS
    assert scene.cameras == ["main"] and scene.size == (320, 180)
    doc = scene.to_dict()
    assert doc["render"]["oit"] == "reference"
    assert scene.set("render.oit.type", "moment-p6") is scene
    scene.set("lights.0.intensity", 40).set("render.exposure", "2")
    doc = scene.to_dict()
    assert doc["render"]["oit"] == {"type": "moment-p6"}
    assert doc["lights"][0]["intensity"] == 40 and doc["render"]["exposure"] == 2
    # The overrides of Scene.load are `--set`'s.
    loaded = veil.Scene.load(SMOKE_GLASS, overrides=["render.width=64"])
    assert loaded.size == (64, 180)
    copy = loaded.copy()
    copy.set("render.width", 32)
    assert loaded.size == (64, 180) and copy.size == (32, 180)


def test_scene_from_dict_round_trip():
    doc = veil.Scene.load(SMOKE_GLASS).to_dict()
    scene = veil.Scene(doc, base_dir=SMOKE_GLASS.parent)
    assert scene.path is None and scene.to_dict() == doc
    assert "oit reference" in repr(scene)
    # NumPy values are JSON too.
    doc["render"]["exposure"] = np.float32(1.5)
    assert veil.Scene(doc).to_dict()["render"]["exposure"] == 1.5


def test_scene_errors_are_the_command_lines(veil_exe, tmp_path):
    # The same override through `veil render --set` and Scene.set: the same line.
    for key, value in [("render.bogus", "1"), ("render.width", "-3"), ("lights.9.intensity", "2"),
                       ("render.oit.type", "[1")]:
        message, status = cli_error(veil_exe, "render", DEFAULT, "-o", tmp_path / "x.png",
                                    "--set", f"{key}={value}")
        assert status == 1
        scene = veil.Scene.load(str(DEFAULT))
        before = scene.to_dict()
        with pytest.raises(veil.Error) as e:
            scene.set(key, value)
        assert str(e.value) == message
        assert scene.to_dict() == before  # unchanged
    with pytest.raises(veil.Error, match="cannot open scene file"):
        veil.Scene.load(tmp_path / "missing.json")
    with pytest.raises(veil.Error, match="not a regular file"):
        veil.Scene.load("/dev/zero")
    (tmp_path / "bad.json").write_text("{\"render\": ")
    with pytest.raises(veil.Error, match="bad.json"):
        veil.Scene.load(tmp_path / "bad.json")
    with pytest.raises(veil.Error, match="/cameras"):
        veil.Scene({"cameras": 3})
    with pytest.raises(veil.Error, match="not JSON"):
        veil.Scene({"render": {"width": object()}})
    with pytest.raises(veil.Error, match="not a finite number"):
        veil.Scene({"render": {"exposure": float("nan")}})
    with pytest.raises(veil.Error, match="expected key=value"):
        veil.Scene.load(DEFAULT, overrides=["render.width"])
    with pytest.raises(veil.Error, match="a key has no '='"):
        veil.Scene.load(DEFAULT).set("a=b", 1)


def test_images_round_trip(tmp_path):
    rng = np.random.default_rng(1)
    img = rng.random((12, 20, 3), dtype=np.float32) * 4.0
    veil.write_image(tmp_path / "a.exr", img)
    back = veil.read_image(tmp_path / "a.exr")
    assert back.dtype == np.float32 and back.shape == (12, 20, 3)
    assert np.array_equal(back, img)  # float32 EXR: exact
    veil.write_image(tmp_path / "h.exr", img, half=True)
    assert np.allclose(veil.read_image(tmp_path / "h.exr"), img, rtol=2.0**-11, atol=0)
    ldr = np.clip(img / 4.0, 0, 1)
    veil.write_image(tmp_path / "a.png", ldr)
    png = veil.read_image(tmp_path / "a.png")
    assert np.max(np.abs(png - ldr)) <= 0.5 / 255 + 1e-6  # 8-bit rounding
    gray = rng.random((5, 6), dtype=np.float32)
    veil.write_image(str(tmp_path / "g.exr"), gray)
    assert np.array_equal(veil.read_image(tmp_path / "g.exr"), gray)


def test_image_errors(tmp_path):
    with pytest.raises(veil.Error, match="does not exist"):
        veil.read_image(tmp_path / "none.exr")
    with pytest.raises(veil.Error, match="must end in .png or .exr"):
        veil.write_image(tmp_path / "a.tif", np.zeros((2, 2, 3)))
    with pytest.raises(veil.Error, match="expected an image array"):
        veil.write_image(tmp_path / "a.exr", np.zeros((2, 2, 7)))
    with pytest.raises(veil.Error, match="expected an image array"):
        veil.write_image(tmp_path / "a.exr", "not an image")
    with pytest.raises(veil.Error, match="folder"):
        veil.write_image(tmp_path / "no" / "a.exr", np.zeros((2, 2, 3)))
    with pytest.raises(veil.Error, match="expected a path"):
        veil.read_image(3)
    assert not list(tmp_path.iterdir())


def test_compare_metrics_against_numpy(tmp_path):
    rng = np.random.default_rng(2)
    a = rng.random((16, 24, 3), dtype=np.float32)
    b = a + rng.normal(0, 0.05, a.shape).astype(np.float32)
    d = (a.astype(np.float64) - b)
    assert veil.compare(a, b) == pytest.approx(np.sqrt(np.mean(d * d)), rel=1e-12)
    assert veil.compare(a, b, metric="maxabs") == pytest.approx(np.max(np.abs(d)), rel=1e-6)
    errors = np.sort(np.abs(d).ravel())
    p99 = errors[int(np.ceil(0.99 * errors.size)) - 1]
    assert veil.compare(a, b, metric="p99") == pytest.approx(p99, rel=1e-6)
    psnr = 10 * np.log10(np.max(b) ** 2 / np.mean(d * d))
    values = veil.compare(a, b, metric=["psnr", "ssim", "relmse"])
    assert values["psnr"] == pytest.approx(psnr, rel=1e-9)
    assert 0.0 < values["ssim"] < 1.0
    assert veil.compare(a, a, metric="ssim") == pytest.approx(1.0)
    # Files and arrays give the same numbers; RGBA compares RGB only.
    veil.write_image(tmp_path / "a.exr", a)
    veil.write_image(tmp_path / "b.exr", b)
    assert veil.compare(tmp_path / "a.exr", str(tmp_path / "b.exr")) == veil.compare(a, b)
    rgba = np.dstack([a, np.zeros(a.shape[:2], np.float32)])
    assert veil.compare(rgba, b) == veil.compare(a, b)
    heat = veil.heat_map(a, b)
    assert heat.shape == (16, 24, 3) and heat.max() <= 1.0
    assert np.allclose(veil.heat_map(a, a), 0.0)
    toned = veil.tonemap(np.full((2, 2, 3), 0.5, np.float32))
    assert toned[0, 0, 0] == pytest.approx(1.055 * 0.5 ** (1 / 2.4) - 0.055, abs=1e-6)


def test_compare_errors(tmp_path):
    a = np.zeros((4, 4, 3), np.float32)
    with pytest.raises(veil.Error, match="unknown metric 'bogus'"):
        veil.compare(a, a, metric="bogus")
    with pytest.raises(veil.Error, match="cannot compare"):
        veil.compare(a, np.zeros((4, 5, 3)))
    with pytest.raises(veil.Error, match="RGB or RGBA needed"):
        veil.compare(np.zeros((4, 4)), a)
    with pytest.raises(veil.Error, match="does not exist"):
        veil.compare(tmp_path / "x.exr", a)
    with pytest.raises(veil.Error, match="use clamp or aces"):
        veil.compare(a, a, metric="ssim", tonemap="reinhard")
    with pytest.raises(veil.Error, match="exposure"):
        veil.tonemap(a, exposure=-1)


def test_vdb_info_matches_the_command(veil_exe):
    import subprocess
    grids = veil.vdb_info(TORUS)
    assert len(grids) >= 1
    g = grids[0]
    text = subprocess.run([veil_exe, "info", str(TORUS)], capture_output=True, text=True,
                          check=True).stdout
    assert f"{g['active_voxels']} active voxels" in text and f"'{g['name']}'" in text
    assert g["type"] == "float" and g["max"] >= g["min"] and g["gpu_bytes"] > 0
    assert all(lo <= hi for lo, hi in zip(g["index_min"], g["index_max"]))
    assert veil.vdb_info(TORUS, grid=0)[0]["name"] == g["name"]
    assert veil.vdb_info(TORUS, grid=g["name"])[0]["index"] == 0


def test_vdb_errors(tmp_path):
    with pytest.raises(veil.Error, match="missing.vdb"):
        veil.vdb_info(tmp_path / "missing.vdb")
    damaged = tmp_path / "damaged.vdb"
    data = bytearray(TORUS.read_bytes())
    data[200:264] = bytes(64)
    damaged.write_bytes(bytes(data[: len(data) // 2]))
    with pytest.raises(veil.Error, match="damaged.vdb"):
        veil.vdb_info(damaged)
    with pytest.raises(veil.Error, match="no grid"):
        veil.vdb_info(TORUS, grid="nope")
    with pytest.raises(veil.Error, match="not a regular file"):
        veil.vdb_info("/dev/zero")


def test_export_vti(tmp_path):
    out = tmp_path / "t.vti"
    info = veil.export_vti(TORUS, out)
    g = veil.vdb_info(TORUS)[0]
    assert out.exists()
    assert info["dims"] == [hi - lo + 1 for lo, hi in zip(g["index_min"], g["index_max"])]
    assert info["box_min"] == g["index_min"] and info["components"] == 1
    half = veil.export_vti(TORUS, tmp_path / "h.vti", box=[0, 0, 0, 3, 3, 3], resample=0.5)
    assert half["dims"] == [2, 2, 2]
    with pytest.raises(veil.Error, match="must end in .vti"):
        veil.export_vti(TORUS, tmp_path / "t.png")
    with pytest.raises(veil.Error, match="must be an OpenVDB file"):
        veil.export_vti(DEFAULT, tmp_path / "d.vti")
    with pytest.raises(veil.Error, match="every minimum must be at most its maximum"):
        veil.export_vti(TORUS, tmp_path / "b.vti", box=[3, 0, 0, 0, 3, 3])
    with pytest.raises(veil.Error, match="a box is 6 numbers"):
        veil.export_vti(TORUS, tmp_path / "b.vti", box=[1, 2])
    with pytest.raises(veil.Error, match="resample"):
        veil.export_vti(TORUS, tmp_path / "b.vti", resample=0)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["h.vti", "t.vti"]


def test_suite_errors(tmp_path):
    with pytest.raises(veil.Error, match="missing.json"):
        veil.Suite(tmp_path / "missing.json")
    (tmp_path / "s.json").write_text(json.dumps({"name": "s", "cases": [{"name": "x"}]}))
    with pytest.raises(veil.Error, match="s.json"):
        veil.Suite(tmp_path / "s.json")
