"""Veil from Python: scenes, headless rendering, image comparison, OpenVDB and voxelization.

    import veil
    scene = veil.Scene.load("datasets/scenes/default.json")
    scene.set("render.oit.type", "moment-p6")
    renderer = veil.Renderer()              # one headless GL context (EGL)
    frame = renderer.render(scene, width=320, height=180)
    frame.rgb                               # float32 H x W x 3, linear radiance
    frame.report["passes"]                  # per-pass times, as `veil render --report`

Every error is a veil.Error carrying the one-line message the `veil` command prints.
docs/python.md has the whole interface.
"""

import os as _os
from dataclasses import dataclass as _dataclass, field as _field

# An installed package carries the shaders beside it; a build tree reads the source tree's.
_shaders = _os.path.join(_os.path.dirname(__file__), "shaders")
if "VEIL_SHADER_DIR" not in _os.environ and _os.path.isdir(_shaders):
    _os.environ["VEIL_SHADER_DIR"] = _shaders

from ._veil import (  # noqa: E402
    Error,
    Scene,
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

__all__ = [
    "Error", "Frame", "Renderer", "Scene", "Suite", "__version__", "compare", "export_vti",
    "heat_map", "read_image", "techniques", "tonemap", "vdb_info", "voxelize", "write_image",
]


@_dataclass
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
    a time per Renderer (calls from several threads wait for each other); use it from the
    thread that made it or make one per thread.
    """

    def __init__(self, device=None):
        super().__init__(device)

    def render(self, scene, width=None, height=None, oit=None, shadows=None, camera=None,
               aovs=(), out=None):
        """Render one frame of `scene` (a Scene, a scene file path, a .vdb path or a dict) as
        `veil render` does, and return a Frame.

        width, height: image size (default the scene's render.width/height); oit: the OIT
        technique (default the scene's render.oit; see techniques()); shadows: the shadow
        technique; camera: a camera name; aovs: ["fog"] adds the fog's radiance and
        transmittance; out: a float32 C-contiguous H x W x 4 array that receives the linear
        HDR image without a copy (frame.rgba is then `out` itself; reuse it across a sweep).
        The result equals `veil render -o x.exr` of the same scene bit for bit.
        """
        if isinstance(aovs, str):
            aovs = [aovs]
        out = self._render(scene, width or 0, height or 0, oit or "", shadows or "",
                           camera or "", list(aovs), out)
        extra = {}
        if "fog" in out:
            extra = {"fog": out["fog"], "fog.transmittance": out["fog_transmittance"]}
        return Frame(rgba=out["rgba"], ldr=out["ldr"], depth=out["depth"],
                     report=out["report"], aovs=extra)

    def techniques(self):
        """techniques() with availability on this renderer's driver."""
        return self._techniques()


def techniques(renderer=None):
    """Every registered technique: a list of dicts with kind ("oit" or "shadows"), name,
    description, available ("yes"/"no" on this GL driver) and properties (key, type,
    default, range, doc, citation), as `veil techniques --json` prints them."""
    if renderer is not None:
        return renderer.techniques()
    return _veil._techniques_without_renderer()
