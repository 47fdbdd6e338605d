"""`Result.animate`: the run's animation, from the frames `simulate` recorded as it ran,
written as the page or the glTF binary that `flexmbd animate` writes, and shown inline."""

import base64
import html.parser
import json
import os
import pickle
import re
import struct

import numpy as np
import pytest

import flexmbd
from conftest import model


def glb_chunks(glb):
    """The JSON document and the length of the BIN chunk of a glTF binary, its header
    checked (magic, version 2, total length)."""
    magic, version, length = struct.unpack_from("<4sII", glb, 0)
    assert (magic, version, length) == (b"glTF", 2, len(glb))
    json_length, kind = struct.unpack_from("<I4s", glb, 12)
    assert kind == b"JSON"
    document = json.loads(glb[20:20 + json_length])
    bin_length, kind = struct.unpack_from("<I4s", glb, 20 + json_length)
    assert kind == b"BIN\0"
    return document, bin_length


def embedded_glb(page):
    """The glTF binary that a page embeds (its `const GLB = "…"` in base64)."""
    found = re.search(r'const GLB = "([A-Za-z0-9+/=]+)";', page)
    assert found, "the page embeds a glb"
    return base64.b64decode(found.group(1))


class Elements(html.parser.HTMLParser):
    """The start tags of a page, as a browser's tokenizer reads them."""

    def __init__(self):
        super().__init__()
        self.tags = []

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)


@pytest.fixture(scope="module")
def four_bar():
    """The double four-bar with its five bars flexible, run for 0.5 s."""
    return flexmbd.simulate(model("double_four_bar.ron"), duration=0.5,
                            sets={f"bodies.{b}.flexible": True
                                  for b in ["crank1", "coupler1", "crank2", "coupler2", "crank3"]})


def test_recording_leaves_the_rows_bit_for_bit(four_bar):
    without = flexmbd.simulate(model("double_four_bar.ron"), duration=0.5, animation_fps=None,
                               sets={f"bodies.{b}.flexible": True
                                     for b in ["crank1", "coupler1", "crank2", "coupler2", "crank3"]})
    assert four_bar.status == without.status == "ok"
    assert np.array_equal(four_bar.data.view(np.int64), without.data.view(np.int64))


def test_html_is_a_page_embedding_the_runs_glb(four_bar, tmp_path):
    out = tmp_path / "run.html"
    animation = four_bar.animate(out, scale=10)
    page = out.read_text(encoding="utf-8")
    assert page == animation.html and animation.path == str(out)
    assert page.startswith("<!DOCTYPE html>")
    parser = Elements()
    parser.feed(page)
    assert {"html", "head", "body", "script"} <= set(parser.tags)
    glb = embedded_glb(page)
    assert glb == animation.glb
    document, _ = glb_chunks(glb)
    assert {n["name"] for n in document["nodes"]} >= {"crank1", "coupler1", "crank2",
                                                      "coupler2", "crank3"}
    # Each flexible bar's morph-target weights are its modal coordinates times the scale.
    assert sum("targets" in p for m in document["meshes"] for p in m["primitives"]) == 5
    assert document["asset"]["extras"]["flexmbd"]["status"] == "ok"


def test_frames_are_the_runs_rows_at_60_per_second(four_bar):
    times = four_bar.animate().times
    # the first row at or past each k / 60 s (half a step's tolerance), and the last row
    h, t = four_bar.summary["step"], four_bar.t
    expected = sorted({t[np.argmax(t >= k / 60 - h / 2)] for k in range(31)} | {t[-1]})
    assert times == expected


def test_glb_is_written_whole(four_bar, tmp_path):
    out = tmp_path / "run.glb"
    animation = four_bar.animate(out)
    data = out.read_bytes()
    glb_chunks(data)
    assert data == animation.glb
    assert os.listdir(tmp_path) == ["run.glb"]  # no temporary file left


def test_jupyter_shows_the_page_in_an_iframe(four_bar):
    shown = four_bar.animate()._repr_html_()
    assert shown.startswith("<iframe") and 'srcdoc="&lt;!DOCTYPE html&gt;' in shown
    # the page is one attribute: no raw quote or tag of it escapes the iframe
    assert shown.count('"') == shown.count('="') * 2 and shown.count("<") == 2


def test_bad_paths_and_scales_are_clear_exceptions(four_bar, tmp_path):
    missing = tmp_path / "no such folder" / "run.html"
    with pytest.raises(FileNotFoundError) as e:
        four_bar.animate(missing)
    assert e.value.filename == str(missing) and "cannot be written" in str(e.value)
    folder = tmp_path / "folder.html"
    folder.mkdir()
    with pytest.raises(IsADirectoryError):
        four_bar.animate(folder)
    with pytest.raises(ValueError, match=r"run\.txt: an animation is written as \.glb"):
        four_bar.animate(tmp_path / "run.txt")
    with pytest.raises(ValueError, match="deformation scale nan: must be a finite number"):
        four_bar.animate(tmp_path / "run.html", scale=float("nan"))
    assert sorted(os.listdir(tmp_path)) == ["folder.html"] and not os.listdir(folder)


def test_a_result_without_frames_says_so(four_bar):
    unpickled = pickle.loads(pickle.dumps(four_bar))
    assert np.array_equal(unpickled.data, four_bar.data)
    with pytest.raises(flexmbd.FlexmbdError, match="no animation frames"):
        unpickled.animate()
    with pytest.raises(ValueError, match="frames per second"):
        flexmbd.simulate(model("double_four_bar.ron"), animation_fps=0.0)


def test_a_failed_run_is_animated_up_to_its_failure_and_marked():
    # The four-bar's first singular passage defeats a 0.3 s step (as in test_simulate).
    result = flexmbd.simulate(model("double_four_bar.ron"), step=0.3,
                              sets={"solver.output_interval": 0.3})
    assert result.status == "failed"
    animation = result.animate()
    assert animation.times == list(result.t)  # every row up to the last good state
    document, _ = glb_chunks(animation.glb)
    marked = document["asset"]["extras"]["flexmbd"]
    assert marked["status"] == "failed" and marked["failed_at"] == result.failed_at
    assert "failed" in document["animations"][0]["name"]
