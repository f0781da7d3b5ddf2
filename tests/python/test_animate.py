"""Seeing the mechanism move from Python: `Model.graphics` lists each GRAPHICS statement
with the values its dataset text writes (the truth is that text, written here), and
`Run.animate()` gives the run's glTF binary (read back with `struct` and `json` as the
glTF 2.0 specification lays it out; equal to `mbfx run --animate`'s) and its
self-contained page, inline in Jupyter through an iframe's `srcdoc` (drawn in headless
Chromium as the page itself is)."""

from __future__ import annotations

import html
import json
import math
import pickle
import re
import struct
import subprocess
from pathlib import Path
from typing import Dict, List

import numpy as np
import pytest

import mbfx
from conftest import ROOT, run_cli

FAILURES = ROOT / "tests" / "models" / "failures"

# Ground, a moving part 2 and the markers every graphic below is placed by; SFORCE/5 is
# the element a FORCE graphic draws, CURVE/7 the curve a CURVE graphic draws.
BASE = """graphics of every kind (tests/python/test_animate.py)
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
ACCGRAV/JGRAV = -9.80665
PART/1, GROUND
MARKER/10, PART = 1
MARKER/11, PART = 1, QP = 1, 0, 0
PART/2, MASS = 1, CM = 20, IP = 0.1, 0.1, 0.1
MARKER/20, PART = 2, QP = 0, -1, 0
MARKER/21, PART = 2, QP = 0, -1.5, 0
MARKER/22, PART = 2
JOINT/1, REVOLUTE, I = 22, J = 10
SFORCE/5, TRANSLATION, I = 20, J = 11, FUNCTION = 0
CURVE/7, CURVE_POINTS, MATRIX = 70
MATRIX/70, FULL = RORDER, ROWS = 4, COLUMNS = 3, VALUES = 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0
"""

D = math.pi / 180
# Each statement as a dataset writes it, with the graphic that text describes: kind,
# view name, part, placing markers, and the kind's arguments (None where not written).
GRAPHICS = [
    (
        "!   adams_view_name='rod'\n"
        "GRAPHICS/1, CYLINDER, CM = 20, LENGTH = -2.5, RADIUS = 0.25, SIDES = 12, SEG = 24, RANGLE = 90D",
        ("CYLINDER", "rod", 2, [20]),
        dict(cm=20, length=-2.5, radius=0.25, rm=None, sides=12, seg=24, rangle=90 * D),
    ),
    (
        "GRAPHICS/2, CYL, CM = 21, LEN = 1, RM = 20",
        ("CYLINDER", None, 2, [21]),
        dict(cm=21, length=1.0, radius=None, rm=20, sides=None, seg=None, rangle=None),
    ),
    (
        "GRAPHICS/3, BOX, CORNER = 10, X = 0.5, Y = -50, Z = 2E-1",
        ("BOX", None, 1, [10]),
        dict(corner=10, x=0.5, y=-50.0, z=0.2),
    ),
    (
        "GRAPHICS/4, FRUSTUM, CM = 20, LENGTH = 3, TOP = 0.1, BOTTOM = 0.3, SIDES = 6",
        ("FRUSTUM", None, 2, [20]),
        dict(cm=20, length=3.0, top=0.1, bottom=0.3, sides=6, seg=None, rangle=None),
    ),
    (
        "GRAPHICS/5, ELLIPSOID, CM = 22, XSCALE = 1, YSCALE = 2, ZSCALE = 0.5",
        ("ELLIPSOID", None, 2, [22]),
        dict(cm=22, xscale=1.0, yscale=2.0, zscale=0.5),
    ),
    (
        "GRAPHICS/6, CIRCLE, CM = 11, RADIUS = 0.75, SEG = 40",
        ("CIRCLE", None, 1, [11]),
        dict(cm=11, radius=0.75, rm=None, seg=40),
    ),
    (
        "GRAPHICS/7, ARC, CM = 20, RADIUS = 2, RANGLE = 45D",
        ("ARC", None, 2, [20]),
        dict(cm=20, radius=2.0, rm=None, rangle=45 * D, seg=None),
    ),
    (
        "GRAPHICS/8, OUTLINE = 10, 20, 21, 10",
        ("OUTLINE", None, 1, [10, 20, 21, 10]),
        dict(outline=[10, 20, 21, 10]),
    ),
    (
        "GRAPHICS/9\n, SPDP\n, I = 20\n, J = 11\n, COILS = 10\n, DA = 0.4",
        ("SPDP", None, 2, [20, 11]),
        dict(i=20, j=11, coils=10, da=0.4, db=None, dc=None, lc=None, ld=None),
    ),
    (
        "GRAPHICS/10, FORCE, ETYPE = SFORCE, EID = 5, EMARKER = 20",
        ("FORCE", None, 2, [20]),
        dict(etype="SFORCE", eid=5, emarker=20),
    ),
    (
        "GRAPHICS/11, CURVE, CID = 7, CRM = 11, SEG = 16",
        ("CURVE", None, 1, [11]),
        dict(cid=7, crm=11, seg=16),
    ),
    (
        "!   adams_view_name='SHELL_12'\n"
        "GRAPHICS/12\n, EXTERNAL\n, RM = 22\n, FILE = curved_beam.xmt_txt\n, ELEMENT = SHELL_12",
        ("EXTERNAL", "SHELL_12", 2, [22]),
        dict(rm=22, file="curved_beam.xmt_txt", element="SHELL_12", faceting_tolerance=None),
    ),
]


