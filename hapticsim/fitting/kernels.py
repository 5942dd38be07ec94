"""Get the fitter's compiled kernels ready before a fit is timed, in parallel on a cold cache.

The fitter's kernels are numba functions cached on disk (``cache=True``). A process loads them
from the cache the first time it calls them (about a second for all of them), and a fresh
installation compiles them first (about 40 CPU-seconds). Neither belongs in a fit's reported
``seconds``: :func:`prepare` runs a tiny problem through every code path a method uses, once per
process, so that :func:`hapticsim.fit` can time the fit alone and report the set-up beside it
(``FitResult.setup_seconds``).

On a cold cache the work splits into independent *parts* (the genetic algorithm and the least
squares, for the paper's EOF and the ML residuals), which :func:`start_background` compiles in
worker processes at once, one per core, each writing numba's cache; the calling process then
only loads. :func:`start_background` starts those workers without waiting, so a command can
simulate while they compile (``hapticsim explore``), and :meth:`Background.wait` shows their
progress on stderr.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TextIO

import numpy as np
from numba.core.registry import cpu_target

from hapticsim import _jit_cache
from hapticsim.errors import InvalidInputError
from hapticsim.fitting.genetic import GeneticOptions, genetic_search
from hapticsim.fitting.hybrid import distinct_starts
from hapticsim.fitting.initial import seed_vectors
from hapticsim.fitting.least_squares import least_squares_run, multi_start_run
from hapticsim.fitting.ml import ml_objective
from hapticsim.fitting.objective import Objective
from hapticsim.fitting.problem import problem_jacobian, problem_residuals

#: The independent parts of the kernels: (residual model, stage).
PARTS: tuple[str, ...] = ("eof-lm", "eof-ga", "ml-lm", "ml-ga")
#: The parts each method runs (multi fits nH per part and refines the parts with nML's
#: least squares).
METHOD_PARTS: dict[str, tuple[str, ...]] = {
    "LS": ("eof-lm",),
    "nLS": ("eof-lm",),
    "H": ("eof-lm", "eof-ga"),
    "nH": ("eof-lm", "eof-ga"),
    "nML": PARTS,
    "multi": ("eof-lm", "eof-ga", "ml-lm"),
    "gpis": (),  # numpy and scipy: no compiled kernel
    "supertoroid": (),
    "nH+track": ("eof-lm", "eof-ga"),  # nH, then SciPy's least squares over the poses
    "multi+track": ("eof-lm", "eof-ga", "ml-lm"),
}

_ready: set[str] = set()
#: The workers this process started last (a second start of the same parts returns them).
_running: Background | None = None


def parts_for(methods: str | tuple[str, ...] | list[str]) -> tuple[str, ...]:
    """The parts the given method(s) need, in :data:`PARTS` order."""
    names = (methods,) if isinstance(methods, str) else tuple(methods)
    wanted: set[str] = set()
    for name in names:
        if name not in METHOD_PARTS:
            raise InvalidInputError(f"unknown method {name!r}; one of {', '.join(METHOD_PARTS)}")
        wanted.update(METHOD_PARTS[name])
    return tuple(p for p in PARTS if p in wanted)


def _tiny_objective(model: str):  # noqa: ANN202 - an Objective
    """An objective on 24 contacts of a sphere of radius 0.03 m (types as a real fit's)."""

    k = np.arange(24) + 0.5
    z = 1.0 - 2.0 * k / 24
    phi = k * np.pi * (3.0 - np.sqrt(5.0))
    r = np.sqrt(1.0 - z * z)
    normals = np.column_stack([r * np.cos(phi), r * np.sin(phi), z])
    points = 0.03 * normals
    if model == "eof":
        return Objective(points, normals, 0.5, 400, "untapered")
    free = 0.05 * normals[:4]
    return ml_objective(points, normals, 400, None, free, None, np.ones((2, 24)), 1.0)


def _run_part(part: str) -> None:
    """Run `part`'s kernels once on a tiny problem (compiling or loading them).

    The order shares work between the workers of a cold compile: both stages call the model's
    residuals, which numba compiles as functions of their own and caches. The least squares'
    worker compiles them first (then the Jacobian, then its loop); the genetic algorithm's
    worker reaches them later in its own compile and usually loads them from numba's cache
    instead of compiling them a second time (run alone, the order changes nothing).
    """
    model, stage = part.split("-")
    objective = _tiny_objective(model)
    seeds = seed_vectors(objective.points, objective.normals, None)
    if stage == "lm":
        problem_residuals(objective.contacts, objective.problem, seeds[:2])
        problem_jacobian(objective.contacts, objective.problem, seeds[0])
        multi_start_run(objective, seeds[:2], 1)
        least_squares_run(objective, seeds[0])
    else:
        run = genetic_search(objective, seeds, np.random.default_rng(0), 200, GeneticOptions())
        distinct_starts(run, 2, objective.bounds.size)


def prepare(methods: str | tuple[str, ...] | list[str] = "nH") -> float:
    """Make every kernel the method(s) use callable in this process (loading them from numba's
    cache, or compiling them there first); returns the seconds it took (0 when done already)."""
    return _prepare_parts(parts_for(methods))


def _prepare_parts(parts: tuple[str, ...]) -> float:
    """:func:`prepare` for the named parts (:data:`PARTS`)."""
    todo = [p for p in parts if p not in _ready]
    if not todo:
        return 0.0
    start = time.perf_counter()
    for part in todo:
        _run_part(part)
        _ready.add(part)
        _jit_cache.mark(part, target_tag())
    return time.perf_counter() - start


def target_tag() -> str:
    """A short tag of numba's code-generation target here (triple, CPU name and features): its
    cache holds machine code for one target, so the markers of :func:`is_cached` name it."""

    magic = cpu_target.target_context.codegen().magic_tuple()
    return hashlib.sha256(repr(magic).encode()).hexdigest()[:12]


def is_cached(part: str) -> bool:
    """Whether `part`'s kernels were compiled into numba's cache for these sources and this
    target (a marker written when a worker or :func:`prepare` finished it; a stale cache is
    deleted first, see :func:`hapticsim._jit_cache.ensure_fresh`)."""
    _jit_cache.ensure_fresh()
    return _jit_cache.is_marked(part, target_tag())


def default_jobs() -> int:
    """Worker processes for a cold compile: the cores this process may use, at most 4."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not on Linux
        cores = os.cpu_count() or 1
    return max(1, min(cores, 4))


@dataclass
class Background:
    """Worker processes compiling parts into numba's cache (from :func:`start_background`)."""

    groups: list[tuple[str, ...]]
    procs: list[subprocess.Popen] = field(default_factory=list)
    started: float = field(default_factory=time.perf_counter)

    @property
    def parts(self) -> tuple[str, ...]:
        """Every part the workers compile."""
        return tuple(p for g in self.groups for p in g)

    def wait(
        self, stream: TextIO | None = None, say: Callable[[str], None] | None = None,
        load: bool = False,
    ) -> float:  # fmt: skip
        """Wait for the workers, printing a line per finished part on `stream` (default
        stderr) and one every 10 s while they run, or handing those lines to `say` (a progress
        bar's); returns the seconds waited. A worker that failed is reported and ignored: the
        kernels are then compiled in this process. With `load`, the parts of a worker that
        finished are loaded into this process (:func:`prepare`) while the others still
        compile, on the core it freed: numba's own start (about 0.7 s) is then paid there."""
        stream = sys.stderr if stream is None else stream
        tell = (lambda line: _say(stream, line)) if say is None else say
        start = time.perf_counter()
        pending = list(zip(self.procs, self.groups, strict=True))
        last = start
        while pending:
            for proc, group in list(pending):
                code = proc.poll()
                if code is None:
                    continue
                pending.remove((proc, group))
                took = time.perf_counter() - self.started
                word = "compiled" if code == 0 else f"failed (exit {code}), compiling here"
                tell(f"hapticsim: {' '.join(group)} {word} after {took:.0f} s")
                if load and code == 0 and pending:
                    _prepare_parts(group)
            if pending and time.perf_counter() - last >= 10.0:
                last = time.perf_counter()
                names = " ".join(p for _, g in pending for p in g)
                took = last - self.started
                tell(f"hapticsim: still compiling {names} ({took:.0f} s so far)")
            if pending:
                time.sleep(0.05)
        return time.perf_counter() - start

    def stop(self) -> None:
        """End the workers that still run (a command that failed before its fit): numba writes
        each cache file atomically, so a stopped worker leaves nothing half-written."""
        global _running
        for proc in self.procs:
            if proc.poll() is None:
                proc.terminate()
        for proc in self.procs:
            try:
                proc.wait(timeout=5)
            except subprocess.TimeoutExpired:  # pragma: no cover - a stuck worker
                proc.kill()
        if _running is self:
            _running = None


def _say(stream: TextIO, line: str) -> None:
    try:
        stream.write(line + "\n")
        stream.flush()
    except (OSError, ValueError):
        pass


def _split(parts: tuple[str, ...], jobs: int) -> list[tuple[str, ...]]:
    """Parts dealt to `jobs` workers round-robin (the GA and LM of a model on different ones)."""
    return [g for g in (tuple(parts[i::jobs]) for i in range(jobs)) if g]


def start_background(
    methods: str | tuple[str, ...] | list[str] = "nH",
    jobs: int | None = None,
    stream: TextIO | None = None,
) -> Background | None:
    """On a cold cache, start worker processes compiling the method(s)' parts; None when the
    cache is warm (nothing to do) or the parts are ready in this process already."""
    global _running
    parts = tuple(p for p in parts_for(methods) if p not in _ready and not is_cached(p))
    if not parts:
        return None
    if _running is not None and set(parts) <= set(_running.parts):
        return _running  # started earlier by this process (the command line, before imports)
    n = default_jobs() if jobs is None else max(1, int(jobs))
    groups = _split(parts, n)
    stream = sys.stderr if stream is None else stream
    _say(
        stream,
        f"hapticsim: compiling the fitter's kernels once for this installation "
        f"({', '.join(parts)}) in {len(groups)} processes; later runs load them",
    )
    env = dict(os.environ, PYTHONWARNINGS="ignore")
    procs = [
        subprocess.Popen(  # noqa: S603 - our own module, no shell
            [sys.executable, "-m", "hapticsim.fitting.kernels", *group],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            env=env,
        )  # fmt: skip
        for group in groups
    ]
    _running = Background(groups=groups, procs=procs)
    return _running


def _main(argv: list[str]) -> int:
    """Worker entry: ``python -m hapticsim.fitting.kernels PART [PART ...]``."""
    for part in argv:
        if part not in PARTS:
            print(f"unknown part {part!r}; one of {', '.join(PARTS)}", file=sys.stderr)
            return 2
        _run_part(part)
        _jit_cache.mark(part, target_tag())
    return 0


if __name__ == "__main__":
    raise SystemExit(_main(sys.argv[1:]))


__all__ = [
    "METHOD_PARTS",
    "PARTS",
    "Background",
    "default_jobs",
    "is_cached",
    "parts_for",
    "prepare",
    "start_background",
    "target_tag",
]
