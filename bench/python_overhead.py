"""The Python module's overhead: a frame rendered N times through veil.Renderer.render (Python:
argument handling, the frame's arrays and report dict) against the same loop in C++
(capture::renderFrame N times in one call, veil._veil._Renderer._render_loop), in one process
and one GL context. Blocks of 10 frames alternate between the two so that clock drift hits
both. Run by bench/run.py (tool "python"); prints JSON.

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python_overhead.py SCENE \
        [--width 64 --height 64 --frames 100] [--json out.json]
"""

import argparse
import json
import statistics
import sys
import time

import veil


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene")
    ap.add_argument("--width", type=int, default=64)
    ap.add_argument("--height", type=int, default=64)
    ap.add_argument("--frames", type=int, default=100)
    ap.add_argument("--warmup", type=int, default=3)
    ap.add_argument("--json")
    args = ap.parse_args()

    renderer = veil.Renderer()
    scene = veil.Scene.load(args.scene)
    for _ in range(args.warmup):
        renderer.render(scene, width=args.width, height=args.height)
    py, cpp = [], []
    block = 10
    done = 0
    while done < args.frames:
        n = min(block, args.frames - done)
        for _ in range(n):
            start = time.perf_counter()
            renderer.render(scene, width=args.width, height=args.height)
            py.append(time.perf_counter() - start)
        cpp += renderer._render_loop(scene, n, args.width, args.height)
        done += n
    result = {
        "scene": args.scene, "width": args.width, "height": args.height, "frames": args.frames,
        "renderer": renderer.gl_renderer, "gl_version": renderer.gl_version,
        "python": {"total_s": sum(py), "median_ms": 1e3 * statistics.median(py),
                   "min_ms": 1e3 * min(py), "max_ms": 1e3 * max(py)},
        "cpp": {"total_s": sum(cpp), "median_ms": 1e3 * statistics.median(cpp),
                "min_ms": 1e3 * min(cpp), "max_ms": 1e3 * max(cpp)},
    }
    result["ratio_total"] = result["python"]["total_s"] / result["cpp"]["total_s"]
    text = json.dumps(result, indent=1)
    if args.json:
        with open(args.json, "w") as f:
            f.write(text + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
