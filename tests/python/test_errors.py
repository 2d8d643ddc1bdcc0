"""The module's errors: classes that are also the standard ones, plain messages that name the
Python argument, deep values refused before they recurse, the checks of heat_map, reading
non-regular files, and what help() and repr() show."""

import builtins
import inspect
import os
import re
import subprocess
import sys
import threading

import numpy as np
import pytest

import veil
from conftest import ROOT

DEFAULT = ROOT / "datasets" / "scenes" / "default.json"
SMOKE_GLASS = ROOT / "datasets" / "scenes" / "oit-smoke-glass.json"
TORUS = ROOT / "datasets" / "third_party" / "vdb-torus-fog" / "torus01.vdb"


def nested(depth, kind):
    value = 1
    for _ in range(depth):
        value = {"a": value} if kind == "dict" else [value]
    return value


@pytest.mark.parametrize("kind", ["dict", "list"])
def test_deep_values_are_refused_not_a_crash(kind):
    # 200000 levels overflowed the C stack in the conversion (a segfault) before the cap.
    deep = nested(200_000, kind)
    doc = {"render": {"width": 16}, "extra": deep}
    with pytest.raises(veil.ValueError, match=r"^Scene\(doc\): /extra/.*nested deeper than 256 "
                                              r"levels"):
        veil.Scene(doc)
    scene = veil.Scene.load(DEFAULT)
    before = scene.to_dict()
    with pytest.raises(veil.ValueError, match=r"^Scene\.set\('render\.width', value\): /.*nested "
                                              r"deeper than 256 levels"):
        scene.set("render.width", deep)
    assert scene.to_dict() == before
    # The cap is the JSON parser's (256 levels): 255 nested values below the root pass the
    # conversion and fail only as scene content.
    with pytest.raises(veil.ValueError) as e:
        scene.set("render.width", nested(255, kind))
    assert "nested deeper" not in str(e.value)


def test_a_value_that_contains_itself_is_refused():
    loop = []
    loop.append(loop)
    with pytest.raises(veil.ValueError, match="nested deeper than 256 levels"):
        veil.Scene({"extra": loop})


def test_classes_are_also_the_standard_ones():
    pairs = [("FileNotFoundError", builtins.FileNotFoundError), ("ValueError", builtins.ValueError),
             ("KeyError", builtins.KeyError), ("KeyError", builtins.ValueError),
             ("TypeError", builtins.TypeError), ("OSError", builtins.OSError),
             ("MemoryError", builtins.MemoryError)]
    for name, standard in pairs:
        cls = getattr(veil, name)
        assert issubclass(cls, veil.Error) and issubclass(cls, standard), name
        assert cls.__module__ == "veil" and name not in veil.__all__
    assert issubclass(veil.Error, RuntimeError) and veil.Error.__module__ == "veil"
    assert veil.Scene.__module__ == "veil" and veil.Renderer.__module__ == "veil"


def test_missing_files_are_file_not_found(tmp_path):
    missing = tmp_path / "none"
    calls = [(veil.read_image, missing.with_suffix(".exr")),
             (veil.Scene.load, missing.with_suffix(".json")),
             (veil.vdb_info, missing.with_suffix(".vdb")),
             (veil.Suite, missing.with_suffix(".json")),
             (lambda p: veil.compare(p, np.zeros((2, 2, 3))), missing.with_suffix(".png"))]
    for call, path in calls:
        with pytest.raises(FileNotFoundError) as e:
            call(path)
        assert isinstance(e.value, veil.Error)
        assert str(path) in str(e.value) and e.value.filename == str(path)
        assert "\n" not in str(e.value)


def test_bad_keys_and_values():
    scene = veil.Scene.load(DEFAULT)
    with pytest.raises(KeyError) as e:
        scene.set("render.bogus", 1)
    assert isinstance(e.value, ValueError) and "/render/bogus: unknown key" in str(e.value)
    assert str(e.value).startswith(str(DEFAULT))  # the line itself, not KeyError's quoted repr
    with pytest.raises(veil.ValueError, match="render"):
        scene.set("render.width", -3)
    with pytest.raises(veil.ValueError, match="unknown metric 'bogus'"):
        veil.compare(np.zeros((2, 2, 3)), np.zeros((2, 2, 3)), metric="bogus")


