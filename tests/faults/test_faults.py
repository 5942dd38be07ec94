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
#: Environment variables of :func:`_interrupt_or_run_trial`: the trial it holds, the pid it
#: sends SIGINT, the file it creates.
HOLD_ENV = "HAPTICSIM_TEST_HOLD_ON"
SIGNAL_PID_ENV = "HAPTICSIM_TEST_SIGNAL_PID"
MARKER_ENV = "HAPTICSIM_TEST_MARKER"
#: File whose creation lets :func:`_hold_until_released` return.
RELEASE_ENV = "HAPTICSIM_TEST_RELEASE"


def _die_or_run_trial(trial):
    """`run_trial`, except that the worker kills itself (SIGKILL) on the trial named by
    KILL_ENV: what a crash in native code or the out-of-memory killer does."""
    if trial.label == os.environ.get(KILL_ENV):
        os.kill(os.getpid(), signal.SIGKILL)
    return run_trial(trial)


def _interrupt_or_run_trial(trial):
    """`run_trial`, except that on the trial named by HOLD_ENV the worker signals that the run
    is under way (SIGINT to the pid in SIGNAL_PID_ENV, or a file created at MARKER_ENV) and then
    holds that trial until the interrupt stops the run (at most 300 s): the run cannot end
    before the interrupt arrives, however fast the machine (no wall-clock delay decides it)."""
    if trial.label == os.environ.get(HOLD_ENV):
        if SIGNAL_PID_ENV in os.environ:
            os.kill(int(os.environ[SIGNAL_PID_ENV]), signal.SIGINT)
        if MARKER_ENV in os.environ:
            Path(os.environ[MARKER_ENV]).touch()
        time.sleep(300.0)  # the parent terminates this worker when it is interrupted
    return run_trial(trial)


def _hold_until_released(task: int) -> int:
    """Create the file ``MARKER_ENV.<task>``, then wait until RELEASE_ENV exists (<= 300 s)."""
    Path(f"{os.environ[MARKER_ENV]}.{task}").touch()
    release, deadline = Path(os.environ[RELEASE_ENV]), time.monotonic() + 300.0
    while not release.exists() and time.monotonic() < deadline:
        time.sleep(0.05)
    return task


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


_HELD_MAP = (
    "from hapticsim.parallel import parallel_map\n"
    "from tests.faults.test_faults import _hold_until_released\n"
    "parallel_map(_hold_until_released, [0, 1], workers=2, progress=False)\n"
)


def test_the_workers_of_a_killed_parent_exit(tmp_path: Path) -> None:
    # SIGKILL (the out-of-memory killer) runs no clean-up in the parent, and each forked worker
    # holds copies of the pipes' parent ends: the workers must notice by themselves (they
    # used to wait on their pipe for ever; found when a test's parent was killed)
    marker, release = tmp_path / "up", tmp_path / "release"
    env = os.environ | {"PYTHONPATH": str(REPO), MARKER_ENV: str(marker),
                        RELEASE_ENV: str(release)}  # fmt: skip
    proc = subprocess.Popen([sys.executable, "-c", _HELD_MAP], cwd=tmp_path, env=env)
    workers: set[int] = set()
    try:
        deadline = time.monotonic() + 300
        while not all(Path(f"{marker}.{i}").exists() for i in (0, 1)):
            assert proc.poll() is None and time.monotonic() < deadline, "workers never started"
            time.sleep(0.05)
        workers = _children(proc.pid)
        assert len(workers) == 2
        proc.kill()
        proc.wait()
        release.touch()  # the tasks end; the workers find no parent
        deadline = time.monotonic() + 60  # a bound on the wait, not a delay: ~1 s is usual
        while _alive(workers) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert not _alive(workers), "workers outlived their killed parent"
    finally:
        release.touch()
        for pid in _alive(workers):
            os.kill(pid, signal.SIGKILL)
        if proc.poll() is None:
            proc.kill()
            proc.wait()


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