def dataset(statements) -> str:
    return BASE + "".join(s + "\n" for s in statements) + "END\n"


# ---------------------------------------------------------------------- Model.graphics


def test_model_graphics_lists_every_statement_with_the_values_its_text_writes():
    model = mbfx.load(dataset(s for s, _, _ in GRAPHICS))
    got = model.graphics
    assert [g.id for g in got] == list(range(1, len(GRAPHICS) + 1))
    for g, (text, (kind, view_name, part, markers), values) in zip(got, GRAPHICS):
        assert isinstance(g, mbfx.Graphic)
        assert (g.kind, g.view_name, g.part, g.markers) == (kind, view_name, part, markers), text
        # The same names in the same order (docs/models.md's table), then the values.
        assert list(g.values) == list(values), text
        for name, want in values.items():
            have = g.values[name]
            if isinstance(want, float):
                assert have == pytest.approx(want, rel=1e-15, abs=0), (text, name)
            else:
                assert have == want and type(have) is type(want), (text, name)
    # Each part a graphic is drawn on is one of the model's, and so is every marker.
    assert {g.part for g in got} <= set(model.parts)
    assert {m for g in got for m in g.markers} <= set(model.markers)


def test_model_graphics_is_empty_without_graphics_and_a_new_list_each_time():
    model = mbfx.load(dataset([]))
    assert model.graphics == []
    model = mbfx.load(dataset([GRAPHICS[2][0]]))
    first = model.graphics
    first.clear()
    assert len(model.graphics) == 1


def test_model_graphics_repr_names_the_kind_and_what_is_written():
    (g,) = mbfx.load(dataset([GRAPHICS[5][0]])).graphics
    assert repr(g) == "mbfx.Graphic(6, CIRCLE, part=1, cm=11, radius=0.75, seg=40)"


def test_a_graphic_on_an_unknown_marker_is_a_check_error_at_its_line():
    text = dataset(["GRAPHICS/1, CYLINDER, CM = 99, LENGTH = 1, RADIUS = 1"])
    with pytest.raises(mbfx.CheckError) as e:
        mbfx.load(text)
    (d,) = [d for d in e.value.diagnostics if d.severity == "error"]
    assert d.code == "E0311"
    assert d.line == text.splitlines().index("GRAPHICS/1, CYLINDER, CM = 99, LENGTH = 1, RADIUS = 1") + 1


# ------------------------------------------------------------------------ Run.animate

# A pendulum of length 1 swinging from horizontal about ground's z axis, a cylinder on it
# and a box on ground; the rod part 3 hangs below it on a second pin (two moving parts).
PENDULUM = """Double pendulum with graphics (tests/python/test_animate.py)
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
ACCGRAV/JGRAV = -9.80665
PART/1, GROUND
MARKER/10, PART = 1
PART/2, MASS = 1, CM = 20, IP = 0.1, 0.1, 0.1
MARKER/20, PART = 2, QP = 0.5, 0, 0
MARKER/21, PART = 2
MARKER/22, PART = 2, QP = 1, 0, 0
MARKER/23, PART = 2, REULER = 90D, 90D, 0D
PART/3, MASS = 1, CM = 30, IP = 0.1, 0.1, 0.1
MARKER/30, PART = 3, QP = 1, -0.5, 0
MARKER/31, PART = 3, QP = 1, 0, 0
JOINT/1, REVOLUTE, I = 21, J = 10
JOINT/2, REVOLUTE, I = 31, J = 22
GRAPHICS/1, CYLINDER, CM = 23, LENGTH = 1, RADIUS = 0.05
GRAPHICS/2, BOX, CORNER = 10, X = 0.1, Y = 0.1, Z = 0.1
GRAPHICS/3, ELLIPSOID, CM = 30, XSCALE = 0.1, YSCALE = 0.5, ZSCALE = 0.1
END
"""