@pytest.mark.parametrize("call, message", [
    (lambda: veil.compare(np.zeros((2, 2, 3)), np.zeros((2, 2, 3)), metric=5),
     r"^metric: expected a metric name \(rmse, .*\) or a list of them, got int 5$"),
    (lambda: veil.compare(np.zeros((2, 2, 3)), np.zeros((2, 2, 3)), metric=["rmse", 3]),
     r"^metric\[1\]: expected a str, got int 3$"),
    (lambda: veil.compare(np.zeros((2, 2, 3)), np.zeros((2, 2, 3)), exposure="1"),
     r"^exposure: expected a number \(int or float\), got str '1'$"),
    (lambda: veil.Scene([1, 2]), r"^Scene\(doc\): expected a dict \(a scene document\), got list$"),
    (lambda: veil.Scene.load(DEFAULT).set(3, 1), r"^Scene\.set\(key\): expected a str, got int 3$"),
    (lambda: veil.Scene.load(DEFAULT, overrides="render.width=3"),
     r"^Scene\.load\(overrides\): expected a list of str, got str"),
    (lambda: veil.write_image("x.exr", np.zeros((2, 2, 3)), half="yes"),
     r"^half: expected a bool \(True or False\), got str 'yes'$"),
    (lambda: veil.heat_map(np.zeros((2, 2, 3)), np.zeros((2, 2, 3)), scale="big"),
     r"^scale: expected a number"),
    (lambda: veil.read_image(3), r"^read_image\(path\): expected a path \(str or os.PathLike\)"),
    (lambda: veil.voxelize(DEFAULT, res=4.5), r"^res: expected an int, got float 4.5$"),
    (lambda: veil.export_vti(TORUS, "b.vti", box="0 0 0 1 1 1"),
     r"^box: expected a list of int, got str"),
])
def test_wrong_types_are_plain_type_errors(call, message):
    with pytest.raises(veil.TypeError) as e:
        call()
    text = str(e.value)
    assert isinstance(e.value, TypeError) and re.search(message, text), text
    # Never pybind11's overload dump or its casting advice, never a private name.
    for bad in ("incompatible function arguments", "Unable to cast", "_render", "_veil",
                "handle"):
        assert bad not in text, text


def test_cpp_exceptions_are_mapped():
    with pytest.raises(veil.MemoryError, match="out of memory"):
        veil._veil._raise_cpp("bad_alloc")
    with pytest.raises(MemoryError, match="out of memory"):
        veil._veil._raise_cpp("length_error")
    with pytest.raises(veil.FileNotFoundError) as e:
        veil._veil._raise_cpp("no_such_file")
    assert e.value.filename == "/nonexistent/x.exr" and "'/nonexistent/x.exr'" in str(e.value)
    with pytest.raises(veil.OSError) as e:
        veil._veil._raise_cpp("permission")
    assert not isinstance(e.value, FileNotFoundError) and "'/proc/x'" in str(e.value)


@pytest.mark.parametrize("scale", [float("nan"), float("inf"), -1.0])
def test_heat_map_scale_must_be_finite_and_not_negative(scale):
    a = np.zeros((4, 4, 3), np.float32)
    with pytest.raises(veil.ValueError, match=r"^scale=.*: expected a finite number >= 0"):
        veil.heat_map(a, a + 1, scale=scale)
    assert veil.heat_map(a, a + 1, scale=2.0).shape == (4, 4, 3)


def test_help_shows_types():
    compare = str(inspect.signature(veil.compare))
    assert "image: 'numpy.ndarray | str | os.PathLike'" in compare
    assert "metric: 'str | list[str]' = 'rmse'" in compare and "exposure: 'float' = 1.0" in compare
    for f in (veil.read_image, veil.write_image, veil.heat_map, veil.tonemap, veil.vdb_info,
              veil.export_vti, veil.voxelize):
        text = str(inspect.signature(f))
        assert "handle" not in text and "'object'" not in text.split(" -> ")[0], f
        assert f.__doc__ and f.__module__ == "veil", f
    for f in (veil.Scene.set, veil.Scene.load, veil.Scene.__init__):
        assert "handle" not in f.__doc__ and ": object" not in f.__doc__, f
    assert "value: str | int | float | bool | list | dict | None" in veil.Scene.set.__doc__
    assert "-> veil.Scene" in veil.Scene.set.__doc__ and "-> dict" in veil.Scene.to_dict.__doc__
    for f in (veil.Scene.set, veil.Scene.load, veil.Scene.copy, veil.Suite.run):
        assert "_veil" not in f.__doc__, f.__doc__
    render = inspect.signature(veil.Renderer.render)
    assert "Optional[int]" in str(render.parameters["width"].annotation)


def test_unknown_or_missing_arguments_are_plain_type_errors():
    with pytest.raises(veil.TypeError, match=r"^compare\(\): got an unexpected keyword "
                                             r"argument 'metrc'$"):
        veil.compare(np.zeros((2, 2, 3)), np.zeros((2, 2, 3)), metrc="rmse")
    with pytest.raises(veil.TypeError, match=r"^read_image\(\): missing a required argument: "
                                             r"'path'$"):
        veil.read_image()
    with pytest.raises(veil.TypeError, match=r"^tonemap\(\): too many positional arguments$"):
        veil.tonemap(np.zeros((2, 2, 3)), 1.0, "clamp", 4)


@pytest.mark.parametrize("path", ["/dev/zero", "fifo"])
def test_reading_a_non_regular_file_is_refused_promptly(path, tmp_path):
    if path == "fifo":
        path = tmp_path / "fifo.exr"
        os.mkfifo(path)
    code = ("import sys, veil\n"
            "try:\n    veil.read_image(sys.argv[1])\n"
            "except veil.Error as e:\n    print(type(e).__name__, e); sys.exit(3)\n")
    run = subprocess.run([sys.executable, "-c", code, str(path)], capture_output=True,
                         text=True, timeout=60, env=os.environ)
    assert run.returncode == 3, run
    assert "not a regular file" in run.stdout and str(path) in run.stdout