def _default_sigint() -> None:
    """In the child before exec: SIGINT handled by default, as under a terminal. A test run in
    the background of a non-interactive shell inherits SIGINT ignored, and Python installs its
    KeyboardInterrupt handler only where SIGINT is not ignored at start."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _interrupt(
    argv: list[str], cwd: Path, when, group: bool = False, timeout: float = 300,
    command: tuple[str, ...] | list[str] = ("-m", "hapticsim.cli"),
):  # fmt: skip
    """Start ``python COMMAND ARGV`` (by default ``hapticsim ARGV``), send SIGINT once
    ``when(proc)`` is true, wait for the end.

    Returns:
        (exit status, stdout, stderr, child pids seen while it ran).
    """
    env = os.environ | {"PYTHONPATH": str(REPO), "MUJOCO_GL": "egl"}
    proc = subprocess.Popen(
        [sys.executable, *command, *argv], cwd=cwd, env=env, text=True,
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=group,
        preexec_fn=_default_sigint,
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
            if group:  # the workers too: they would keep the pipes open
                os.killpg(proc.pid, signal.SIGKILL)
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
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    from hapticsim.fitting import driver

    # a real SIGINT as the search starts, after the contacts were read and before anything is
    # written (a fixed delay is not a fixed place: since the fast loop 5 000 contacts fit in
    # 1.4 s). The compiled search does not look at signals, so Ctrl-C during it takes effect
    # when its call returns (measured: 20 000 contacts at budget 10^6 took 19-38 s to stop).
    real_search, sent = driver.hybrid_search, []

    def search(*args, **kwargs):
        sent.append(1)
        os.kill(os.getpid(), signal.SIGINT)
        return real_search(*args, **kwargs)

    monkeypatch.setattr(driver, "hybrid_search", search)
    write_contacts(tmp_path / "c.npz", paper_dataset(get_body("cube"), rng=0, count=500))
    with _sigint_after(600.0):  # only installs the handler; the signal above is the one sent
        code = main(["fit", str(tmp_path / "c.npz"), "--out", str(tmp_path / "fit.json")])
    assert sent, "the fit never started its search"
    assert (code, *capsys.readouterr()) == (130, "", "hapticsim fit: interrupted\n")
    assert _files_under(tmp_path) == ["c.npz"]


def test_ctrl_c_during_explore_leaves_no_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    from hapticsim.sim.recorder import Recorder

    # a real SIGINT in the middle of the simulation, as the 60th contact is recorded (a fixed
    # delay is not a fixed place: since the fast loop the whole run can end within 1.5 s)
    real_add, sent = Recorder.add, []

    def add(self, contact, pattern, sensed=None):
        if len(self) == 60 and not sent:
            sent.append(1)
            os.kill(os.getpid(), signal.SIGINT)
        return real_add(self, contact, pattern, sensed)

    monkeypatch.setattr(Recorder, "add", add)
    argv = ["explore", "--object", "cube", "--count", "150", "--quiet", "--out",
            str(tmp_path / "run")]  # fmt: skip
    with _sigint_after(600.0):  # only installs the handler; the signal above is the one sent
        code = main(argv)
    assert sent, "the exploration never recorded 60 contacts"
    assert (code, *capsys.readouterr()) == (130, "", "hapticsim explore: interrupted\n")
    assert _files_under(tmp_path) == []


def test_ctrl_c_during_reproduce_leaves_no_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    from hapticsim.experiments import reproduce

    # the worker running the third of 16 trials sends this process a real SIGINT and holds its
    # trial, so the interrupt lands while trials are running
    monkeypatch.setenv(HOLD_ENV, Fig4Config(runs=1).trials()[2].label)
    monkeypatch.setenv(SIGNAL_PID_ENV, str(os.getpid()))
    monkeypatch.setattr(reproduce, "run_trial", _interrupt_or_run_trial)
    argv = ["reproduce", "fig4", "--runs", "1", "--workers", "2", "--quiet", "--out",
            str(tmp_path / "rep"), "--results", str(tmp_path / "RESULTS.md")]  # fmt: skip
    with _sigint_after(600.0):  # only installs the handler; the worker sends the signal
        code = main(argv)
    assert (code, *capsys.readouterr()) == (130, "", "hapticsim reproduce: interrupted\n")
    assert _files_under(tmp_path) == []


#: ``hapticsim`` with :func:`_interrupt_or_run_trial` as the trial function of ``reproduce``.
_HELD_REPRODUCE = (
    "import sys\n"
    "from hapticsim.cli import main\n"
    "from hapticsim.experiments import reproduce\n"
    "from tests.faults.test_faults import _interrupt_or_run_trial\n"
    "reproduce.run_trial = _interrupt_or_run_trial\n"
    "sys.exit(main(sys.argv[1:]))\n"
)


def test_ctrl_c_in_a_terminal_during_reproduce_stops_every_process_and_leaves_no_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # Ctrl-C in a terminal signals the whole process group: the parent and its workers. It is
    # sent once the worker running the third of 16 trials says so (a file) and holds its trial:
    # workers are up and trials running (a fixed delay is not a fixed place: since the fast
    # loop the whole run can end within one)
    run, marker = tmp_path / "run", tmp_path / "held"
    run.mkdir()
    monkeypatch.setenv(HOLD_ENV, Fig4Config(runs=1).trials()[2].label)
    monkeypatch.setenv(MARKER_ENV, str(marker))
    argv = ["reproduce", "fig4", "--runs", "1", "--workers", "2", "--quiet", "--out", "rep",
            "--results", "RESULTS.md"]  # fmt: skip
    code, out, err, children = _interrupt(
        argv, run, lambda proc: marker.exists(), group=True, command=["-c", _HELD_REPRODUCE]
    )
    assert (code, out, err) == (130, "", "hapticsim reproduce: interrupted\n")
    assert children and not _alive(children)
    assert _files_under(run) == []


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
    from hapticsim.data import rundir

    # contacts.npz and truth.json are written, then Ctrl-C arrives as metrics.json is (the
    # run directory's own write_json: the name it calls)
    _interrupt_on_call(monkeypatch, rundir, "write_json", 2)
    argv = ["explore", "--object", "ellipsoid", "--strategy", "patch", "--count", "20",
            "--method", "nLS", "--quiet", "--out", str(tmp_path / "run")]  # fmt: skip
    assert main(argv) == 130
    assert capsys.readouterr().err == "hapticsim explore: interrupted\n"
    assert _files_under(tmp_path) == []


@pytest.mark.slow  # ~11 s: 16 fits and the Fig. 4 pictures
def test_ctrl_c_while_reproduce_writes_its_files_leaves_none_of_them(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from hapticsim.experiments import reproduce as module
    from hapticsim.experiments.reproduce import reproduce

    # every table, picture and the report are written; Ctrl-C arrives as summary.json is
    # (reproduce's own write_json: the name it calls)
    _interrupt_on_call(monkeypatch, module, "write_json", 1)
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
