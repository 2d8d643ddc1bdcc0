#!/usr/bin/python3
"""The viewer's panel renders and fits: `veil view --script` in a real 1280x720 window under Xvfb
with the OIT, Shadows and Frame sections open (reference OIT, whose statistics fill a table),
then checks the window screenshot:
- the panel (its blue title bar) is 24 font heights wide at most: under 30% of the window;
- no label runs into the panel's right edge: the 24 px left of the scrollbar hold no white text
  pixels outside widgets (a label cut off by the edge, as `initial_nodes_p` once was, puts
  them there);
- the frame is drawn beside it (the right half is not the clear colour).
Standard library only (a PNG reader for 8-bit RGB/RGBA below). Writes panel.png into OUTPUT_DIR.
Usage: viewer_panel.py VEIL_EXE SOURCE_DIR OUTPUT_DIR [PNG]   (PNG: check that file instead)
"""
import json
import os
import shutil
import struct
import subprocess
import sys
import zlib


def read_png(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path}: not a PNG"
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        n, kind = struct.unpack("!I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, colour, _, _, interlace = struct.unpack("!IIBBBBB", body)
            assert depth == 8 and colour in (2, 6) and not interlace, f"{path}: unsupported PNG"
            bpp = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, stride = zlib.decompress(idat), w * bpp
    rows, prev = [], bytearray(stride)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return w, h, lambda x, y: tuple(rows[y][x * bpp:x * bpp + 3])


def main():
    if len(sys.argv) not in (4, 5):
        print(__doc__.strip().split("\n")[-1], file=sys.stderr)
        return 2
    veil, source, out = sys.argv[1:4]
    shot = os.path.join(out, "panel.png")
    if len(sys.argv) == 5:
        shot = sys.argv[4]
    else:
        if shutil.which("xvfb-run") is None:
            print("FAIL: xvfb-run missing (scripts/install-deps.sh installs xvfb)", file=sys.stderr)
            return 1
        shutil.rmtree(out, ignore_errors=True)
        os.makedirs(out)
        script = os.path.join(out, "script.json")
        json.dump([{"expand": ["Transparency (OIT)", "Shadows", "Frame"]}, {"frames": 2},
                   {"window_screenshot": shot}], open(script, "w"))
        r = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1280x720x24", veil, "view",
                            os.path.join(source, "datasets/scenes/oit-smoke-glass.json"),
                            "--oit", "reference", "--width", "160", "--height", "90",
                            "--window-width", "1280", "--window-height", "720",
                            "--script", script], capture_output=True, text=True, timeout=120)
        if r.returncode != 0:
            print(f"FAIL: veil view exited {r.returncode}:\n{r.stdout}{r.stderr}",
                  file=sys.stderr)
            return 1
    w, h, px = read_png(shot)
    failures = []

    def check(ok, what):
        print(("ok   " if ok else "FAIL ") + what)
        if not ok:
            failures.append(what)

    check((w, h) == (1280, 720), f"window screenshot is 1280x720 ({w}x{h})")
    # The title bar: ImGui's active title colour (0.16, 0.29, 0.48) along a row near the top.
    y = 12
    title = [x for x in range(w) if all(abs(a - b) <= 3 for a, b in zip(px(x, y), (41, 74, 122)))]
    right = max(title) if title else 0
    check(200 <= right < 0.3 * w, f"the panel ends at x = {right} (under 30% of {w})")
    # Labels end before the edge: no white text in the 24 px left of the scrollbar (14 px) and
    # border, below the title bar and status line.
    # Rows crossing a widget there (its frame is blue: b - r > 25) are left out: a widget's
    # own glyphs (a combo's arrow) may be white.
    white = []
    for yy in range(40, h - 8):
        row = [px(x, yy) for x in range(right - 14 - 24, right - 14)]
        if not any(c[2] - c[0] > 25 for c in row):
            white += [(right - 38 + i, yy) for i, c in enumerate(row) if min(c) >= 200]
    check(not white, f"no text runs into the panel's right edge ({len(white)} white pixels, "
                     f"first {white[:3]})")
    # The frame beside the panel is drawn (not the clear colour everywhere).
    colours = {px(x, yy) for x in range(right + 40, w, 37) for yy in range(40, h, 31)}
    check(len(colours) > 10, f"the frame is drawn beside the panel ({len(colours)} colours)")
    if failures:
        print(f"{len(failures)} check(s) failed; screenshot {shot}", file=sys.stderr)
        return 1
    print(f"panel ok; screenshot {shot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
