"""Long runs of ``hapticsim/HapticExplore-v0`` in one process, recording resident memory, open
file descriptors and threads after every episode (issue 14 item 3).

Shared by ``scripts/soak.py`` (the full soak: 1,000 analytic and 100 MuJoCo episodes) and the
slow test (a shorter one with measured bounds). Linux only: the figures come from ``/proc``.
"""

from __future__ import annotations

import gc
import os
import sys
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass

import numpy as np


def resident_bytes() -> int:
    """Resident set size of this process [bytes] (``/proc/self/statm``)."""
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def open_fds() -> int:
    """Number of open file descriptors of this process."""
    return len(os.listdir("/proc/self/fd"))


def threads() -> int:
    """Number of threads of this process (OpenGL drivers start some per context)."""
    return len(os.listdir("/proc/self/task"))


@dataclass(frozen=True)
class Sample:
    """The process after one episode.

    Attributes:
        episode: index of the episode (0-based).
        rendered: whether it ran with ``render_mode="rgb_array"``, rendering every step.
        rss_mb: resident set size after the episode and a garbage collection [MB].
        fds: open file descriptors.
        threads: threads.
        seconds: wall time since the soak started [s].
        steps: steps of the episode.
    """

    episode: int
    rendered: bool
    rss_mb: float
    fds: int
    threads: int
    seconds: float
    steps: int


def soak(
    backend: str,
    episodes: int,
    render_every: int = 10,
    seed: int = 0,
    touches: int = 20,
    progress: Callable[[Sample], None] | None = None,
) -> list[Sample]:
    """Run `episodes` random-policy episodes on `backend` in this process.

    One environment made once (``gymnasium.make``) runs the episodes, reset after each; every
    `render_every`-th episode instead runs in an environment made with
    ``render_mode="rgb_array"`` that renders after every step and is closed at the end, so
    renderer contexts are created and freed over and over as well (0: never).

    Returns:
        One :class:`Sample` per episode.
    """
    import gymnasium as gym

    import hapticsim  # noqa: F401  (registers the environment)

    def make(render: bool):
        return gym.make(
            "hapticsim/HapticExplore-v0", backend=backend, touch_budget=touches,
            render_mode="rgb_array" if render else None,
        )  # fmt: skip

    env = make(False)
    samples: list[Sample] = []
    start = time.perf_counter()
    try:
        for episode in range(episodes):
            rendered = render_every > 0 and episode % render_every == render_every - 1
            current = make(True) if rendered else env
            try:
                current.reset(seed=seed + episode)
                current.action_space.seed(seed + episode)
                steps, done = 0, False
                while not done:
                    _, _, terminated, truncated, _ = current.step(current.action_space.sample())
                    steps += 1
                    if rendered:
                        frame = current.render()
                        assert frame is not None and frame.dtype == np.uint8
                    done = terminated or truncated
            finally:
                if rendered:
                    current.close()
            gc.collect()
            sample = Sample(episode, rendered, resident_bytes() / 2**20, open_fds(), threads(),
                            time.perf_counter() - start, steps)  # fmt: skip
            samples.append(sample)
            if progress is not None:
                progress(sample)
    finally:
        env.close()
    return samples


def summary(samples: list[Sample], skip: int) -> dict[str, object]:
    """Curve end points: RSS, fds and threads at episode `skip` and at the last episode, the
    growth between them (the issue's "growth over the last N episodes"), and the extremes."""
    first, last = samples[skip - 1], samples[-1]
    tail = samples[skip - 1 :]
    return {
        "episodes": len(samples),
        "rendered_episodes": sum(s.rendered for s in samples),
        "rss_mb_first_episode": round(samples[0].rss_mb, 1),
        f"rss_mb_after_episode_{skip}": round(first.rss_mb, 1),
        "rss_mb_last": round(last.rss_mb, 1),
        f"rss_growth_mb_last_{len(samples) - skip}": round(last.rss_mb - first.rss_mb, 1),
        "rss_mb_max": round(max(s.rss_mb for s in samples), 1),
        "fds": {"first": samples[0].fds, f"after_{skip}": first.fds, "last": last.fds,
                "min": min(s.fds for s in tail), "max": max(s.fds for s in tail)},
        "threads": {"first": samples[0].threads, "last": last.threads,
                    "max": max(s.threads for s in samples)},
        "seconds": round(last.seconds, 1),
    }  # fmt: skip


def to_rows(samples: list[Sample]) -> list[dict[str, object]]:
    """The samples as JSON-ready rows."""
    return [{k: (round(v, 2) if isinstance(v, float) else v) for k, v in asdict(s).items()}
            for s in samples]  # fmt: skip


def log_progress(every: int) -> Callable[[Sample], None]:
    """A progress callback printing every `every`-th sample on stderr."""

    def report(sample: Sample) -> None:
        if (sample.episode + 1) % every == 0:
            sys.stderr.write(
                f"episode {sample.episode + 1}: rss {sample.rss_mb:.1f} MB, fds {sample.fds}, "
                f"threads {sample.threads}, {sample.seconds:.0f} s\n"
            )
            sys.stderr.flush()

    return report


__all__ = ["Sample", "log_progress", "open_fds", "resident_bytes", "soak", "summary", "threads"]
