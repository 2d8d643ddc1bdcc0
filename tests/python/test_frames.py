"""Renderer.frames(): a frame range rendered with one renderer (sequence/range_player.h), each
frame equal bit for bit to `veil render --frame N` of the same scene, the later frames
replacing only the volumes' data with their upload made during the previous frame's render."""

import json
import subprocess

import numpy as np
import pytest

import veil
from conftest import ROOT

FIRE = ROOT / "datasets" / "third_party" / "vdb-embergen-fire-seq" / "embergen_fire_a_#.vdb"


def fire_scene(folder, gpu_cache_mib=None):
    """The fire frames 1-4 glowing (temperature emission), a shadow-casting key, a turntable;
    40x32 and few steps: cheap on llvmpipe."""
    doc = {
        "render": {"width": 40, "height": 32, "fog_steps": 40, "shadows": "opaque"},
        "cameras": [{"position": [0, -62, -98], "target": [0, 0, -112], "up": [0, 0, 1],
                     "turntable": {"frames": 8, "start_frame": 1}}],
        "lights": [{"type": "directional", "direction": [-0.4, 0.5, -0.75]}],
        "volumes": [{"name": "fire", "path": str(FIRE), "grid": "flames",
                     "density_scale": 6.0, "temperature_grid": "temperature",
                     "temperature_scale": 1100, "temperature_offset": 900, "after": "loop"}],
    }
    if gpu_cache_mib is not None:
        doc["render"]["sequence_gpu_cache_mib"] = gpu_cache_mib
    path = folder / f"fire{'' if gpu_cache_mib is None else gpu_cache_mib}.json"
    path.write_text(json.dumps(doc))
    return path


def test_frames_equal_single_frame_renders(renderer, veil_exe, tmp_path):
    scene = fire_scene(tmp_path)
    frames = renderer.frames(scene, 1, 3)
    assert len(frames) == 3
    numbers, seen = [], []
    for number, frame in frames:
        exr = tmp_path / f"alone.{number}.exr"
        subprocess.run([veil_exe, "render", str(scene), "--frame", str(number), "-o", str(exr)],
                       check=True, capture_output=True)
        alone = veil.read_image(exr)
        assert frame.rgb.shape == (32, 40, 3)
        assert np.array_equal(frame.rgb, alone[..., :3]), f"frame {number}"
        r = frame.report
        assert r["frame"] == number and r["renderers_built"] == 1
        # The frames after the first were uploaded while the one before rendered.
        assert r["uploaded_ahead"] == (number > 1)
        assert r["uploaded_bytes"] > 0 and r["upload_ms"] >= 0.0
        numbers.append(number)
        seen.append(frame.rgb.copy())
    assert numbers == [1, 2, 3]
    assert not np.array_equal(seen[0], seen[1])  # the fire and the camera moved


def test_frame_report_has_the_fields_of_the_range_report(renderer, veil_exe, tmp_path):
    # frame.report and `veil render --frames --report` give a frame's stages under the same
    # names (sequence/range_player.h FrameStages::json).
    scene = fire_scene(tmp_path)
    report = tmp_path / "range.json"
    subprocess.run([veil_exe, "render", str(scene), "--frames", "1-2", "-o",
                    str(tmp_path / "r.#.exr"), "--report", str(report)],
                   check=True, capture_output=True)
    cli = json.loads(report.read_text())["frames"]
    played = list(renderer.frames(scene, 1, 2))
    for entry, (number, frame) in zip(cli, played):
        stages = set(entry) - {"output", "gpu_ms", "write_ms"}
        assert {"ahead_ms", "uploads", "active_voxels"} <= stages
        assert stages <= set(frame.report), stages - set(frame.report)
        assert frame.report["active_voxels"] == entry["active_voxels"] > 0
        assert frame.report["uploads"] == entry["uploads"], number


def test_looped_frames_held_on_the_gpu_upload_nothing(renderer, tmp_path):
    # Frames 5 and 6 loop back to the files of 1 and 2; frame 2's upload is held on the GPU
    # (frame 1 was uploaded by the renderer being built, without a key, so 5 uploads again).
    for budget in (None, 0):
        scene = fire_scene(tmp_path, budget)
        played = list(renderer.frames(scene, 1, 6))
        uploaded = [frame.report["uploaded_bytes"] for _, frame in played]
        assert uploaded[4] > 0, uploaded
        assert (uploaded[5] == 0) == (budget is None), uploaded
        _, alone = next(iter(renderer.frames(scene, 6)))
        assert np.array_equal(played[5][1].rgb, alone.rgb), f"budget {budget}"


def test_frames_first_alone_and_step(renderer, tmp_path):
    scene = fire_scene(tmp_path)
    assert [n for n, _ in renderer.frames(scene, 2)] == [2]
    assert len(renderer.frames(scene, 1, 5, step=2)) == 3


def test_frames_bad_arguments(renderer, tmp_path):
    scene = fire_scene(tmp_path)
    with pytest.raises(veil.ValueError, match="first=3 is after last=1"):
        renderer.frames(scene, 3, 1)
    with pytest.raises(veil.ValueError, match="step=0"):
        renderer.frames(scene, 1, 2, step=0)
    with pytest.raises(veil.ValueError, match="threads=0"):
        renderer.frames(scene, 1, 2, threads=0)
