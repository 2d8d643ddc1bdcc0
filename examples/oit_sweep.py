"""Every OIT technique on the smoke + glass scene: image error against `reference` (the exact
per-pixel sorted composite) versus the technique's GPU time, plotted with matplotlib.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/oit_sweep.py -o oit-sweep.png

GPU time is the technique's own passes (`transparent` + `resolve`, GL_TIME_ELAPSED on a GPU;
glFinish + CPU clock on llvmpipe, where it measures the CPU rasterizer), the median of
--frames frames. Error is the RMSE of linear HDR RGB against `reference` of the same frame;
stochastic techniques are one seed (their noise is part of their error).
"""

import argparse
import json
import pathlib
import statistics

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import veil  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
TECHNIQUE_PASSES = ("transparent", "resolve")


def technique_ms(frame):
    return sum(p["ms"] for p in frame.report["passes"] if p["name"] in TECHNIQUE_PASSES)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", default="oit-sweep.png")
    ap.add_argument("--scene", default=str(ROOT / "datasets/scenes/oit-smoke-glass.json"))
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=180)
    ap.add_argument("--frames", type=int, default=3, help="frames per technique (median time)")
    ap.add_argument("--json", help="also write the numbers here")
    args = ap.parse_args()

    renderer = veil.Renderer()
    scene = veil.Scene.load(args.scene)
    size = dict(width=args.width, height=args.height)
    reference = renderer.render(scene, oit="reference", **size)
    rows = []
    for t in veil.techniques(renderer):
        if t["kind"] != "oit" or t["available"] != "yes":
            continue
        frames = [renderer.render(scene, oit=t["name"], **size) for _ in range(args.frames)]
        rows.append({"technique": t["name"],
                     "ms": statistics.median(technique_ms(f) for f in frames),
                     "rmse": veil.compare(frames[0].rgb, reference.rgb, metric="rmse")})
        print(f"{t['name']:<28} {rows[-1]['ms']:9.3f} ms  rmse {rows[-1]['rmse']:.5f}")

    fig, ax = plt.subplots(figsize=(7.5, 4.6), dpi=110)
    for row in rows:
        exact = row["technique"] == "reference"
        ax.scatter(row["ms"], max(row["rmse"], 1e-5), s=36, color="black" if exact else "tab:blue",
                   marker="*" if exact else "o", zorder=3)
        ax.annotate(row["technique"], (row["ms"], max(row["rmse"], 1e-5)), fontsize=7,
                    xytext=(4, 3), textcoords="offset points")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("technique GPU time, transparent + resolve (ms, median of "
                  f"{args.frames}; {renderer.gl_renderer.split(' (')[0]})")
    ax.set_ylabel("RMSE vs reference (linear HDR RGB)")
    ax.set_title(f"OIT techniques on {pathlib.Path(args.scene).name}, "
                 f"{args.width}x{args.height} (reference plotted at 1e-5)", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    pathlib.Path(args.output).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.output)
    print(f"wrote {args.output}")
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(
            {"renderer": renderer.gl_renderer, "width": args.width, "height": args.height,
             "rows": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()
