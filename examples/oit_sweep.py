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
    ap.add_argument("--replot", help="plot the numbers of an earlier --json file instead")
    args = ap.parse_args()

    if args.replot:  # the numbers of an earlier --json, plotted again without rendering
        saved = json.loads(pathlib.Path(args.replot).read_text())
        plot(args, saved["rows"], saved["renderer"])
        return
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
    plot(args, rows, renderer.gl_renderer)
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(
            {"renderer": renderer.gl_renderer, "width": args.width, "height": args.height,
             "rows": rows}, indent=1) + "\n")


def plot(args, rows, renderer_name):
    fig, ax = plt.subplots(figsize=(8, 5), dpi=110)
    exact = next((r for r in rows if r["technique"] == "reference"), None)
    others = sorted((r for r in rows if r is not exact), key=lambda r: r["ms"])
    if exact:  # RMSE 0: a vertical line at its time
        ax.axvline(exact["ms"], color="black", linestyle="--", linewidth=1)
        ax.annotate("reference (exact, RMSE 0)", (exact["ms"], 1), xycoords=("data", "axes fraction"),
                    xytext=(3, -12), textcoords="offset points", fontsize=7)
    families = {"moment": "tab:red", "stochastic": "tab:green", "phenomenological": "tab:purple"}
    for i, row in enumerate(others):
        color = next((c for k, c in families.items() if row["technique"].startswith(k)), "tab:blue")
        ax.scatter(row["ms"], row["rmse"], s=30, color=color, zorder=3)
        ax.annotate(row["technique"], (row["ms"], row["rmse"]), fontsize=6.5, color=color,
                    xytext=(4, 4 if i % 2 == 0 else -9), textcoords="offset points")
    ax.set_xscale("log")
    ax.set_xlabel("technique time, transparent + resolve (ms, median of "
                  f"{args.frames}; {renderer_name.split(' (')[0]})")
    ax.set_ylabel("RMSE vs reference (linear HDR RGB)")
    ax.set_title(f"OIT techniques on {pathlib.Path(args.scene).name}, {args.width}x{args.height}",
                 fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    pathlib.Path(args.output).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.output)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
