"""Stopping and resuming the real `ratchet` binary with real signals (docs/cli.md,
"Stopping and resuming"): SIGINT and SIGTERM stop a run cleanly (exit 128 + signal,
run.json "interrupted", a checkpoint, the CSVs left as .partial), SIGKILL leaves the last
periodic checkpoint; `ratchet run --resume DIR` then gives the bytes of a run that never
stopped (the wall-clock time_* columns and timings aside). A sweep stopped by SIGINT
resumes its runs from their checkpoints and gives the summary of a sweep never stopped.
The in-process version of the same checks, at chosen steps, is
reference_engine/tests/run/checkpoint_test.cpp."""

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from common.paths import REPO_ROOT, engine_binary  # noqa: E402

RATCHET = engine_binary()
pytestmark = pytest.mark.skipif(not RATCHET.is_file(), reason=f"engine not built ({RATCHET})")

# The README's example bed (60 polyhedra, settle section, 2 cycles; about 5 s), with a
# checkpoint every 300 steps and VTK every 500, so that every kind of output is resumed.
SCENE = REPO_ROOT / "validation" / "examples" / "my_bed.json"
SETTINGS = ["--set", "outputs.checkpoint_every=300", "--set", "outputs.vtk_every=500", "--set",
            "outputs.timeseries_every=10"]


def run_args(out: Path):
    return [str(RATCHET), "run", str(SCENE), "--out", str(out), "--quiet", *SETTINGS]


def rows_written(out: Path) -> int:
    """Timeseries rows on disk so far (buffered writes: a lower bound)."""
    for name in ("timeseries.csv.partial", "timeseries.csv"):
        try:
            with open(out / name, "rb") as f:
                return f.read().count(b"\n") - 1
        except FileNotFoundError:
            continue
    return 0


def stop_after_rows(args, out: Path, rows: int, sig: int, timeout: float = 60.0) -> subprocess.CompletedProcess:
    """Starts the run and sends `sig` once `rows` timeseries rows are on disk."""
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + timeout
    while rows_written(out) < rows and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    assert proc.poll() is None, "the run ended before the signal could be sent: raise its length"
    proc.send_signal(sig)
    stdout, stderr = proc.communicate(timeout=timeout)
    return subprocess.CompletedProcess(args, proc.returncode, stdout, stderr)


def timeseries_without_timings(path: Path) -> pd.DataFrame:
    df = pd.read_csv(path, dtype=str)  # as text: the bytes of each value are compared
    return df[[c for c in df.columns if not c.startswith("time_")]]


def run_json_without_timings(path: Path) -> dict:
    """run.json without what the clock and the invocation decide: the timings, and the
    provenance (date, host, command line: a resumed run lists its resumes)."""
    j = json.loads(path.read_text())
    j.pop("wall_seconds", None)
    assert j.pop("provenance")["host"]
    for phase in j["phases"]:
        phase.pop("seconds", None)
    if isinstance(j.get("packing"), dict):  # the packing's folder is the sweep's own
        j["packing"]["file"] = Path(j["packing"]["file"]).name
    return j


def assert_same_run(a: Path, b: Path):
    files_a = sorted(p.relative_to(a) for p in a.rglob("*") if p.is_file())
    files_b = sorted(p.relative_to(b) for p in b.rglob("*") if p.is_file())
    assert files_a == files_b
    for f in files_a:
        if f.name == "timeseries.csv":
            pd.testing.assert_frame_equal(timeseries_without_timings(a / f), timeseries_without_timings(b / f))
        elif f.name == "run.json":
            assert run_json_without_timings(a / f) == run_json_without_timings(b / f)
        else:
            assert (a / f).read_bytes() == (b / f).read_bytes(), f"{f} differs"


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("resume") / "whole"
    subprocess.run(run_args(out), check=True, capture_output=True, text=True, timeout=300)
    assert json.loads((out / "run.json").read_text())["status"] == "completed"
    assert not (out / "checkpoint.state").exists()
    return out


def total_rows(reference: Path) -> int:
    return len(pd.read_csv(reference / "timeseries.csv"))