def test_frame_repr_is_short(renderer):
    frame = renderer.render(SMOKE_GLASS, width=32, height=18, oit="blend")
    text = repr(frame)
    assert text.startswith("<veil.Frame 32x18 oit=blend") and text.endswith(" ms>")
    assert len(text) < 120 and str(frame) == text
    assert "veil.Renderer" in repr(renderer)


def test_messages_name_the_python_argument(renderer):
    scene = veil.Scene.load(SMOKE_GLASS)  # no volumes, no fog
    with pytest.raises(veil.ValueError) as e:
        renderer.render(scene, width=16, height=16, aovs=["fog"])
    assert str(e.value).startswith("aovs=['fog']: the scene") and "--aov" not in str(e.value)
    with pytest.raises(veil.ValueError, match=r"^aovs=\['depth'\]: unknown AOV 'depth'"):
        renderer.render(scene, aovs=["depth"])
    with pytest.raises(veil.ValueError, match=r"^width=0 is not in range \[1, 16384\]"):
        renderer.render(scene, width=0)
    with pytest.raises(veil.ValueError, match=r"^camera='nope': the scene has no such camera "
                                              r"\(cameras: main\)"):
        renderer.render(scene, width=16, height=16, camera="nope")
    with pytest.raises(veil.TypeError, match=r"^width: expected an int or None, got str '16'"):
        renderer.render(scene, width="16")
    with pytest.raises(veil.TypeError, match=r"^scene: expected a veil.Scene, a path"):
        renderer.render(42)


def test_a_renderer_works_from_other_threads(renderer):
    made_here = veil.Renderer()
    results, errors = {}, []

    def render(key, r):
        try:
            results[key] = r.render(SMOKE_GLASS, width=24, height=16, oit="blend").rgb
        except Exception as e:  # noqa: BLE001: reported below
            errors.append(e)

    # One other thread, then two at once on the same renderer (they wait for each other),
    # then the main thread again.
    t = threading.Thread(target=render, args=("other", made_here))
    t.start()
    t.join()
    threads = [threading.Thread(target=render, args=(k, made_here)) for k in ("a", "b")]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    here = made_here.render(SMOKE_GLASS, width=24, height=16, oit="blend").rgb
    for key in ("other", "a", "b"):
        assert np.array_equal(results[key], here), key
    # The module's renderer (made on this thread) is usable after another one ran here.
    assert renderer.render(SMOKE_GLASS, width=8, height=8).rgb.shape == (8, 8, 3)


def random_value(rng, depth):
    """A random Python value as Scene() takes them: nested dicts, lists and tuples (down to
    `depth` levels) of str, int, float, bool, None and NumPy scalars and arrays."""
    kind = rng.integers(0, 10) if depth > 0 else rng.integers(0, 6)
    if kind == 0:
        return None
    if kind == 1:
        return bool(rng.integers(0, 2))
    if kind == 2:
        return int(rng.integers(-2**62, 2**62))
    if kind == 3:
        return float(rng.normal() * 10.0 ** rng.integers(-30, 30))
    if kind == 4:
        return "".join(chr(c) for c in rng.integers(1, 0x2FF, rng.integers(0, 8)))
    if kind == 5:
        return np.float32(rng.normal())
    if kind in (6, 7):
        return {f"k{i}": random_value(rng, depth - 1) for i in range(rng.integers(0, 4))}
    if kind == 8:
        return [random_value(rng, depth - 1) for _ in range(rng.integers(0, 4))]
    return tuple(random_value(rng, depth - 1) for _ in range(rng.integers(0, 3)))


def plain(value):
    """What JSON makes of a value: tuples are lists, NumPy scalars Python numbers."""
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


def container_depth(value):
    if isinstance(value, dict):
        return 1 + max(map(container_depth, value.values()), default=0)
    if isinstance(value, (list, tuple)):
        return 1 + max(map(container_depth, value), default=0)
    return 0


def test_the_converter_on_random_values():
    # 2000 random documents: each converts to the JSON of its plain form, exactly; a deep
    # chain wrapped around one is refused by depth alone, with the pointer to where.
    import json
    rng = np.random.default_rng(7)
    for i in range(2000):
        value = random_value(rng, int(rng.integers(0, 6)))
        assert json.loads(veil._veil._json_text(value)) == plain(value), i
        depth = int(rng.integers(250, 262))
        wrapped = nested(depth, "list" if i % 2 else "dict")
        inner = wrapped
        for _ in range(depth - 1):
            inner = inner[0] if i % 2 else inner["a"]
        if i % 2:
            inner[0] = value
        else:
            inner["a"] = value
        levels = depth + container_depth(value)
        if levels <= 256:
            assert json.loads(veil._veil._json_text(wrapped)) == plain(wrapped), i
        else:
            with pytest.raises(veil.ValueError, match="^value: /.*nested deeper than 256"):
                veil._veil._json_text(wrapped)
