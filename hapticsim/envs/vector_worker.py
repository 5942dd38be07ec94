"""The worker side of :class:`~hapticsim.envs.vector.HapticVectorEnv`: a shard of environments
in a worker process (:class:`Shard`, served by :func:`serve`), and the idle-priority helper
that draws their next episodes ahead (:func:`draw_ahead`)."""

from __future__ import annotations

import os
import traceback
from multiprocessing.connection import Connection, wait
from typing import Any

import gymnasium as gym
from gymnasium.vector import AutoresetMode

from hapticsim.envs.episode_draw import EpisodeDraw
from hapticsim.envs.haptic_explore_v0 import HapticExploreEnv
from hapticsim.errors import InvalidInputError
from hapticsim.parallel.base import limit_threads

#: Info keys whose value stays the same object for a whole episode: a worker sends them once per
#: episode and the vector environment puts its copy back (a mesh truth is megabytes).
EPISODE_CONSTANT_INFO: tuple[str, ...] = ("truth",)
#: What a worker sends instead of an episode-constant value it has sent before.
SAME = "__hapticsim_same__"


def explore_core(env: gym.Env) -> HapticExploreEnv | None:
    """The :class:`HapticExploreEnv` at the core of `env` (``env.unwrapped``: every variant is a
    wrapper of it), or None."""
    core = env.unwrapped
    return core if isinstance(core, HapticExploreEnv) else None


def batch_priority() -> None:
    """Let this process's wakeups not preempt the running one (Linux ``SCHED_BATCH``: the same
    share of the cores, only no preemption on wakeup; elsewhere nothing)."""
    try:
        os.sched_setscheduler(0, os.SCHED_BATCH, os.sched_param(0))  # type: ignore[attr-defined]
    except (AttributeError, OSError):
        pass


def idle_priority() -> None:
    """Run this process only on a core nobody else wants (Linux ``SCHED_IDLE``; elsewhere the
    lowest nice level)."""
    try:
        os.sched_setscheduler(0, os.SCHED_IDLE, os.sched_param(0))  # type: ignore[attr-defined]
    except (AttributeError, OSError):
        try:
            os.nice(19)
        except (AttributeError, OSError):
            pass


def draw_ahead(conn: Connection, other_end: Connection | None = None) -> None:
    """A worker's helper process: draw its environments' next episodes
    (:meth:`~hapticsim.envs.episode_draw.EpisodeDrawer.draw`) at idle priority, so that
    the vision estimate a reset needs is made while the worker waits for the other shards.

    Messages: ``("drawers", {j: drawer})`` once, then ``("draw", j, generator)``; every request
    is answered, ``(j, draw)`` or ``(j, None)``: of several requests for one environment only
    the newest is drawn, and a draw that fails is not sent (the reset draws itself and raises
    there). `other_end` (the worker's end of the pipe, inherited by a forked helper) is closed at
    once, so that the helper sees the pipe end when the worker does.
    """
    if other_end is not None:
        other_end.close()
    idle_priority()
    limit_threads()
    drawers: dict[int, Any] = {}
    while True:
        try:
            pending = [conn.recv()]
            while conn.poll():
                pending.append(conn.recv())
        except (EOFError, OSError, KeyboardInterrupt):
            break
        requests: dict[int, Any] = {}
        answers: list[tuple[int, Any]] = []
        for message in pending:
            if message[0] == "drawers":
                drawers = message[1]
            else:
                if message[1] in requests:  # superseded
                    answers.append((message[1], None))
                requests[message[1]] = message[2]
        try:
            for answer in answers:
                conn.send(answer)
            for j, rng in requests.items():
                try:
                    draw = drawers[j].pack(drawers[j].draw(rng))
                except Exception:  # noqa: BLE001 - the reset will draw itself and report it
                    draw = None
                conn.send((j, draw))
        except (OSError, EOFError):
            return
    conn.close()