# Fractions of the run's rows at which the signal is sent: in the settle stage (about the
# first 60 % of this run) and in the cycles.
@pytest.mark.parametrize("sig, fraction", [(signal.SIGINT, 0.2), (signal.SIGTERM, 0.7)])
def test_sigint_and_sigterm_stop_cleanly_and_resume_gives_the_same_bytes(reference, tmp_path, sig, fraction):
    out = tmp_path / "stopped"
    stopped = stop_after_rows(run_args(out), out, int(fraction * total_rows(reference)), sig)
    assert stopped.returncode == 128 + sig, stopped.stderr
    name = signal.Signals(sig).name
    assert f"stopped by {name}" in stopped.stderr and f"ratchet run --resume {out}" in stopped.stderr
    meta = json.loads((out / "run.json").read_text())
    assert meta["status"] == "interrupted" and meta["signal"] == name
    assert (out / "checkpoint.state").is_file()
    assert (out / "timeseries.csv.partial").is_file() and not (out / "timeseries.csv").exists()

    resumed = subprocess.run([str(RATCHET), "run", "--resume", str(out)], capture_output=True, text=True, timeout=300)
    assert resumed.returncode == 0, resumed.stderr
    assert f"resuming at step {meta['steps']}" in resumed.stderr
    assert_same_run(reference, out)


@pytest.mark.parametrize("fraction", [0.45, 0.85])
def test_sigkill_leaves_a_checkpoint_that_resumes_to_the_same_bytes(reference, tmp_path, fraction):
    out = tmp_path / "killed"
    killed = stop_after_rows(run_args(out), out, int(fraction * total_rows(reference)), signal.SIGKILL)
    assert killed.returncode == -signal.SIGKILL
    assert not (out / "run.json").exists()  # nothing ran at the kill
    assert (out / "checkpoint.state").is_file()
    resumed = subprocess.run([str(RATCHET), "run", "--resume", str(out), "--quiet"], capture_output=True, text=True,
                             timeout=300)
    assert resumed.returncode == 0, resumed.stderr
    assert_same_run(reference, out)


def test_a_stopped_sweep_resumes_its_runs_from_their_checkpoints(tmp_path):
    """Two runs, one at a time; SIGINT during the first. The rerun resumes it (not from
    step 0) and the summary equals that of a sweep never stopped."""
    shutil.copy(SCENE, tmp_path / "bed.json")
    scene = json.loads(SCENE.read_text())
    scene["outputs"]["checkpoint_every"] = 300
    scene["thermal"]["cycles"] = 1
    (tmp_path / "bed.json").write_text(json.dumps(scene))
    sweep = {"scene": "bed.json", "grid": {"materials.friction": [0.3, 0.5]}, "realizations": 1}
    (tmp_path / "sweep.json").write_text(json.dumps(sweep))

    def sweep_args(out):
        return [str(RATCHET), "sweep", str(tmp_path / "sweep.json"), "--out", str(out), "--jobs", "1"]

    whole = tmp_path / "whole"
    subprocess.run(sweep_args(whole), check=True, capture_output=True, text=True, timeout=600)

    out = tmp_path / "stopped"
    run0 = out / "runs" / "0"
    proc = subprocess.Popen(sweep_args(out), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300
    # After the packings, once run 0 has passed a checkpoint.
    while not (run0 / "checkpoint.state").exists() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    assert proc.poll() is None, "the sweep ended before the signal could be sent"
    proc.send_signal(signal.SIGINT)
    _, stderr = proc.communicate(timeout=300)
    assert proc.returncode == 128 + signal.SIGINT, stderr
    assert "run the same command again to resume" in stderr
    assert json.loads((run0 / "run.json").read_text())["status"] == "interrupted"
    assert not (out / "runs" / "1" / "run.json").exists()  # no new run started after the signal

    again = subprocess.run(sweep_args(out), capture_output=True, text=True, timeout=600)
    assert again.returncode == 0, again.stderr
    assert "run 0 resumes at step " in again.stderr
    assert (out / "summary.csv").read_bytes() == (whole / "summary.csv").read_bytes()
    assert_same_run(whole / "runs" / "0", run0)


def state_of(packing: Path) -> bytes:
    """The State of a state file (docs/output-format.md, *State files*): the bytes between
    the metadata (its length at offset 12) and the checksum; the metadata holds the pour's
    wall seconds, which differ from pour to pour."""
    data = packing.read_bytes()
    meta = int.from_bytes(data[12:16], "little")
    return data[40 + meta:-8]


def stop_once_exists(args, path: Path, sig: int, timeout: float = 120.0) -> subprocess.CompletedProcess:
    """Starts the command and sends `sig` once `path` exists."""
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + timeout
    while not path.exists() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.005)
    assert proc.poll() is None, "the command ended before the signal could be sent: checkpoint the pour more often"
    proc.send_signal(sig)
    stdout, stderr = proc.communicate(timeout=timeout)
    return subprocess.CompletedProcess(args, proc.returncode, stdout, stderr)


