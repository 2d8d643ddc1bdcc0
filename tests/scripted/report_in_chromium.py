#!/usr/bin/python3
"""The HTML report of `veil regress` in headless Chromium, driven through the DevTools protocol.

Runs a small suite with the real binary (one case fails on purpose, two pass), opens the
report's index.html in Debian's chromium, and checks the page as a user meets it: the summary
table comes first with one row per case; a click on a passed case's row (a real mouse event)
opens its card and scrolls to it; a click on the render flips it to the reference and back; the
mouse over an image moves the magnifiers to that pixel; each heat map has a colour bar whose
ends are 0 and the case's heat scale. Writes a screenshot (report.png) into the output folder.

Standard library only (the WebSocket client is below). Usage:
  report_in_chromium.py VEIL_EXE OUTPUT_DIR [CHROMIUM]
Exit 0 when every check holds; 1 with one line per failed check; 1 when chromium is missing.
"""
import base64
import json
import os
import shutil
import socket
import struct
import subprocess
import sys
import tempfile
import time
import urllib.request

SCENE = {
    "render": {"width": 40, "height": 30, "oit": "blend"},
    "cameras": [{"name": "c", "position": [0, 1, 4], "target": [0, 0.5, 0]}],
    "lights": [{"type": "directional", "direction": [0.3, -1, -0.2], "intensity": 2}],
    "materials": {"m": {"base_color": 0.5}, "glass": {"base_color": 1, "alpha": 0.4}},
    "objects": [{"shape": {"type": "box", "size": [2, 1, 0.5]}, "material": "m"},
                {"shape": {"type": "sphere", "radius": 0.5, "segments": 16, "rings": 8},
                 "material": "glass", "transform": {"translate": [0, 0.8, 1]}}],
}
SUITE = {
    "name": "report in chromium",
    "defaults": {"scene": "scene.json", "width": 40, "height": 30},
    "cases": [
        # blend differs from the exact composite behind the glass: an rmse of 1e-9 fails.
        {"name": "blend-tight", "technique": "blend", "reference": "reference",
         "metrics": {"rmse": 1e-9, "maxabs": 1.0}},
        {"name": "wboit", "technique": "wboit", "reference": "reference",
         "metrics": {"rmse": 0.5, "psnr": 5}},
        {"name": "exact", "technique": "reference", "reference": "reference",
         "metrics": {"maxabs": 0.0}},
    ],
}


class WebSocket:
    """A WebSocket client (RFC 6455) for one local DevTools connection: text frames out
    (masked, as a client must send), text frames in, continuation frames joined."""

    def __init__(self, url):
        assert url.startswith("ws://")
        hostport, path = url[5:].split("/", 1)
        host, port = hostport.rsplit(":", 1)
        self.sock = socket.create_connection((host, int(port)), timeout=30)
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall((f"GET /{path} HTTP/1.1\r\nHost: {hostport}\r\nUpgrade: websocket\r\n"
                           f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
                           "Sec-WebSocket-Version: 13\r\n\r\n").encode())
        head = b""
        while b"\r\n\r\n" not in head:
            chunk = self.sock.recv(4096)
            if not chunk:
                raise RuntimeError("DevTools closed the connection during the handshake")
            head += chunk
        head, self.buffer = head.split(b"\r\n\r\n", 1)
        if b" 101 " not in head.split(b"\r\n")[0]:
            raise RuntimeError("DevTools refused the WebSocket: " + head.decode(errors="replace"))

    def _read(self, n):
        while len(self.buffer) < n:
            chunk = self.sock.recv(1 << 16)
            if not chunk:
                raise RuntimeError("DevTools closed the connection")
            self.buffer += chunk
        out, self.buffer = self.buffer[:n], self.buffer[n:]
        return out

    def send(self, text):
        data = text.encode()
        header = bytes([0x81])  # FIN, text
        if len(data) < 126:
            header += bytes([0x80 | len(data)])
        elif len(data) < 1 << 16:
            header += bytes([0x80 | 126]) + struct.pack("!H", len(data))
        else:
            header += bytes([0x80 | 127]) + struct.pack("!Q", len(data))
        mask = os.urandom(4)
        self.sock.sendall(header + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(data)))

    def receive(self):
        message = b""
        while True:
            b0, b1 = self._read(2)
            opcode, length = b0 & 0x0F, b1 & 0x7F
            if length == 126:
                length = struct.unpack("!H", self._read(2))[0]
            elif length == 127:
                length = struct.unpack("!Q", self._read(8))[0]
            mask = self._read(4) if b1 & 0x80 else None
            payload = self._read(length)
            if mask:
                payload = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
            if opcode == 0x8:
                raise RuntimeError("DevTools closed the WebSocket")
            if opcode in (0x9, 0xA):  # ping, pong: DevTools sends none; ignore
                continue
            message += payload
            if b0 & 0x80:
                return message.decode()


