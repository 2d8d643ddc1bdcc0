#!/usr/bin/python3
"""The viewer's panel renders and fits: `veil view --script` in a real 1280x720 window under Xvfb
with the OIT, Shadows and Frame sections open (reference OIT, whose statistics fill a table),
then checks the window screenshot:
- the panel (its blue title bar) is 24 font heights wide at most: under 30% of the window;
- no label runs into the panel's right edge: the 24 px left of the scrollbar hold no white text
  pixels outside widgets (a label cut off by the edge, as `initial_nodes_p` once was, puts
  them there);
- the frame is drawn beside it (the right half is not the clear colour);
- an interactive run (its window closed as a window manager closes it) keeps the panel's
  layout: loads imgui.ini and writes it back, atomically, at exit.
Standard library only (a PNG reader for 8-bit RGB/RGBA below). Writes panel.png into OUTPUT_DIR.
Usage: viewer_panel.py VEIL_EXE SOURCE_DIR OUTPUT_DIR [PNG]   (PNG: check that file instead)
"""
import json
import os
import shutil
import struct
import subprocess
import sys
import time
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


def close_veil_windows(display):
    """Sends WM_DELETE_WINDOW (what a window manager's close button sends) to the top-level
    windows named "veil view: ..." on `display`, through libX11 by ctypes. Returns how many."""
    import ctypes
    import ctypes.util
    X = ctypes.CDLL(ctypes.util.find_library("X11"))
    X.XOpenDisplay.restype = ctypes.c_void_p
    X.XOpenDisplay.argtypes = [ctypes.c_char_p]
    X.XDefaultRootWindow.restype = ctypes.c_ulong
    X.XDefaultRootWindow.argtypes = [ctypes.c_void_p]
    X.XInternAtom.restype = ctypes.c_ulong
    X.XInternAtom.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_int]
    X.XQueryTree.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.POINTER(ctypes.c_ulong),
                             ctypes.POINTER(ctypes.c_ulong),
                             ctypes.POINTER(ctypes.POINTER(ctypes.c_ulong)),
                             ctypes.POINTER(ctypes.c_uint)]
    X.XFetchName.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.POINTER(ctypes.c_char_p)]
    X.XFlush.argtypes = [ctypes.c_void_p]
    X.XCloseDisplay.argtypes = [ctypes.c_void_p]

    class ClientMessage(ctypes.Structure):
        _fields_ = [("type", ctypes.c_int), ("serial", ctypes.c_ulong),
                    ("send_event", ctypes.c_int), ("display", ctypes.c_void_p),
                    ("window", ctypes.c_ulong), ("message_type", ctypes.c_ulong),
                    ("format", ctypes.c_int), ("data", ctypes.c_long * 5)]

    class Event(ctypes.Union):
        _fields_ = [("xclient", ClientMessage), ("pad", ctypes.c_long * 24)]

    X.XSendEvent.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.c_int, ctypes.c_long,
                             ctypes.POINTER(Event)]
    d = X.XOpenDisplay(display.encode())
    if not d:
        return 0
    root, parent, n = ctypes.c_ulong(), ctypes.c_ulong(), ctypes.c_uint()
    kids = ctypes.POINTER(ctypes.c_ulong)()
    X.XQueryTree(d, X.XDefaultRootWindow(d), ctypes.byref(root), ctypes.byref(parent),
                 ctypes.byref(kids), ctypes.byref(n))
    protocols = X.XInternAtom(d, b"WM_PROTOCOLS", 0)
    delete = X.XInternAtom(d, b"WM_DELETE_WINDOW", 0)
    sent = 0
    for i in range(n.value):
        name = ctypes.c_char_p()
        if X.XFetchName(d, kids[i], ctypes.byref(name)) and name.value and \
                name.value.startswith(b"veil view"):
            e = Event()
            e.xclient.type, e.xclient.window = 33, kids[i]  # ClientMessage
            e.xclient.message_type, e.xclient.format = protocols, 32
            e.xclient.data[0] = delete
            X.XSendEvent(d, kids[i], 0, 0, ctypes.byref(e))
            sent += 1
    X.XFlush(d)
    X.XCloseDisplay(d)
    return sent


def layout_is_kept(veil, source, out):
    """An interactive `veil view` (no script) loads imgui.ini from $XDG_CONFIG_HOME/veil and
    writes it back when its window is closed: a panel width of 500 px written there before
    the run is there after it, in a file the viewer rewrote. Returns a failure text or ''."""
    config = os.path.join(out, "config")
    os.makedirs(os.path.join(config, "veil"))
    ini = os.path.join(config, "veil", "imgui.ini")
    open(ini, "w").write("[Window][Veil]\nPos=6,6\nSize=500,200\nCollapsed=0\n")
    xvfb = subprocess.Popen(["Xvfb", "-displayfd", "1", "-screen", "0", "640x480x24"],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        display = ":" + xvfb.stdout.readline().strip()
        env = dict(os.environ, DISPLAY=display, XDG_CONFIG_HOME=config)
        view = subprocess.Popen([veil, "view",
                                 os.path.join(source, "tests/regression/scenes/golden_basic.json"),
                                 "--window-width", "640", "--window-height", "480"],
                                env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                text=True)
        end, sent = time.time() + 60, 0
        while time.time() < end and view.poll() is None and not sent:
            time.sleep(1.0)
            sent = close_veil_windows(display)
        try:
            output = view.communicate(timeout=60)[0]
        except subprocess.TimeoutExpired:
            view.kill()
            return "veil view did not end within 60 s of its window's close"
        if view.returncode != 0:
            return f"veil view exited {view.returncode}: {output}"
    finally:
        xvfb.kill()
        xvfb.wait()
    text = open(ini).read()
    if "Size=500,200" not in text.split("[Window][Veil]")[1].split("[")[0]:
        return f"the panel's size is not kept: {ini} holds {text!r}"
    if "[Window][Debug##Default]" not in text:
        return f"{ini} was not written back at exit: {text!r}"
    if [f for f in os.listdir(os.path.dirname(ini)) if f != "imgui.ini"]:
        return f"files left beside {ini}: {os.listdir(os.path.dirname(ini))}"
    return ""


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
    if len(sys.argv) == 4:
        problem = layout_is_kept(veil, source, out)
        check(not problem, "an interactive run keeps the panel's layout in imgui.ini " + problem)
    if failures:
        print(f"{len(failures)} check(s) failed; screenshot {shot}", file=sys.stderr)
        return 1
    print(f"panel ok; screenshot {shot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
