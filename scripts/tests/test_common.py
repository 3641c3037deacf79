"""Tests of scripts/common, the helpers shared by the scripts (atomic writing, JSON with
comments, JSON-safe values, the figure folder, paths, the git commit), and of the way
each entry point finds them.

Run with Debian's interpreter: /usr/bin/python3 -m pytest -q scripts/tests
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

SCRIPTS = Path(__file__).resolve().parent.parent
REPO = SCRIPTS.parent
sys.path.insert(0, str(SCRIPTS))

from common import fsutil, gitinfo, jsonc, jsonsafe, paths  # noqa: E402
from common.figures import figure_caption, save_figure  # noqa: E402

PYTHON = "/usr/bin/python3"


# ------------------------------------------------------------------------ fsutil --

def test_write_atomic_is_the_package_s(tmp_path):
    from ratchet import files
    assert fsutil.write_atomic is files.write_atomic  # one implementation for the package and the harness


def test_write_atomic_writes_text_as_utf8_and_bytes_unchanged(tmp_path):
    text = tmp_path / "a.txt"
    fsutil.write_atomic(text, "θ_c = 6°\n")
    assert text.read_bytes() == "θ_c = 6°\n".encode("utf-8")
    raw = tmp_path / "b.bin"
    fsutil.write_atomic(str(raw), b"\x00\xff\r\n")
    assert raw.read_bytes() == b"\x00\xff\r\n"


def test_write_atomic_creates_the_folder_and_replaces_the_file(tmp_path):
    target = tmp_path / "new" / "deeper" / "f.txt"
    fsutil.write_atomic(target, "one\n")
    fsutil.write_atomic(target, "two\n")
    assert target.read_text() == "two\n"
    assert sorted(p.name for p in target.parent.iterdir()) == ["f.txt"]


def test_write_atomic_gives_the_usual_file_mode(tmp_path):
    old = os.umask(0o027)
    try:
        fsutil.write_atomic(tmp_path / "f.txt", "x")
    finally:
        os.umask(old)
    # Not the 0600 of a temporary file: 0666 less the umask.
    assert stat.S_IMODE((tmp_path / "f.txt").stat().st_mode) == 0o640


def test_failed_replace_leaves_the_old_file_and_no_temporary_file(tmp_path, monkeypatch):
    target = tmp_path / "report.md"
    target.write_text("old\n")

    def broken_replace(src, dst):
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", broken_replace)
    with pytest.raises(OSError, match="disk full"):
        fsutil.write_atomic(target, "new\n")
    assert [p.name for p in tmp_path.iterdir()] == ["report.md"]
    assert target.read_text() == "old\n"


def test_failure_while_writing_leaves_no_partial_file(tmp_path, monkeypatch):
    def broken_fsync(fd):
        raise OSError("I/O error")

    monkeypatch.setattr(os, "fsync", broken_fsync)
    with pytest.raises(OSError, match="I/O error"):
        fsutil.write_atomic(tmp_path / "data.csv", "a,b\n" * 1000)
    assert list(tmp_path.iterdir()) == []


def test_write_atomic_refuses_other_content_before_writing(tmp_path):
    with pytest.raises(TypeError, match="str or bytes"):
        fsutil.write_atomic(tmp_path / "f.json", {"a": 1})
    assert list(tmp_path.iterdir()) == []


def test_write_csv_atomic_keeps_every_digit_and_no_index(tmp_path):
    df = pd.DataFrame({"t": [0.1 + 0.2, 1.0 / 3.0], "n": [1, 2]})
    path = tmp_path / "x.csv"
    fsutil.write_csv_atomic(df, path)
    lines = path.read_text().splitlines()
    assert lines[0] == "t,n"
    assert [float(line.split(",")[0]) for line in lines[1:]] == [0.1 + 0.2, 1.0 / 3.0]  # bit for bit


def _figure():
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    fig = Figure(figsize=(1, 1))
    fig.add_subplot().plot([0, 1], [1, 0])
    return fig


def test_save_figure_atomic_writes_a_png(tmp_path):
    path = tmp_path / "f.png"
    fsutil.save_figure_atomic(_figure(), path, dpi=50)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir()] == ["f.png"]


@pytest.mark.parametrize("name, magic", [("f.pdf", b"%PDF-"), ("F.SVG", b"<?xml"), ("f.png", b"\x89PNG")])
def test_save_figure_atomic_takes_the_format_from_the_extension(tmp_path, name, magic):
    path = tmp_path / name
    fsutil.save_figure_atomic(_figure(), path, dpi=50)
    data = path.read_bytes()
    assert data.startswith(magic)
    if name.lower().endswith(".svg"):
        assert b"<svg" in data[:2000]
    assert [p.name for p in tmp_path.iterdir()] == [name]


@pytest.mark.parametrize("name", ["f.jpg", "f", "f.png.txt"])
def test_save_figure_atomic_refuses_an_unknown_extension_and_writes_nothing(tmp_path, name):
    with pytest.raises(ValueError, match=r"expected a figure file name ending in \.png, \.pdf, \.svg"):
        fsutil.save_figure_atomic(_figure(), tmp_path / name)
    assert list(tmp_path.iterdir()) == []


# ----------------------------------------------------------------------- figures --

def test_save_figure_writes_png_and_caption_in_the_figures_folder(tmp_path):
    png = save_figure(_figure(), tmp_path, "wall pressure", caption="P(t)  over\ntwo cycles")
    assert png == tmp_path / "figures" / "wall pressure.png"
    assert png.read_bytes()[:4] == b"\x89PNG"
    assert sorted(p.name for p in png.parent.iterdir()) == ["wall pressure.png", "wall pressure.txt"]
    assert figure_caption(png) == "P(t) over two cycles"  # white space folded


def test_figure_caption_falls_back_to_the_file_name(tmp_path):
    png = tmp_path / "v.png"
    png.write_bytes(b"")
    assert figure_caption(png) == "v.png"
    (tmp_path / "v.txt").write_text("  \n")
    assert figure_caption(png) == "v.png"


# ------------------------------------------------------------------------- jsonc --

def test_comments_are_removed_outside_strings():
    text = '{"a": 1, // one\n /* two */ "b": 2}'
    assert json.loads(jsonc.strip_json_comments(text)) == {"a": 1, "b": 2}


def test_strings_containing_comment_markers_are_kept():
    text = '{"url": "http://example.org/x", "c": "a /* b */ c", "d": "// d"} // end'
    assert json.loads(jsonc.strip_json_comments(text)) == {
        "url": "http://example.org/x", "c": "a /* b */ c", "d": "// d"}


def test_escaped_quotes_and_backslashes_do_not_end_a_string_early():
    # "say \"// hi\"" holds an escaped quote; "dir\\" ends with an escaped backslash,
    # so the // after it starts a real comment.
    text = '["say \\"// hi\\"", "dir\\\\" // comment\n]'
    assert json.loads(jsonc.strip_json_comments(text)) == ['say "// hi"', "dir\\"]


def test_line_numbers_are_kept_and_block_comments_still_separate_tokens():
    text = '{\n"a": 1, // x\n/* y\n */ "b": 2\n}'
    out = jsonc.strip_json_comments(text)
    assert out.splitlines()[1].rstrip() == '"a": 1,'  # the // comment's newline stays
    assert jsonc.strip_json_comments("1/**/2") == "1 2"  # not "12"
    assert jsonc.strip_json_comments("[1] // no newline at the end") == "[1] "


def test_unterminated_block_comment_is_an_error():
    with pytest.raises(ValueError, match="unterminated"):
        jsonc.strip_json_comments('{"a": 1 /* open')


def test_load_json_with_comments_reads_a_file(tmp_path):
    p = tmp_path / "scene.json"
    p.write_text('// a scene\n{"name": "bed", /* seed */ "seed": 7, "note": "r ≤ 1"}\n',
                 encoding="utf-8")
    assert jsonc.load_json_with_comments(p) == {"name": "bed", "seed": 7, "note": "r ≤ 1"}
    p.write_text('{"name": "bed",}')
    with pytest.raises(ValueError):
        jsonc.load_json_with_comments(p)
    with pytest.raises(OSError):
        jsonc.load_json_with_comments(tmp_path / "missing.json")


def test_every_scene_of_the_repository_reads(tmp_path):
    scenes = [p for folder in ("validation", "golden") for p in (REPO / folder).rglob("*.json")
              if "manifest" not in p.name]
    assert scenes
    for p in scenes:
        assert isinstance(jsonc.load_json_with_comments(p), (dict, list)), p


# ---------------------------------------------------------------------- jsonsafe --

def test_plain_makes_numpy_and_pandas_values_json_ready():
    value = {1: np.float64(0.5), "n": np.int64(3), "ok": np.bool_(True), "bad": math.nan,
             "big": -math.inf, "arr": np.array([1.0, np.nan]), "t": (1, 2), "p": Path("a/b"),
             "df": pd.DataFrame({"x": [1.5, np.nan]})}
    out = jsonsafe.plain(value)
    assert out == {"1": 0.5, "n": 3, "ok": True, "bad": None, "big": None, "arr": [1.0, None],
                   "t": [1, 2], "p": "a/b", "df": [{"x": 1.5}, {"x": None}]}
    assert type(out["n"]) is int and type(out["ok"]) is bool and type(out["1"]) is float


def test_dumps_never_writes_nan():
    text = jsonsafe.dumps({"a": np.float32("nan"), "b": [np.inf]})
    assert text.endswith("\n") and "NaN" not in text and "Infinity" not in text
    assert json.loads(text) == {"a": None, "b": [None]}


# ------------------------------------------------------------------------- paths --

def test_engine_binary_prefers_ratchet_bin_then_the_build_folder(monkeypatch, tmp_path):
    assert (paths.REPO_ROOT / "scripts" / "common" / "paths.py").is_file()
    monkeypatch.setenv("RATCHET_BIN", str(tmp_path / "my_ratchet"))
    assert paths.engine_binary() == tmp_path / "my_ratchet"
    monkeypatch.setenv("RATCHET_BIN", "")  # empty counts as unset
    monkeypatch.setenv("RATCHET_BUILD_DIR", "build-dbg")
    assert paths.engine_binary() == paths.REPO_ROOT / "build-dbg" / "reference_engine" / "ratchet"
    monkeypatch.setenv("RATCHET_BUILD_DIR", str(tmp_path))
    assert paths.engine_binary() == tmp_path / "reference_engine" / "ratchet"
    monkeypatch.delenv("RATCHET_BUILD_DIR")
    monkeypatch.delenv("RATCHET_BIN")
    assert paths.engine_binary() == paths.REPO_ROOT / "build" / "reference_engine" / "ratchet"


# ----------------------------------------------------------------------- gitinfo --

@pytest.mark.skipif(shutil.which("git") is None, reason="git is not installed")
def test_git_commit_and_dirty_state(tmp_path):
    assert gitinfo.git_commit(tmp_path) == (None, False)  # not a checkout

    def git(*args):
        subprocess.run(["git", "-C", str(tmp_path), "-c", "user.name=t", "-c", "user.email=t@t",
                        *args], check=True, capture_output=True)

    git("init", "-q")
    (tmp_path / "f.txt").write_text("1\n")
    git("add", "f.txt")
    git("commit", "-q", "-m", "one")
    commit, dirty = gitinfo.git_commit(tmp_path)
    assert re.fullmatch(r"[0-9a-f]{40}", commit) and not dirty
    assert gitinfo.git_commit(tmp_path, short=12) == (commit[:12], False)
    (tmp_path / "untracked.txt").write_text("x\n")
    assert gitinfo.git_commit(tmp_path) == (commit, False)  # untracked files do not count
    (tmp_path / "f.txt").write_text("2\n")
    assert gitinfo.git_commit(tmp_path) == (commit, True)


# ------------------------------------------------------- one copy, found by all --

def _python_sources():
    files = [p for p in SCRIPTS.rglob("*.py") if "tests" not in p.parts]
    files += [SCRIPTS / "trends", SCRIPTS / "compare-methods", SCRIPTS / "compare-settings", SCRIPTS / "accuracy-pareto", SCRIPTS / "method-cost",
              SCRIPTS / "plot-run", SCRIPTS / "plot-sweep", SCRIPTS / "bench-cycled", SCRIPTS / "campaign",
              SCRIPTS / "paper-repro", REPO / "regression" / "run"]
    files += list((REPO / "regression").glob("*.py")) + list((REPO / "validation").rglob("*.py"))
    files += list(PACKAGE.glob("*.py"))
    return files


#: The Python package ratchet, and its module that is the one home of write_atomic.
PACKAGE = REPO / "reference_engine" / "python" / "ratchet"
PACKAGE_FILES = PACKAGE / "files.py"


def test_shared_helpers_are_defined_only_in_common():
    pattern = re.compile(r"^\s*def (write_atomic|write_csv_atomic|save_figure_atomic|save_figure|"
                         r"figure_caption|strip_json_comments|strip_comments|plain|dumps|md_cell)\b|"
                         r"mkstemp|\.partial\"|importlib", re.M)
    offenders = []
    for path in _python_sources():
        if SCRIPTS / "common" in path.parents or path == PACKAGE_FILES:
            continue
        for m in pattern.finditer(path.read_text(encoding="utf-8")):
            line = path.read_text(encoding="utf-8").count("\n", 0, m.start()) + 1
            offenders.append(f"{path.relative_to(REPO)}:{line}: {m.group(0).strip()}")
    assert offenders == []


@pytest.mark.parametrize("command", [
    ["scripts/trends", "--help"],
    ["scripts/campaign", "--help"],
    ["scripts/paper-repro", "--help"],
    ["scripts/plot-run", "--help"],
    ["scripts/plot-sweep", "--help"],
    ["scripts/compare-methods", "--help"],
    ["scripts/report.py", "--help"],
    ["scripts/liggghts/parse.py", "--help"],
    ["scripts/liggghts/translate.py", "--help"],
    ["regression/run", "--help"],
    ["regression/make_compare_vectors.py", "--check"],
    ["validation/liggghts/check.py", "--help"],
], ids=lambda c: c[0])
def test_every_entry_point_finds_common_from_any_folder(command, tmp_path):
    # Started from elsewhere, each entry point must still put scripts/ on its path.
    done = subprocess.run([PYTHON, str(REPO / command[0]), *command[1:]], cwd=tmp_path,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "usage:" in done.stdout or "up to date" in done.stdout
    assert "Traceback" not in done.stderr