GLB_MAGIC, JSON_CHUNK, BIN_CHUNK = 0x46546C67, 0x4E4F534A, 0x004E4942


def gltf_json(glb: bytes) -> dict:
    """The JSON chunk of a glTF binary, read as the glTF 2.0 specification lays it out
    (section "Binary glTF Layout"): a 12-byte header (magic, version 2, total length),
    then chunks of (length, type, data), the JSON chunk first and 4-byte aligned."""
    magic, version, length = struct.unpack_from("<III", glb, 0)
    assert (magic, version, length) == (GLB_MAGIC, 2, len(glb))
    chunk_length, chunk_type = struct.unpack_from("<II", glb, 12)
    assert chunk_type == JSON_CHUNK and chunk_length % 4 == 0
    doc = json.loads(glb[20 : 20 + chunk_length].decode("utf-8"))
    rest = 20 + chunk_length
    if rest < len(glb):
        bin_length, bin_type = struct.unpack_from("<II", glb, rest)
        assert bin_type == BIN_CHUNK and rest + 8 + bin_length == len(glb)
    return doc


def key_times(doc: dict) -> List[int]:
    """The input accessor count of every sampler of the animation named `run`."""
    (anim,) = [a for a in doc["animations"] if a.get("name") == "run"]
    return sorted({doc["accessors"][s["input"]]["count"] for s in anim["samplers"]})


@pytest.fixture(scope="module")
def pendulum_run():
    return mbfx.load(PENDULUM).run(1.0, output_step=0.02)


def test_animate_gives_a_glb_with_a_node_per_part_and_a_key_per_row(pendulum_run):
    model = mbfx.load(PENDULUM)
    anim = pendulum_run.animate()
    assert isinstance(anim, mbfx.Animation)
    glb = anim.glb()
    assert glb[:4] == b"glTF"
    doc = gltf_json(glb)
    names = [n.get("name") for n in doc["nodes"]]
    for part in model.parts:
        assert names.count(f"PART/{part}") == 1, names
    # A frame at each output row: 0 to 1 s every 0.02 s.
    assert len(pendulum_run) == 51
    assert anim.frames == 51
    assert key_times(doc) == [51]


def test_animate_at_a_frame_rate_runs_again_and_leaves_the_rows(pendulum_run):
    rows = pendulum_run.data.copy()
    anim = pendulum_run.animate(fps=30)
    # 0 to 1 s at 1/30 s: 31 frames, whatever the output step.
    assert (anim.frames, anim.fps) == (31, 30.0)
    assert key_times(gltf_json(anim.glb())) == [31]
    assert np.array_equal(pendulum_run.data, rows)
    # The recorded animation is untouched.
    assert pendulum_run.animate().frames == 51


def test_repr_html_is_an_iframe_whose_srcdoc_unescapes_to_the_page(pendulum_run):
    anim = pendulum_run.animate()
    page = anim.html()
    assert page.lstrip().lower().startswith("<!doctype html")
    shown = anim._repr_html_()
    m = re.fullmatch(r'<iframe srcdoc="([^"]*)"([^>]*)></iframe>', shown)
    assert m, shown[:200]
    assert html.unescape(m.group(1)) == page
    # Nothing in the attribute could end it or open a tag of the notebook's page.
    assert "<" not in m.group(1) and ">" not in m.group(1)
    assert re.search(r"height: *\d+px", m.group(2))


