"""Faults (issue 14 item 4): a worker killed during ``reproduce`` and ``suite run``, Ctrl-C
(SIGINT) during ``explore``, ``fit --out`` and ``reproduce``, and Ctrl-C in the middle of
writing a run's files. Each ends with one line on stderr, a non-zero status and no partial
output: no half-written file, and no file of a run that did not finish.
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from hapticsim.cli import main
from hapticsim.data.bodies import get_body
from hapticsim.data.io import write_contacts
from hapticsim.data.synthetic import paper_dataset
from hapticsim.experiments.fig4 import Fig4Config
from hapticsim.experiments.trial import run_trial
from hapticsim.suites.cases import run_case

REPO = Path(__file__).resolve().parents[2]
#: Environment variable naming the task a patched worker function dies on.
KILL_ENV = "HAPTICSIM_TEST_DIE_ON"


def _die_or_run_trial(trial):
    """`run_trial`, except that the worker kills itself (SIGKILL) on the trial named by
    KILL_ENV: what a crash in native code or the out-of-memory killer does."""
    if trial.label == os.environ.get(KILL_ENV):
        os.kill(os.getpid(), signal.SIGKILL)
    return run_trial(trial)


def _die_or_run_case(task):
    """`run_case`, except that the worker kills itself on the case named by KILL_ENV."""
    if task.label == os.environ.get(KILL_ENV):
        os.kill(os.getpid(), signal.SIGKILL)
    return run_case(task)


def _files_under(root: Path) -> list[str]:
    return sorted(str(p.relative_to(root)) for p in root.rglob("*") if p.is_file())


def _one_line(err: str) -> str:
    lines = [ln for ln in err.split("\n") if ln.split("\r")[-1].strip()]
    assert len(lines) == 1, err
    return lines[0].split("\r")[-1]


# ----------------------------------------------------------------------------- killed workers
def test_a_worker_killed_during_reproduce_names_the_trial_and_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    from hapticsim.experiments import reproduce

    victim = Fig4Config(runs=1).trials()[2].label
    monkeypatch.setenv(KILL_ENV, victim)
    monkeypatch.setattr(reproduce, "run_trial", _die_or_run_trial)
    out = tmp_path / "rep"
    argv = ["reproduce", "fig4", "--runs", "1", "--workers", "2", "--out", str(out),
            "--results", str(tmp_path / "RESULTS.md")]  # fmt: skip
    assert main(argv) == 2
    line = _one_line(capsys.readouterr().err)
    assert line.startswith("hapticsim reproduce: error: a worker process")
    assert "died (killed by signal SIGKILL) while running " + victim in line
    assert _files_under(tmp_path) == []


def test_a_worker_killed_during_suite_run_names_the_case_and_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    from hapticsim.suites import runner

    monkeypatch.setenv(KILL_ENV, "case 'cube/nH/noise=0.05/run=2' of fit-v1")  # of 8 cases
    monkeypatch.setattr(runner, "run_case", _die_or_run_case)
    out = tmp_path / "results.json"
    argv = ["suite", "run", "fit-v1", "--cases", "cube/nH/noise=0.05/*", "--workers", "2",
            "--quiet",
            "--out", str(out)]  # fmt: skip
    assert main(argv) == 2
    line = _one_line(capsys.readouterr().err)
    assert line.startswith("hapticsim suite run: error: a worker process")
    assert "'cube/nH/noise=0.05/run=2'" in line and "was not written" in line
    assert _files_under(tmp_path) == []


# ----------------------------------------------------------------------------- Ctrl-C
def _children(pid: int) -> set[int]:
    """Child processes of `pid` (from /proc)."""
    kids: set[int] = set()
    for tid in os.listdir(f"/proc/{pid}/task"):
        try:
            text = Path(f"/proc/{pid}/task/{tid}/children").read_text()
        except OSError:
            continue
        kids.update(int(k) for k in text.split())
    return kids


def _interrupt(argv: list[str], cwd: Path, when, group: bool = False, timeout: float = 300):
    """Start ``hapticsim ARGV``, send SIGINT once ``when(proc)`` is true, wait for the end.

    Returns:
        (exit status, stdout, stderr, child pids seen while it ran).
    """
    env = os.environ | {"PYTHONPATH": str(REPO), "MUJOCO_GL": "egl"}
    proc = subprocess.Popen(
        [sys.executable, "-m", "hapticsim.cli", *argv], cwd=cwd, env=env, text=True,
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=group,
    )  # fmt: skip
    children: set[int] = set()
    deadline = time.monotonic() + timeout
    try:
        while not when(proc) and proc.poll() is None:
            if time.monotonic() > deadline:
                raise AssertionError(f"{argv} never reached the point to interrupt it")
            children |= _children(proc.pid)
            time.sleep(0.05)
        assert proc.poll() is None, f"{argv} ended before it could be interrupted"
        children |= _children(proc.pid)
        if group:
            os.killpg(proc.pid, signal.SIGINT)  # what Ctrl-C in a terminal does
        else:
            proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    return proc.returncode, out, err, children


def _alive(pids: set[int]) -> list[int]:
    alive = []
    for pid in pids:
        try:
            state = Path(f"/proc/{pid}/stat").read_text().split()[2]
        except OSError:
            continue
        if state != "Z":
            alive.append(pid)
    return alive


@contextlib.contextmanager
def _sigint_after(seconds: float) -> Iterator[None]:
    """Send this process a real SIGINT `seconds` into the block, handled as Python's default
    handler does (KeyboardInterrupt in the main thread); one arriving after the block ends is
    dropped, so that it cannot stop the test session."""
    armed = threading.Event()
    armed.set()

    def handler(signum, frame):
        if armed.is_set():
            raise KeyboardInterrupt

    previous = signal.signal(signal.SIGINT, handler)
    timer = threading.Timer(seconds, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        yield
    finally:
        armed.clear()
        timer.cancel()
        timer.join()
        signal.signal(signal.SIGINT, previous)


def test_ctrl_c_during_fit_out_leaves_no_file(
    tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    # 15 000 contacts: the fit takes about 4 s (5 000 took 1.4 s on a quiet machine since the
    # fast loop, too close to the 1 s); Ctrl-C comes after 1 s. The
    # compiled search does not look at signals, so Ctrl-C takes effect when its call returns
    # (measured: 20 000 contacts at budget 10^6 took 19-38 s to stop).
    write_contacts(tmp_path / "c.npz", paper_dataset(get_body("cube"), rng=0, count=15_000))
    with _sigint_after(1.0):
        code = main(["fit", str(tmp_path / "c.npz"), "--out", str(tmp_path / "fit.json")])
    assert (code, *capsys.readouterr()) == (130, "", "hapticsim fit: interrupted\n")
    assert _files_under(tmp_path) == ["c.npz"]


def test_ctrl_c_during_explore_leaves_no_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    from hapticsim.sim.recorder import Recorder

    # a real SIGINT in the middle of the simulation, as the 60th contact is recorded (a fixed
    # delay is not a fixed place: since the fast loop the whole run can end within 1.5 s)
    real_add, sent = Recorder.add, []

    def add(self, contact, pattern):
        if len(self) == 60 and not sent:
            sent.append(1)
            os.kill(os.getpid(), signal.SIGINT)
        return real_add(self, contact, pattern)

    monkeypatch.setattr(Recorder, "add", add)
    argv = ["explore", "--object", "cube", "--count", "150", "--quiet", "--out",
            str(tmp_path / "run")]  # fmt: skip
    with _sigint_after(600.0):  # only installs the handler; the signal above is the one sent
        code = main(argv)
    assert sent, "the exploration never recorded 60 contacts"
    assert (code, *capsys.readouterr()) == (130, "", "hapticsim explore: interrupted\n")
    assert _files_under(tmp_path) == []


def test_ctrl_c_during_reproduce_leaves_no_file(
    tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    argv = ["reproduce", "fig4", "--runs", "2", "--workers", "2", "--quiet", "--out",
            str(tmp_path / "rep"), "--results", str(tmp_path / "RESULTS.md")]  # fmt: skip
    with _sigint_after(2.0):  # 32 fits: about 10 s on two workers
        code = main(argv)
    assert (code, *capsys.readouterr()) == (130, "", "hapticsim reproduce: interrupted\n")
    assert _files_under(tmp_path) == []


def _has_workers(proc) -> bool:
    return len(_children(proc.pid)) >= 2


def test_ctrl_c_in_a_terminal_during_reproduce_stops_every_process_and_leaves_no_file(
    tmp_path: Path,
) -> None:
    # Ctrl-C in a terminal signals the whole process group: the parent and its workers
    argv = ["reproduce", "fig4", "--runs", "2", "--workers", "2", "--quiet", "--out", "rep",
            "--results", "RESULTS.md"]  # fmt: skip
    started = {}

    def working(proc) -> bool:  # workers up for a second: trials are running
        if _has_workers(proc):
            started.setdefault("t", time.monotonic())
        return "t" in started and time.monotonic() - started["t"] > 1.0

    code, out, err, children = _interrupt(argv, tmp_path, working, group=True)
    assert (code, out, err) == (130, "", "hapticsim reproduce: interrupted\n")
    assert children and not _alive(children)
    assert _files_under(tmp_path) == []


# ----------------------------------------------------------------------------- while writing
def _interrupt_on_call(monkeypatch: pytest.MonkeyPatch, module, name: str, call: int) -> None:
    """Make the `call`-th call of ``module.name`` raise KeyboardInterrupt (1-based)."""
    real, calls = getattr(module, name), []

    def interrupted(*args, **kwargs):
        calls.append(1)
        if len(calls) == call:
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    monkeypatch.setattr(module, name, interrupted)


def test_ctrl_c_while_explore_writes_its_files_leaves_none_of_them(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    from hapticsim.data import io

    # contacts.npz and truth.json are written, then Ctrl-C arrives as fit.json is
    _interrupt_on_call(monkeypatch, io, "write_json", 2)
    argv = ["explore", "--object", "ellipsoid", "--strategy", "patch", "--count", "20",
            "--method", "nLS", "--quiet", "--out", str(tmp_path / "run")]  # fmt: skip
    assert main(argv) == 130
    assert capsys.readouterr().err == "hapticsim explore: interrupted\n"
    assert _files_under(tmp_path) == []


@pytest.mark.slow  # ~11 s: 16 fits and the Fig. 4 pictures
def test_ctrl_c_while_reproduce_writes_its_files_leaves_none_of_them(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from hapticsim.data import io
    from hapticsim.experiments.reproduce import reproduce

    # every table, picture and the report are written; Ctrl-C arrives as summary.json is
    _interrupt_on_call(monkeypatch, io, "write_json", 1)
    with pytest.raises(KeyboardInterrupt):
        reproduce("fig4", tmp_path / "rep", runs=1, workers=1, budget=300, progress=False,
                  results=tmp_path / "RESULTS.md")  # fmt: skip
    assert _files_under(tmp_path) == []


def test_an_output_set_commits_together_and_discards_together(tmp_path: Path) -> None:
    from hapticsim._files import OutputSet, write_json

    (tmp_path / "old.json").write_text("{}")
    with pytest.raises(KeyboardInterrupt), OutputSet():
        write_json(tmp_path / "a.json", {"a": 1})
        write_json(tmp_path / "old.json", {"new": True})
        raise KeyboardInterrupt
    assert _files_under(tmp_path) == ["old.json"]  # the earlier run's file as it was
    assert json.loads((tmp_path / "old.json").read_text()) == {}
    with OutputSet() as outputs:
        write_json(tmp_path / "a.json", {"a": 1})
        assert not (tmp_path / "a.json").exists()  # not before the commit
        assert json.loads(outputs.source(tmp_path / "a.json").read_text()) == {"a": 1}
    assert _files_under(tmp_path) == ["a.json", "old.json"]