def test_a_stopped_pack_goes_on_from_its_pour_checkpoint_to_the_same_packing(tmp_path):
    """`ratchet pack` stopped by SIGTERM during the pour keeps FILE.pour-checkpoint and no
    packing; the same command again resumes the pour there and writes the packing of a
    pour never stopped (the same State bytes), then removes the checkpoint."""
    every = ["--set", "outputs.checkpoint_every=500"]  # the pour is about 3900 steps
    whole = tmp_path / "whole.state"
    subprocess.run([str(RATCHET), "pack", str(SCENE), "--out", str(whole), *every], check=True,
                   capture_output=True, text=True, timeout=300)
    packing = tmp_path / "stopped.state"
    checkpoint = tmp_path / "stopped.state.pour-checkpoint"
    args = [str(RATCHET), "pack", str(SCENE), "--out", str(packing), *every]
    stopped = stop_once_exists(args, checkpoint, signal.SIGTERM)
    assert stopped.returncode == 128 + signal.SIGTERM, stopped.stderr
    assert "the pour stopped by SIGTERM at step " in stopped.stderr
    assert "run the same command again to resume" in stopped.stderr
    assert checkpoint.is_file() and not packing.exists()

    again = subprocess.run(args, capture_output=True, text=True, timeout=300)
    assert again.returncode == 0, again.stderr
    assert f"resumes the pour from {checkpoint} at step " in again.stderr
    assert state_of(packing) == state_of(whole)
    assert not checkpoint.exists()


def test_a_sweep_stopped_in_its_pour_goes_on_from_the_pour_checkpoint(tmp_path):
    """A sweep stopped by SIGINT while it makes its packing starts no run; run again, it
    resumes the pour and its summary equals that of a sweep never stopped."""
    scene = json.loads(SCENE.read_text())
    scene["outputs"]["checkpoint_every"] = 500
    scene["thermal"]["cycles"] = 1
    (tmp_path / "bed.json").write_text(json.dumps(scene))
    (tmp_path / "sweep.json").write_text(json.dumps({"scene": "bed.json", "realizations": 1}))

    def sweep_args(out):
        return [str(RATCHET), "sweep", str(tmp_path / "sweep.json"), "--out", str(out), "--jobs", "1"]

    whole = tmp_path / "whole"
    subprocess.run(sweep_args(whole), check=True, capture_output=True, text=True, timeout=600)
    (key,) = [p.name.removesuffix(".state") for p in (whole / "packings").glob("*.state")]
    out = tmp_path / "stopped"
    checkpoint = out / "packings" / f"{key}.state.pour-checkpoint"
    stopped = stop_once_exists(sweep_args(out), checkpoint, signal.SIGINT)
    assert stopped.returncode == 128 + signal.SIGINT, stopped.stderr
    assert "the pour stopped by SIGINT" in stopped.stderr
    assert not (out / "runs" / "0" / "run.json").exists()  # no run started after the signal

    again = subprocess.run(sweep_args(out), capture_output=True, text=True, timeout=600)
    assert again.returncode == 0, again.stderr
    assert f"packing {key}: resumes the pour from " in again.stderr
    assert state_of(out / "packings" / f"{key}.state") == state_of(whole / "packings" / f"{key}.state")
    assert (out / "summary.csv").read_bytes() == (whole / "summary.csv").read_bytes()
    assert not checkpoint.exists()