class Page:
    def __init__(self, ws):
        self.ws, self.next_id, self.events = ws, 0, []

    def call(self, method, **params):
        self.next_id += 1
        self.ws.send(json.dumps({"id": self.next_id, "method": method, "params": params}))
        while True:
            m = json.loads(self.ws.receive())
            if m.get("id") == self.next_id:
                if "error" in m:
                    raise RuntimeError(f"{method}: {m['error']}")
                return m.get("result", {})
            self.events.append(m)

    def wait_event(self, name, timeout=30):
        end = time.time() + timeout
        while time.time() < end:
            for i, e in enumerate(self.events):
                if e.get("method") == name:
                    return self.events.pop(i)
            self.events.append(json.loads(self.ws.receive()))
        raise RuntimeError(f"no {name} within {timeout} s")

    def js(self, expression):
        r = self.call("Runtime.evaluate", expression=expression, returnByValue=True)
        if "exceptionDetails" in r:
            raise RuntimeError(f"page script failed: {expression}: {r['exceptionDetails']}")
        return r["result"].get("value")

    def mouse(self, kind, x, y, **extra):
        self.call("Input.dispatchMouseEvent", type=kind, x=x, y=y, **extra)

    def click(self, x, y):
        self.mouse("mouseMoved", x, y)
        self.mouse("mousePressed", x, y, button="left", clickCount=1)
        self.mouse("mouseReleased", x, y, button="left", clickCount=1)

    def centre(self, selector):
        r = self.js(f"(function(){{var e=document.querySelector({json.dumps(selector)});"
                    "if(!e)return null;e.scrollIntoView({block:'center'});"
                    "var r=e.getBoundingClientRect();return [r.left,r.top,r.width,r.height];})()")
        if r is None:
            raise RuntimeError(f"no element {selector}")
        return r


def start_chromium(chromium, profile):
    args = [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
            "--remote-debugging-port=0", f"--user-data-dir={profile}", "--window-size=1280,1000",
            "--hide-scrollbars", "about:blank"]
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    port_file = os.path.join(profile, "DevToolsActivePort")
    end = time.time() + 60
    while time.time() < end:
        if proc.poll() is not None:
            raise RuntimeError(f"chromium exited with {proc.returncode} before DevTools started")
        if os.path.exists(port_file):
            lines = open(port_file).read().split("\n")
            if len(lines) >= 2 and lines[0].isdigit():
                return proc, int(lines[0])
        time.sleep(0.1)
    proc.kill()
    raise RuntimeError("chromium's DevTools port did not appear within 60 s")