def test_save_writes_either_format_by_suffix_and_refuses_others(pendulum_run, tmp_path):
    anim = pendulum_run.animate()
    assert anim.save(tmp_path / "swing.glb").read_bytes() == anim.glb()
    assert (tmp_path / "swing.html").exists() is False
    anim.save(str(tmp_path / "swing.html"))
    assert (tmp_path / "swing.html").read_text(encoding="utf-8") == anim.html()
    for bad in ("swing.gltf", "swing.png", "swing"):
        with pytest.raises(ValueError, match=r"\.html or \.glb"):
            anim.save(tmp_path / bad)
        assert not (tmp_path / bad).exists()


def test_a_pickled_run_keeps_its_rows_and_says_its_animation_stayed_behind(pendulum_run):
    back = pickle.loads(pickle.dumps(pendulum_run))
    assert np.array_equal(back.data, pendulum_run.data)
    with pytest.raises(mbfx.MbfxError, match="another process"):
        back.animate()


def test_a_failed_run_animates_the_rows_it_kept():
    with pytest.raises(mbfx.RunError) as caught:
        mbfx.load(FAILURES / "nan_in_force.adm", dim=3).run(
            1.0, output_step=0.01, fixed_step=1e-3, animation=True
        )
    partial = caught.value.run
    # 0 to 0.5 s every 0.01 s before the force turns NaN (test_model.py's figures).
    assert len(partial) == 51
    anim = partial.animate()
    assert anim.frames == 51 and key_times(gltf_json(anim.glb())) == [51]


def test_animation_false_records_nothing_and_animate_says_so():
    run = mbfx.load(PENDULUM).run(0.1, animation=False)
    assert len(run) == 101
    with pytest.raises(mbfx.MbfxError, match=r"animation=False"):
        run.animate()


@pytest.mark.parametrize("glyphs", [False, True])
def test_the_glb_is_the_command_lines_byte_for_byte(cli, tmp_path, glyphs):
    # The same run through `mbfx run --animate` (with `--glyphs`): the same scene, the
    # same frames, so the same file; animate(glyphs=) redraws the recorded frames.
    path = tmp_path / "pendulum.adm"
    path.write_text(PENDULUM, encoding="utf-8")
    out = tmp_path / "cli.glb"
    args = ["run", str(path), "--end", "1", "--output-step", "0.02", "--animate", str(out)]
    done = run_cli(*args, *(["--glyphs"] if glyphs else []))
    assert done.returncode == 0, done.stderr
    anim = mbfx.load(path).run(1.0, output_step=0.02).animate(glyphs=glyphs)
    assert anim.glyphs is glyphs
    assert anim.glb() == out.read_bytes()


def test_geometry_that_cannot_be_read_fails_the_run_naming_the_file(tmp_path):
    model = mbfx.load(dataset([GRAPHICS[11][0]]))
    missing = tmp_path / "no_such_body.stl"
    with pytest.raises(mbfx.RunError) as caught:
        model.run(0.1, geometry={12: missing})
    assert caught.value.code == "E0501" and str(missing) in str(caught.value)
    with pytest.raises(ValueError, match="GRAPHICS id"):
        model.run(0.1, geometry={"GRAPHICS/12": str(missing)})


def roles(anim: "mbfx.Animation") -> Dict[str, str]:
    """Each named node's role (`extras.mbfx.role`) in the animation's .glb."""
    doc = gltf_json(anim.glb())
    return {n["name"]: n["extras"]["mbfx"]["role"] for n in doc["nodes"] if "mbfx" in n.get("extras", {})}


def test_glyphs_are_drawn_on_every_part_only_when_asked_for(pendulum_run):
    plain, glyphs = roles(pendulum_run.animate()), roles(pendulum_run.animate(glyphs=True))
    # Every part of the pendulum has a GRAPHICS statement: no part needs glyphs.
    assert sorted(n for n, r in plain.items() if r == "graphic") == ["GRAPHICS/1", "GRAPHICS/2", "GRAPHICS/3"]
    assert "glyph" not in plain.values()
    assert {n: r for n, r in glyphs.items() if r == "graphic"} == {n: r for n, r in plain.items() if r == "graphic"}
    assert "glyph" in glyphs.values()