class Shard:
    """Environments stepped one after the other (in a worker process, or in this one)."""

    def __init__(self, env_id: str, kwargs: dict[str, Any], size: int, mode: AutoresetMode,
                 first: int = 0, helper: Connection | None = None) -> None:  # fmt: skip
        # (importing this module imported hapticsim, which registered the ids)
        self.env_id, self.kwargs, self.size = env_id, kwargs, size
        #: the pipe to the process that draws the environments' next episodes ahead, or None
        self.helper = helper
        self._asked = 0  # requests the helper has not answered yet
        self._cores: list[HapticExploreEnv | None] = []
        self.first = first  # index of the shard's first environment in the batch
        self.current = first  # the environment being made or stepped (named in errors)
        self.envs: list[gym.Env] = []
        self.mode = mode
        self.autoreset = [False] * size
        self._sent: list[dict[str, Any]] = [{} for _ in range(size)]

    def make(self) -> list[None]:
        """Make the shard's environments (``gym.make``, as Gymnasium's SyncVectorEnv does)."""
        for j in range(self.size):
            self.current = self.first + j
            self.envs.append(gym.make(self.env_id, **self.kwargs))
        self._cores = [explore_core(env) for env in self.envs]
        drawers = {j: core.drawer for j, core in enumerate(self._cores) if core is not None}
        if drawers:
            self._to_helper("drawers", drawers)
        else:
            self.helper = None
        return []

    # ------------------------------------------------------------------ draws ahead
    def _to_helper(self, *message: Any) -> None:
        if self.helper is None:
            return
        try:
            self.helper.send(message)
        except (OSError, EOFError):  # the helper is gone: every reset draws its own
            self.helper = None

    def _ask_ahead(self, j: int) -> None:
        """Ask the helper for environment j's next episode, drawn from a copy of its generator
        as it is now (nothing else draws from it until the next reset; a reset that is seeded
        or given a shape draws its own)."""
        core = self._cores[j]
        # A helper starved of CPU (a machine busy with other work) is not asked more than this,
        # so that its pipe never fills and a send never blocks the worker.
        if self.helper is not None and core is not None and self._asked < 2 * self.size:
            self._to_helper("draw", j, core.np_random)
            self._asked += 1

    def collect(self) -> None:
        """Hand the draws the helper has finished to their environments (without waiting)."""
        try:
            while self.helper is not None and self.helper.poll():
                j, draw = self.helper.recv()
                self._asked -= 1
                core = self._cores[j]
                if core is not None and isinstance(draw, EpisodeDraw):
                    core.offer_draw(draw)
        except (OSError, EOFError):
            self.helper = None

    def _reset_env(self, j: int, **kwargs: Any) -> tuple[Any, dict[str, Any]]:
        self.collect()
        out = self.envs[j].reset(**kwargs)
        self._ask_ahead(j)
        return out

    def _pack(self, j: int, info: dict[str, Any]) -> dict[str, Any]:
        """`info` with the episode-constant values already sent replaced by a marker."""
        for key in EPISODE_CONSTANT_INFO:
            if key in info:
                if key in self._sent[j] and info[key] is self._sent[j][key]:
                    info = {**info, key: SAME}
                else:
                    self._sent[j][key] = info[key]
        return info

    def reset(self, seeds: list[int | None], options: dict[str, Any] | None, mask: list[bool]):
        out = []
        for j, (seed, on) in enumerate(zip(seeds, mask, strict=True)):
            if not on:
                out.append(None)
                continue
            self.current = self.first + j
            obs, info = self._reset_env(j, seed=seed, options=options)
            self.autoreset[j] = False
            out.append((obs, self._pack(j, info)))
        return out

    def _step_one(self, j: int, action: Any) -> tuple:
        env = self.envs[j]
        extra: dict[str, Any] = {}
        if self.mode == AutoresetMode.NEXT_STEP and self.autoreset[j]:
            obs, info = self._reset_env(j)
            reward, terminated, truncated = 0.0, False, False
        else:
            obs, reward, terminated, truncated, info = env.step(action)
            if self.mode == AutoresetMode.SAME_STEP and (terminated or truncated):
                extra = {"final_obs": obs, "final_info": info}
                obs, info = self._reset_env(j)
        self.autoreset[j] = bool(terminated or truncated)
        return obs, float(reward), bool(terminated), bool(truncated), extra, info

    def step(self, actions: Any):
        out = []
        for j, action in enumerate(actions):
            self.current = self.first + j
            obs, reward, terminated, truncated, extra, info = self._step_one(j, action)
            if extra:
                extra["final_info"] = self._pack(j, extra["final_info"])
            out.append((obs, reward, terminated, truncated, extra, self._pack(j, info)))
        return out

    def call(self, name: str, args: tuple, kwargs: dict[str, Any]) -> list[Any]:
        out = []
        for j, env in enumerate(self.envs):
            self.current = self.first + j
            attr = env.get_wrapper_attr(name)
            out.append(attr(*args, **kwargs) if callable(attr) else attr)
        return out

    def set_attr(self, name: str, values: list[Any]) -> list[None]:
        for env, value in zip(self.envs, values, strict=True):
            env.set_wrapper_attr(name, value)
        return [None] * len(self.envs)

    def spaces(self) -> tuple[Any, Any, Any]:
        """The first environment's observation and action spaces and frame rate."""
        env = self.envs[0]
        return env.observation_space, env.action_space, env.metadata.get("render_fps")

    def close(self) -> None:
        for env in self.envs:
            env.close()


def failure(index: int, exc: BaseException) -> tuple[int, bool, str, str, str]:
    """What a worker reports of an exception: the environment, whether it is bad input (raised
    again as :class:`InvalidInputError` in the parent), its type, message and traceback."""
    invalid = isinstance(exc, InvalidInputError)
    return index, invalid, type(exc).__name__, str(exc), traceback.format_exc()


def serve(conn: Connection, env_id: str, kwargs: dict[str, Any], size: int, mode: str,
           first: int, helper: Connection | None = None, batch: bool = False) -> None:  # fmt: skip
    """A worker process: answer the vector environment's commands until told to close; while
    waiting for one, take in the draws its helper process (if any) has finished."""
    # One BLAS/OpenMP thread per worker, as in hapticsim's other process pools: the workers
    # already fill the cores (on 2 cores and 8 environments no difference was measurable).
    limit_threads()
    if batch:
        batch_priority()
    shard = Shard(env_id, kwargs, size, AutoresetMode(mode), first, helper)
    while True:
        try:
            while shard.helper is not None and conn not in wait([conn, shard.helper]):
                shard.collect()
            command, data = conn.recv()
        except (EOFError, KeyboardInterrupt):
            break
        try:
            if command == "close":
                shard.close()
                conn.send(("ok", None))
                break
            conn.send(("ok", getattr(shard, command)(*data)))
        except BaseException as exc:  # noqa: BLE001 - reported to the parent, which raises
            conn.send(("error", failure(shard.current, exc)))
    conn.close()


__all__ = ["EPISODE_CONSTANT_INFO", "SAME", "Shard", "draw_ahead", "explore_core", "serve"]
