"""The tiers' bed scenes and the scaling scene are scenes the engine accepts as they are
(`ratchet run --explain`: the scene is built and checked, nothing runs): a change of the
scene format that one of them no longer follows fails here, not in a campaign.

Run with Debian's interpreter: /usr/bin/python3 -m pytest -q scripts/tests/test_scenes.py
"""

import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from common.paths import REPO_ROOT, engine_binary  # noqa: E402

SCENES = sorted([*(REPO_ROOT / "validation" / "sweeps").glob("bed_*.json"),
                 *(REPO_ROOT / "validation" / "scaling").glob("*.json")])


def test_there_are_scenes_to_check():
    names = {p.name for p in SCENES}
    assert {"bed_quick.json", "bed_standard.json", "bed_paper.json", "bed_20k.json"} <= names


@pytest.mark.parametrize("scene", SCENES, ids=lambda p: p.name)
def test_the_engine_accepts_the_scene(scene):
    binary = engine_binary()
    if not binary.exists():
        pytest.skip(f"the engine is not built ({binary})")
    done = subprocess.run([str(binary), "run", "--explain", str(scene)], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith(f"scene {scene.stem} (")