def test_an_external_graphic_is_drawn_from_the_mesh_given_else_as_a_placeholder(tmp_path):
    model = mbfx.load(dataset([GRAPHICS[11][0]]))
    # One triangle, (0, 0, 0), (2, 0, 0), (0, 3, 0), in the frame of RM (MARKER/22).
    obj = tmp_path / "shell.obj"
    obj.write_text("v 0 0 0\nv 2 0 0\nv 0 3 0\nf 1 2 3\n", encoding="utf-8")
    drawn = model.run(0.1, geometry={12: obj}).animate()
    assert roles(drawn)["GRAPHICS/12"] == "graphic"
    assert not any("placeholder" in n for n in drawn.notes)
    doc = gltf_json(drawn.glb())
    (node,) = [n for n in doc["nodes"] if n.get("name") == "GRAPHICS/12"]
    (prim,) = doc["meshes"][node["mesh"]]["primitives"]
    position = doc["accessors"][prim["attributes"]["POSITION"]]
    assert (position["min"], position["max"]) == ([0, 0, 0], [2, 3, 0])
    stand_in = model.run(0.1).animate()
    assert roles(stand_in)["GRAPHICS/12"] == "placeholder"
    assert any("placeholder" in n for n in stand_in.notes)


def test_a_study_records_no_animation():
    # The study's runs are reduced to responses in its workers: recording would be waste.
    from mbfx.study import execute

    job = execute.Job(0.1, {}, {}, {})
    run = execute.simulate(mbfx.load(PENDULUM), job, {})
    assert run._recording is None


@pytest.mark.parametrize("fps", [0, -30, math.inf, math.nan])
def test_a_frame_rate_that_is_not_positive_is_a_value_error(pendulum_run, fps):
    with pytest.raises(ValueError, match="fps must be a positive"):
        pendulum_run.animate(fps=fps)


# ------------------------------------------------- the iframe in a real browser

CHROMIUM = Path("/usr/bin/chromium-headless-shell")
# The notebook cell's size: the iframe's width, and its fixed height.
VIEW = (900, mbfx.animation.HEIGHT)


def screenshot(page: Path) -> np.ndarray:
    """`page` as headless Chromium draws it in a window of VIEW (RGB in [0, 1]); WebGL
    through SwiftShader, as the viewer's own tests run it."""
    if not CHROMIUM.exists():
        pytest.fail(f"{CHROMIUM} is missing: sudo apt-get install chromium-headless-shell")
    import matplotlib.image

    png = page.with_suffix(".png")
    subprocess.run(
        [str(CHROMIUM), "--no-sandbox", "--enable-unsafe-swiftshader", "--use-angle=swiftshader",
         "--hide-scrollbars", f"--window-size={VIEW[0]},{VIEW[1]}", "--virtual-time-budget=5000",
         f"--screenshot={png}", page.as_uri()],
        capture_output=True, timeout=120, check=True,
    )
    return matplotlib.image.imread(png)[:, :, :3]


def differing(a: np.ndarray, b: np.ndarray) -> float:
    """The fraction of pixels whose colours differ by more than 2 % in a channel."""
    return float((np.abs(a - b).max(axis=2) > 0.02).mean())


def test_the_iframe_in_a_notebook_draws_what_the_page_draws_with_its_scripts(tmp_path):
    anim = mbfx.load(ROOT / "examples" / "slider.adm").run(2.0, output_step=0.01).animate()
    page = anim.save(tmp_path / "page.html")
    # A notebook's output: the cell's HTML inside another page, the iframe at its corner.
    cell = tmp_path / "cell.html"
    cell.write_text(f'<!doctype html><body style="margin: 0">{anim._repr_html_()}</body>', encoding="utf-8")
    # The page with its scripts cut out: what the iframe would show if they did not run.
    inert = tmp_path / "inert.html"
    inert.write_text(re.sub(r"<script\b.*?</script\s*>", "", anim.html(), flags=re.S | re.I), encoding="utf-8")
    shots = {p.stem: screenshot(p) for p in (page, cell, inert)}
    assert differing(shots["page"], shots["inert"]) > 0.01
    assert differing(shots["cell"], shots["page"]) < 0.001


def test_a_plain_run_records_nothing_and_animate_runs_it_again():
    # Recording costs a small model's run a third: only animation=True records as it
    # runs. animate() on a plain run runs it again, and the frames come out the same.
    model = mbfx.load(PENDULUM)
    plain = model.run(1.0, output_step=0.02)
    recorded = model.run(1.0, output_step=0.02, animation=True)
    assert not plain._recording.recorded_frames
    assert recorded._recording.recorded_frames
    assert plain.animate().glb() == recorded.animate().glb()
