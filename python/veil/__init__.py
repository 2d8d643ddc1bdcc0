"""Veil from Python: scenes, headless rendering, image comparison, OpenVDB and voxelization.

    import veil
    scene = veil.Scene.load("datasets/scenes/default.json")
    scene.set("render.oit.type", "moment-p6")
    renderer = veil.Renderer()              # one headless GL context (EGL)
    frame = renderer.render(scene, width=320, height=180)
    frame.rgb                               # float32 H x W x 3, linear radiance
    frame.report["passes"]                  # per-pass times, as `veil render --report`

Every error is a veil.Error carrying the one-line message the `veil` command prints; each
is also the standard exception of its kind (veil.FileNotFoundError is a FileNotFoundError,
veil.ValueError a ValueError, veil.KeyError a KeyError, veil.TypeError a TypeError, ...).
docs/python.md has the whole interface.
"""

import builtins as _builtins
import os as _os
from dataclasses import dataclass as _dataclass, field as _field
from typing import Any as _Any, Optional as _Optional, Sequence as _Sequence, Union as _Union

# An installed package carries the shaders beside it; a build tree reads the source tree's.
_shaders = _os.path.join(_os.path.dirname(__file__), "shaders")
if "VEIL_SHADER_DIR" not in _os.environ and _os.path.isdir(_shaders):
    _os.environ["VEIL_SHADER_DIR"] = _shaders

from ._veil import (  # noqa: E402
    Error,
    FileNotFoundError,
    KeyError,
    MemoryError,
    OSError,
    Scene,
    TypeError,
    ValueError,
    Suite,
    __version__,
    compare,
    export_vti,
    heat_map,
    read_image,
    tonemap,
    vdb_info,
    voxelize,
    write_image,
)
from . import _veil  # noqa: E402

# The exception classes named like the built-in ones (veil.ValueError, ...) are not in
# __all__: `from veil import *` must not replace a caller's built-in ValueError.
__all__ = [
    "Error", "Frame", "Renderer", "Scene", "Suite", "__version__", "compare", "export_vti",
    "heat_map", "read_image", "techniques", "tonemap", "vdb_info", "voxelize", "write_image",
]



def _public(function):
    """The extension's `function` behind a Python function of the same name, signature and
    docstring: help() and inspect.signature() show its typed parameters, and a call with
    unknown or missing arguments is a veil.TypeError in Python's words ("compare(): got an
    unexpected keyword argument 'metrc'"), not pybind11's list of overloads."""
    import ast
    import functools
    import inspect
    import re

    name = function.__name__
    head, _, doc = (function.__doc__ or "").partition("\n")
    m = re.fullmatch(r"\w+\((.*)\) -> (.*)", head.strip())
    if not m:
        return function
    parameters = []
    try:
        for part in filter(None, m.group(1).split(", ")):
            pname, _, rest = part.partition(": ")
            annotation, _, default = rest.partition(" = ")
            value = ast.literal_eval(default) if default else inspect.Parameter.empty
            parameters.append(inspect.Parameter(pname, inspect.Parameter.POSITIONAL_OR_KEYWORD,
                                                default=value, annotation=annotation))
        signature = inspect.Signature(parameters, return_annotation=m.group(2))
    except (ValueError, SyntaxError):
        return function

    @functools.wraps(function)
    def call(*args, **kwargs):
        __tracebackhide__ = True
        try:
            signature.bind(*args, **kwargs)
        except _builtins.TypeError as e:
            raise TypeError(f"{name}(): {e}") from None
        return function(*args, **kwargs)

    del call.__wrapped__  # inspect shows `signature`, not the extension's opaque one
    call.__signature__ = signature
    call.__doc__ = doc.strip()
    call.__module__ = "veil"
    return call


compare = _public(compare)
export_vti = _public(export_vti)
heat_map = _public(heat_map)
read_image = _public(read_image)
tonemap = _public(tonemap)
vdb_info = _public(vdb_info)
voxelize = _public(voxelize)
write_image = _public(write_image)
# Public names in tracebacks and help(): veil.Scene, not veil._veil.Scene.
Scene.__module__ = "veil"
Suite.__module__ = "veil"


@_dataclass(repr=False)
class Frame:
    """One rendered frame. Arrays are float32, row 0 at the top, and share the read-back
    buffers (no copies).

    rgb    H x W x 3 linear HDR radiance (what `veil render -o x.exr` writes as R, G, B)
    alpha  H x W, 1 everywhere (the background is part of rgb)
    rgba   H x W x 4, rgb and alpha in one array (rgb and alpha are views of it)
    ldr    H x W x 4 tone-mapped sRGB in [0, 1] (what a PNG gets; alpha 1)
    depth  H x W view depth of the nearest opaque surface, +inf where there is none (Z)
    aovs   {"fog": H x W x 3 fog radiance, "fog.transmittance": H x W} when aovs=["fog"]
    report the `veil render --report` fields of the frame: passes [{name, ms}], total_ms,
           timer, gpu_bytes, oit, oit_properties, oit_stats, shadows, shadow_properties,
           frame_passes, volumes, scene_values (every effective scene value), width,
           height, camera, renderer, seconds (wall clock of the call)
    """

    rgba: object
    ldr: object
    depth: object
    report: dict
    aovs: dict = _field(default_factory=dict)

    def __repr__(self):
        """<veil.Frame 640x360 aovs=[fog] oit=blend shadows=moment 4.2 ms>: the size, the AOVs,
        the techniques and the GPU time, never the arrays or the whole report."""
        r = self.report or {}
        h, w = self.rgba.shape[:2]
        parts = [f"{w}x{h}"]
        if self.aovs:
            parts.append("aovs=[" + ", ".join(k for k in self.aovs if "." not in k) + "]")
        if r.get("oit"):
            parts.append(f"oit={r['oit']}")
        shadows = r.get("shadows")
        if isinstance(shadows, dict):
            shadows = shadows.get("name") or shadows.get("type")
        if shadows:
            parts.append(f"shadows={shadows}")
        if isinstance(r.get("total_ms"), (int, float)):
            parts.append(f"{r['total_ms']:.1f} ms")
        return "<veil.Frame " + " ".join(parts) + ">"

    __str__ = __repr__

    @property
    def rgb(self):
        return self.rgba[..., :3]

    @property
    def alpha(self):
        return self.rgba[..., 3]


