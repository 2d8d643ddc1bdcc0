"""A contact sheet of the fog's density scale x Henyey-Greenstein anisotropy on fog.json's
homogeneous haze (volume 1; --volume 0 is the smoke): one row per density scale, one column
per anisotropy g (positive: forward scattering, so the shafts seen against the light brighten).

    PYTHONPATH=build/release/python /usr/bin/python3 examples/fog_sweep.py -o fog-sweep.png

Each tile is the tone-mapped frame (as a PNG of `veil render` would show it).
"""

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import veil  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", default="fog-sweep.png")
    ap.add_argument("--scene", default=str(ROOT / "datasets/scenes/fog.json"))
    ap.add_argument("--volume", type=int, default=1, help="index of the volume to vary")
    ap.add_argument("--density", type=float, nargs="+", default=[0.02, 0.06, 0.18])
    ap.add_argument("--anisotropy", type=float, nargs="+", default=[-0.5, 0.0, 0.5, 0.85])
    ap.add_argument("--width", type=int, default=192)
    ap.add_argument("--height", type=int, default=108)
    args = ap.parse_args()

    renderer = veil.Renderer()
    base = veil.Scene.load(args.scene)
    rows, cols = len(args.density), len(args.anisotropy)
    fig, axes = plt.subplots(rows, cols, figsize=(2.2 * cols, 1.35 * rows + 0.5), dpi=110,
                             squeeze=False)
    for i, density in enumerate(args.density):
        for j, g in enumerate(args.anisotropy):
            scene = base.copy()
            scene.set(f"volumes.{args.volume}.density_scale", density)
            scene.set(f"volumes.{args.volume}.anisotropy", g)
            frame = renderer.render(scene, width=args.width, height=args.height)
            ax = axes[i][j]
            ax.imshow(frame.ldr[..., :3], interpolation="nearest")
            ax.set_xticks([])
            ax.set_yticks([])
            if i == 0:
                ax.set_title(f"g = {g:g}", fontsize=8)
            if j == 0:
                ax.set_ylabel(f"density_scale {density:g}", fontsize=7)
    fig.suptitle(f"{pathlib.Path(args.scene).name}: volume {args.volume} density scale x "
                 "anisotropy", fontsize=9)
    fig.tight_layout()
    pathlib.Path(args.output).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.output)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
