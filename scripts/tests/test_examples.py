"""The README's quick-start scene: the file and the README's copy of it agree, and it runs
to completion with the command the README gives."""

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from common.paths import REPO_ROOT, engine_binary  # noqa: E402

SCENE = REPO_ROOT / "validation" / "examples" / "my_bed.json"


def test_the_readme_shows_the_example_scene_as_it_is():
    readme = (REPO_ROOT / "README.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```json\n(.*?)```", readme, flags=re.S)
    shown = [json.loads(b) for b in blocks if '"name": "my_bed"' in b]
    assert shown == [json.loads(SCENE.read_text(encoding="utf-8"))]


def test_the_example_scene_runs_to_completion(tmp_path):
    binary = engine_binary()
    if not binary.exists():
        pytest.skip(f"the engine is not built ({binary})")
    out = tmp_path / "my_bed"
    # One cycle instead of two keeps the test near 2 s; the scene is otherwise as shown.
    done = subprocess.run([str(binary), "run", str(SCENE), "--out", str(out), "--quiet",
                           "--set", "thermal.cycles=1"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    meta = json.loads((out / "run.json").read_text(encoding="utf-8"))
    assert meta["status"] == "completed"
    assert meta["summary"]["unconverged_steps"] == 0
    assert 0.0 < meta["summary"]["V_over_V0_end"] < 1.0  # the poured bed compacts