class Renderer(_veil._Renderer):
    """A headless OpenGL 4.5 context (EGL: the GPU, or Mesa llvmpipe without one) that renders
    frames. device: EGL device index (default: $VEIL_EGL_DEVICE, else the first that works).

    The GL work runs with the GIL released: other Python threads go on meanwhile. One frame at
    a time per Renderer: calls from several threads wait for each other, each making the
    context current on its own thread for the call (any thread may use it).
    """

    def __init__(self, device: _Optional[int] = None):
        super().__init__(device)

    def __repr__(self):
        return f"<veil.Renderer {self.gl_renderer}, OpenGL {self.gl_version}>"

    def render(self, scene: _Union["Scene", str, _os.PathLike, dict],
               width: _Optional[int] = None, height: _Optional[int] = None,
               oit: _Optional[str] = None, shadows: _Optional[str] = None,
               camera: _Optional[str] = None, aovs: _Union[str, _Sequence[str]] = (),
               out: _Any = None) -> Frame:
        """Render one frame of `scene` (a Scene, a scene file path, a .vdb path or a dict) as
        `veil render` does, and return a Frame.

        width, height: image size (default the scene's render.width/height); oit: the OIT
        technique (default the scene's render.oit; see techniques()); shadows: the shadow
        technique; camera: a camera name; aovs: ["fog"] adds the fog's radiance and
        transmittance (the scene needs a volume or fog); out: a float32 C-contiguous
        H x W x 4 array that receives the linear HDR image without a copy (frame.rgba is
        then `out` itself; reuse it across a sweep). The result equals `veil render -o x.exr`
        of the same scene bit for bit. Errors: veil.TypeError for an argument of the wrong
        type, veil.ValueError for a bad value, veil.FileNotFoundError for a missing scene.
        """
        out = self._render(scene, width, height, oit, shadows, camera, aovs, out)
        extra = {}
        if "fog" in out:
            extra = {"fog": out["fog"], "fog.transmittance": out["fog_transmittance"]}
        return Frame(rgba=out["rgba"], ldr=out["ldr"], depth=out["depth"],
                     report=out["report"], aovs=extra)

    def frames(self, scene: _Union["Scene", str, _os.PathLike, dict],
               first: _Optional[int] = None, last: _Optional[int] = None, step: int = 1,
               width: _Optional[int] = None, height: _Optional[int] = None,
               oit: _Optional[str] = None, threads: int = 2):
        """An iterator of (frame number, Frame) over frames first..last (step) of an animated
        scene (default: the scene's whole range; first alone: that frame), rendered as
        `veil render --frames` renders them: one renderer for the range, worker threads
        (`threads`) reading and converting the next frames' grids, each later frame of the
        same structure replacing only the volumes' data, camera and lights, its upload made
        while the previous frame renders. Each Frame equals a frame rendered alone.
        len() gives the number of frames. frame.report holds the frame's passes and its
        times: wait_ms, read_ms, convert_ms, setup_ms, upload_ms (uploaded_ahead: during the
        previous frame's render), uploads, uploaded_bytes, render_ms, ahead_ms, active_voxels
        (the fields of `veil render --frames --report`).

            for number, frame in renderer.frames("datasets/scenes/fire-sequence.json", 1, 48):
                veil.write_image(f"out.{number:04d}.exr", frame.rgb)
        """
        frames = _veil._Frames(self, scene, first, last, step, width, height, oit, threads)
        return _FrameIterator(frames)

    def techniques(self) -> list:
        """techniques() with availability on this renderer's driver."""
        return self._techniques()


class _FrameIterator:
    """Renderer.frames(): (frame number, Frame) for each frame of the range."""

    def __init__(self, frames):
        self._frames = frames

    def __iter__(self):
        return self

    def __next__(self):
        number, out = next(self._frames)
        return number, Frame(rgba=out["rgba"], ldr=out["ldr"], depth=out["depth"],
                             report=out["report"])

    def __len__(self):
        return len(self._frames)


def techniques(renderer: _Optional["Renderer"] = None) -> list:
    """Every registered technique: a list of dicts with kind ("oit", "shadows" or "integrator":
    the CPU integrators of `veil render --integrator`), name, description, available
    ("yes"/"no" on this GL driver, "yes (CPU)" for an integrator) and properties (key, type,
    default, range, doc, citation), as `veil techniques --json` prints them."""
    if renderer is not None:
        if not isinstance(renderer, Renderer):
            raise TypeError(f"renderer: expected a veil.Renderer or None, got "
                            f"{type(renderer).__name__}")
        return renderer.techniques()
    return _veil._techniques_without_renderer()
