#!/usr/bin/python3
"""Relative error of GPU fog frames against a path-traced reference over the volume's pixels.

usage: volume_error.py REFERENCE.exr[,...] REFERENCE-stderr.exr[,...] BACKGROUND_R,G,B IMAGE.exr [...]
       [--bin K] [--error-map IMAGE.exr OUT.png]... [--png IMAGE.exr OUT.png]...

Reads linear EXR radiance (several reference runs with different seeds: their mean)
through oiiotool --dumpdata. The volume's pixels are those where the reference's luminance differs from the background's by more than 2 % of it. Per image:
mean and 99th percentile of |Y - Y_ref| / Y_ref (Y: Rec. 709 luminance) over those pixels,
and the reference's own mean relative standard error there (its noise floor). --error-map
writes |Y - Y_ref| / Y_ref as a false-colour PNG (0 black .. 0.5 white) through oiiotool;
--png writes an image tone-mapped as the frame's default (ACES fit [Narkowicz16], sRGB).
--bin K compares K x K pixel blocks of the reference (means; its standard error / K) with
the images box-filtered to the same size (an image of the binned size is taken as it is).
Needs /usr/bin/python3 with numpy and OpenImageIO's oiiotool on PATH.
"""
import os
import subprocess
import sys
import tempfile

import numpy as np


def read_rgb(path):
    """RGB of an image file, top row first (oiiotool --dumpdata: text at full precision)."""
    out = subprocess.run(["oiiotool", "--info", "--dumpdata", path], check=True,
                         capture_output=True, text=True).stdout
    pixels = {}
    for line in out.splitlines():
        line = line.strip()
        if line.startswith("Pixel ("):
            xy, values = line[len("Pixel ("):].split("):")
            x, y = (int(v) for v in xy.split(","))
            pixels[(x, y)] = [float(v) for v in values.split()[:3]]
    w = 1 + max(x for x, _ in pixels)
    h = 1 + max(y for _, y in pixels)
    rgb = np.zeros((h, w, 3))
    for (x, y), v in pixels.items():
        rgb[y, x] = v
    return rgb


def bin_to(y, k):
    """Means of k x k blocks."""
    if k == 1:
        return y
    h, w = y.shape
    return y.reshape(h // k, k, w // k, k).mean(axis=(1, 3))


def luminance(rgb):
    return rgb @ np.array([0.2126, 0.7152, 0.0722])


def write_png(rgb, out):
    """rgb in [0, 1], top row first."""
    h, w, _ = rgb.shape
    with tempfile.TemporaryDirectory() as d:
        ppm = os.path.join(d, "x.ppm")
        with open(ppm, "wb") as f:
            f.write(f"P6\n{w} {h}\n255\n".encode())
            f.write((np.clip(rgb, 0.0, 1.0) * 255 + 0.5).astype(np.uint8).tobytes())
        subprocess.run(["oiiotool", ppm, "-o", out], check=True)


def tone_map(x):
    y = np.clip(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0)
    return np.where(y <= 0.0031308, 12.92 * y, 1.055 * y ** (1 / 2.4) - 0.055)


def take(argv, flag):
    out = []
    while flag in argv:
        i = argv.index(flag)
        out.append((argv[i + 1], argv[i + 2]))
        del argv[i:i + 3]
    return out


def main(argv):
    maps = take(argv, "--error-map")
    for image, out in take(argv, "--png"):
        runs = image.split(",")  # several runs: their mean
        write_png(tone_map(sum(read_rgb(r) for r in runs) / len(runs)), out)
    if len(argv) < 3:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    k = 1
    if "--bin" in argv:
        i = argv.index("--bin")
        k = int(argv[i + 1])
        del argv[i:i + 2]
    # Several runs of the reference (different seeds), comma-separated: their mean.
    refs = argv[0].split(",")
    ref = bin_to(sum(luminance(read_rgb(p)) for p in refs) / len(refs), k)
    se = np.sqrt(sum(luminance(read_rgb(p)) ** 2 for p in argv[1].split(","))) / len(refs)
    se = bin_to(se, k) / k
    bg = luminance(np.array([float(v) for v in argv[2].split(",")]))
    mask = np.abs(ref - bg) > 0.02 * bg
    print(f"volume pixels: {mask.sum()} of {mask.size}; reference mean Y {ref[mask].mean():.4f}; "
          f"reference mean relative standard error {(se[mask] / np.maximum(ref[mask], 1e-6)).mean():.4f}")
    for path in argv[3:] + [m[0] for m in maps if m[0] not in argv[3:]]:
        y = luminance(read_rgb(path))
        y = bin_to(y, y.shape[1] // ref.shape[1])
        rel = np.abs(y - ref) / np.maximum(ref, 1e-6)
        bias = (y[mask] - ref[mask]).sum() / ref[mask].sum()
        print(f"{path}: mean relative error {rel[mask].mean():.4f}, p99 "
              f"{np.percentile(rel[mask], 99):.4f}, mean Y {y[mask].mean():.4f} "
              f"(bias {bias:+.4f})")
        for image, out in maps:
            if image == path:
                err = np.where(mask, np.clip(rel / 0.5, 0.0, 1.0), 0.0)
                write_png(np.stack([err, err ** 2, err ** 4], axis=-1), out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
