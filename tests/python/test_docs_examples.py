"""Every ```python block of docs/python.md runs: in order, in one namespace (a block may use
what an earlier one made, as a reader would), in a temporary folder that holds a link to the
checkout's datasets/, so what the examples write stays there."""

import contextlib
import io
import re

import pytest

from conftest import ROOT

DOC = ROOT / "docs" / "python.md"


def python_blocks(text):
    """(first line number, code) of each ```python ... ``` block."""
    blocks = []
    for m in re.finditer(r"^```python\n(.*?)^```", text, flags=re.S | re.M):
        line = text.count("\n", 0, m.start()) + 2
        blocks.append((line, m.group(1)))
    return blocks


def test_the_page_has_examples():
    blocks = python_blocks(DOC.read_text())
    assert len(blocks) >= 3 and "veil.Renderer()" in blocks[0][1]


def test_docs_examples_run(tmp_path, monkeypatch):
    (tmp_path / "datasets").symlink_to(ROOT / "datasets")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("VEIL_TEST_OUTPUT", str(tmp_path / "failures"))
    namespace = {"__name__": "docs_python_md"}
    printed = io.StringIO()
    for line, code in python_blocks(DOC.read_text()):
        # Blank lines in front keep the page's line numbers in a traceback.
        compiled = compile("\n" * (line - 1) + code, str(DOC), "exec")
        with contextlib.redirect_stdout(printed):
            try:
                exec(compiled, namespace)
            except Exception as e:  # noqa: BLE001: name the block, keep the traceback
                pytest.fail(f"docs/python.md block at line {line} raised "
                            f"{type(e).__name__}: {e}")
    # What the examples print is what the page says they print.
    out = printed.getvalue()
    assert re.search(r"<veil\.Frame 160x90 oit=blend shadows=moment [0-9.]+ ms>", out), out
    assert "cannot open scene file 'no-such-scene.json': no such file" in out
    assert "widht" in out and "unknown key" in out
    # Everything the examples wrote is inside the temporary folder.
    assert {p.name for p in tmp_path.iterdir()} >= {"x.exr", "smoke.vti", "teapot.vdb"}