def main():
    if len(sys.argv) not in (3, 4):
        print(__doc__.strip().split("\n\n")[-1], file=sys.stderr)
        return 2
    veil, out = sys.argv[1], sys.argv[2]
    chromium = sys.argv[3] if len(sys.argv) == 4 else (shutil.which("chromium") or
                                                       "/usr/bin/chromium")
    if not (os.path.isfile(chromium) and os.access(chromium, os.X_OK)):
        print(f"FAIL: chromium not found at '{chromium}': install Debian's chromium "
              "(scripts/install-deps.sh lists it); this test does not skip", file=sys.stderr)
        return 1
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    json.dump(SCENE, open(os.path.join(out, "scene.json"), "w"))
    json.dump(SUITE, open(os.path.join(out, "suite.json"), "w"))
    report = os.path.join(out, "report")
    r = subprocess.run([veil, "regress", os.path.join(out, "suite.json"), "-o", report],
                       capture_output=True, text=True)
    if r.returncode != 1 or "1 case(s) failed: blend-tight" not in r.stdout + r.stderr:
        print(f"FAIL: veil regress exited {r.returncode} (expected 1, blend-tight failing):\n"
              + r.stdout + r.stderr, file=sys.stderr)
        return 1
    results = json.load(open(os.path.join(report, "results.json")))
    scales = {c["name"]: c.get("heat_scale") for c in results["cases"]}

    failures = []

    def check(ok, what):
        print(("ok   " if ok else "FAIL ") + what)
        if not ok:
            failures.append(what)

    profile = tempfile.mkdtemp(prefix="veil-chromium-")
    proc = None
    try:
        proc, port = start_chromium(chromium, profile)
        targets = json.load(urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list",
                                                   timeout=30))
        page = Page(WebSocket(next(t for t in targets if t["type"] == "page")
                              ["webSocketDebuggerUrl"]))
        page.call("Page.enable")
        page.call("Page.navigate", url="file://" + os.path.abspath(report) + "/index.html")
        page.wait_event("Page.loadEventFired")

        # The summary table first: before every card, one row per case in suite order.
        rows = page.js("Array.from(document.querySelectorAll('#summary tbody tr'))"
                       ".map(function(r){return [r.dataset.case,"
                       "r.querySelector('td.result').textContent,"
                       "r.querySelector('a').getAttribute('href')];})")
        check(rows == [["blend-tight", "FAIL", "#blend-tight"], ["wboit", "pass", "#wboit"],
                       ["exact", "pass", "#exact"]], f"summary rows {rows}")
        check(page.js("!!(document.getElementById('summary').compareDocumentPosition("
                      "document.querySelector('details.case')) & 4)"),
              "the summary table comes before the first card")
        headers = page.js("Array.from(document.querySelectorAll('#summary th'))"
                          ".map(function(h){return h.textContent;})")
        check(headers == ["case", "technique vs reference", "maxabs", "rmse", "psnr", "result",
                          "time (s)"], f"summary columns {headers}")
        check(page.js("document.querySelector('#summary tr[data-case=\"blend-tight\"] td.bad')"
                      " !== null"), "the failed metric is marked in the summary")
        check(page.js("[document.getElementById('blend-tight').open,"
                      "document.getElementById('exact').open]") == [True, False],
              "the failed case's card is open, a passed one closed")

        # A real click on the passed case's row opens its card and scrolls to it.
        x, y, w, h = page.centre('#summary tr[data-case="exact"] td.what')
        page.click(x + w / 2, y + h / 2)
        end = time.time() + 10  # the hashchange event is a task of its own: wait for it
        while True:
            state = page.js("(function(){var c=document.getElementById('exact');"
                            "var r=c.getBoundingClientRect();return [location.hash,c.open,"
                            "c.classList.contains('selected'),Math.round(r.top),innerHeight,"
                            "scrollY];})()")
            if (state[1] and state[2]) or time.time() > end:
                break
            time.sleep(0.1)
        # The last card cannot scroll to the very top: in view and the page scrolled to it.
        check(state[0] == "#exact" and state[1] and state[2] and 0 <= state[3] < state[4] / 2
              and state[5] > 0,
              f"a click on row 'exact' opens, selects and scrolls to its card [{state}]")

        # A click on the render flips it to the reference and back.
        sel = "#wboit img.flip"
        page.js("document.getElementById('wboit').open = true")
        x, y, w, h = page.centre(sel)
        src = "document.querySelector('#wboit img.flip').getAttribute('src')"
        before = page.js(src)
        page.click(x + w / 2, y + h / 2)
        after = page.js(src)
        shown = page.js("document.querySelector('#wboit .shown').textContent")
        page.click(x + w / 2, y + h / 2)
        again = page.js(src)
        check(before == "images/wboit-render.png" and after == "images/wboit-reference.png"
              and shown == "reference" and again == before,
              f"a click flips render / reference ({before} -> {after} -> {again})")

        # The mouse over the heat map puts that pixel at the magnifiers' centre.
        x, y, w, h = page.centre("#wboit img.heat")
        px, py = 10, 20  # of 40x30
        page.mouse("mouseMoved", x + (px + 0.5) * w / 40, y + (py + 0.5) * h / 30)
        loupe = page.js("(function(){var l=document.querySelectorAll('#wboit .loupe');"
                        "return Array.from(l).map(function(e){return [e.style.backgroundPosition,"
                        "e.style.backgroundSize,e.dataset.src];}).concat("
                        "[document.querySelector('#wboit .where').textContent]);})()")
        # Zoom 8, loupes 160 px wide (border excluded: clientWidth 160): centre 80 - (x+.5)*8.
        expect = f"{80 - (px + 0.5) * 8:g}px {80 - (py + 0.5) * 8:g}px"
        check(len(loupe) == 4 and all(l[0] == expect and l[1] == "320px 240px" for l in loupe[:3])
              and [l[2] for l in loupe[:3]] == ["images/wboit-render.png",
                                                "images/wboit-reference.png",
                                                "images/wboit-diff.png"]
              and loupe[3].startswith(f"pixel ({px}, {py})"),
              f"the magnifiers follow the mouse to pixel ({px}, {py}) [{loupe}]")

        # Every heat map has a colour bar from 0 to its case's scale, ramp from the stops.
        bars = page.js("Array.from(document.querySelectorAll('details.case')).map(function(c){"
                       "var b=c.querySelector('.cbar');return [c.id, b ? Array.from("
                       "b.querySelectorAll('.tick')).map(function(t){return t.textContent;}) "
                       ": null, b ? getComputedStyle(b.querySelector('.ramp')).backgroundImage"
                       " : ''];})")
        for name, ticks, ramp in bars:
            scale = scales[name]
            ok = (ticks is not None and len(ticks) == 3 and float(ticks[0]) == 0.0 and
                  abs(float(ticks[2]) - scale) <= 1e-4 * max(scale, 1e-12) and
                  abs(float(ticks[1]) - scale / 2) <= 1e-4 * max(scale, 1e-12) and
                  "rgb(26, 26, 204) 25%" in ramp and "rgb(255, 255, 255) 100%" in ramp)
            check(ok, f"case {name}: colour bar 0..{scale} ({ticks}, {ramp[:60]}...)")

        # A screenshot of the page with the 'exact' card selected, to look at.
        page.js("document.getElementById('wboit').scrollIntoView({block:'start'})")
        page.mouse("mouseMoved", x + (px + 0.5) * w / 40, y + (py + 0.5) * h / 30)
        shot = page.call("Page.captureScreenshot", format="png")
        open(os.path.join(out, "report.png"), "wb").write(base64.b64decode(shot["data"]))
        page.js("window.scrollTo(0, 0)")
        shot = page.call("Page.captureScreenshot", format="png")
        open(os.path.join(out, "report-top.png"), "wb").write(base64.b64decode(shot["data"]))
    except (RuntimeError, OSError, StopIteration, KeyError, ValueError) as e:
        failures.append(str(e))
        print(f"FAIL {e}")
    finally:
        if proc:
            proc.kill()
            proc.wait()
        shutil.rmtree(profile, ignore_errors=True)
    if failures:
        print(f"{len(failures)} check(s) failed; report in {report}", file=sys.stderr)
        return 1
    print(f"all checks passed; screenshots in {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
