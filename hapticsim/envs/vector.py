"""A native vector environment: N hapticsim environments in a few worker processes.

``gym.make_vec("hapticsim/HapticExplore-v0", num_envs=8)`` (``vectorization_mode`` None or
``"vector_entry_point"``) makes a :class:`HapticVectorEnv`: the N environments are split into
``workers`` contiguous shards (by default one per CPU core), and each worker process steps its
shard one environment after the other. A vector step then waits for the slowest *shard*, the sum
of N / workers step times, instead of the slowest environment as Gymnasium's
``AsyncVectorEnv`` (one process per environment) does: a step's cost varies by 20x (a full fit,
a refinement, a kept estimate, a reset), and over a shard the spread averages out.

Why processes and not threads: the compiled kernels release the GIL, but half of an analytic
step is Python (the touch's section walk, the fitter's driver, the observation), so a pool of
two threads stepping 8 environments gives 1.31x one (analytic; ``docs/vector.md``).

What a worker does while it waits for the others: each worker has a helper process at idle
priority (Linux ``SCHED_IDLE``) that draws its environments' next episodes ahead, the object
and its vision estimate (:class:`~hapticsim.envs.episode_draw.EpisodeDrawer`, most of a
reset's time), from a copy of each environment's generator, which nothing touches between two
resets; a reset that finds its draw ready skips that work, one that does not draws its own.
The workers run as ``SCHED_BATCH`` processes, whose wakeups do not preempt this process, so
every worker has its actions before any starts. Neither changes a result.

Each environment is made by ``gym.make(env_id, **kwargs)`` in its worker, as Gymnasium's
``SyncVectorEnv`` makes it, and seeded as there (``reset(seed=s)`` seeds environment i with
``s + i``), so every environment of the batch gives the results it gives alone, bit for bit
(``tests/envs/test_vector.py``). Autoreset as Gymnasium 1.x defines it: ``NEXT_STEP`` by default,
``SAME_STEP`` and ``DISABLED`` on request (``autoreset_mode``).
"""

from __future__ import annotations

import multiprocessing
import os
from copy import deepcopy
from multiprocessing.connection import wait
from typing import Any

import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space, concatenate, create_empty_array, iterate

from hapticsim._validate import positive_int
from hapticsim.envs.vector_worker import (
    EPISODE_CONSTANT_INFO,
    SAME,
    Shard,
    draw_ahead,
    serve,
)
from hapticsim.errors import ChoiceError, HapticsimError, InvalidInputError
from hapticsim.parallel.base import RemoteTraceback

#: Seconds to wait for a worker to shut down before it is terminated.
CLOSE_TIMEOUT: float = 10.0
#: Seconds to wait for a worker's helper (which holds nothing to save) before it is terminated.
HELPER_CLOSE_TIMEOUT: float = 1.0


class VectorEnvError(HapticsimError):
    """An environment of a :class:`HapticVectorEnv` failed, or its worker died."""


def default_workers(num_envs: int) -> int:
    """Worker processes for `num_envs` environments: one per usable CPU core, at most N."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        cores = os.cpu_count() or 1
    return max(1, min(int(num_envs), cores))


def _autoreset_mode(value: str | AutoresetMode) -> AutoresetMode:
    """An :class:`AutoresetMode` from itself, its value (``"NextStep"``) or its snake-case
    name (``"next_step"``)."""
    if isinstance(value, AutoresetMode):
        return value
    key = str(value).replace("_", "").lower()
    for mode in AutoresetMode:
        if mode.value.lower() == key:
            return mode
    choices = ["next_step", "same_step", "disabled"]
    raise ChoiceError("autoreset_mode", value, choices)


class _Remote:
    """A shard in a worker process (same commands as :class:`Shard`, sent through a pipe)."""

    def __init__(self, context: Any, env_id: str, kwargs: dict[str, Any], size: int,
                 mode: AutoresetMode, first: int, name: str, ahead: bool,
                 batch: bool) -> None:  # fmt: skip
        self.conn, child = context.Pipe()
        self.helper = None
        worker_end = helper_end = None
        if ahead:  # (started by us: a worker, a daemon, may not start processes)
            worker_end, helper_end = context.Pipe()
            self.helper = context.Process(target=draw_ahead, args=(helper_end, worker_end),
                                          name=f"{name}-ahead", daemon=True)  # fmt: skip
            self.helper.start()
            helper_end.close()
        self.process = context.Process(
            target=serve,
            args=(child, env_id, kwargs, size, mode.value, first, worker_end, batch),
            name=name, daemon=True,
        )  # fmt: skip
        self.process.start()
        child.close()
        if worker_end is not None:
            worker_end.close()
        self.name = name

    def send(self, command: str, *data: Any) -> None:
        try:
            self.conn.send((command, data))
        except (BrokenPipeError, ConnectionResetError, EOFError) as exc:
            self.process.join(1.0)
            code = self.process.exitcode
            raise VectorEnvError(f"worker {self.name} died (exit code {code})") from exc

    def receive(self) -> Any:
        try:
            status, payload = self.conn.recv()
        except (EOFError, ConnectionResetError, BrokenPipeError) as exc:
            code = self.process.exitcode
            raise VectorEnvError(f"worker {self.name} died (exit code {code})") from exc
        if status == "error":
            index, invalid, kind, message, trace = payload
            if invalid:  # bad input: the error a single environment gives
                raise InvalidInputError(f"environment {index}: {message}") from RemoteTraceback(
                    trace
                )
            raise VectorEnvError(
                f"environment {index} (worker {self.name}) failed: {kind}: {message}"
            ) from RemoteTraceback(trace)
        return payload

    def close(self) -> None:
        if self.process.is_alive():
            try:
                self.conn.send(("close", ()))
                if self.conn.poll(CLOSE_TIMEOUT):
                    self.conn.recv()
            except (EOFError, OSError):
                pass
            self.process.join(CLOSE_TIMEOUT)
        if self.process.is_alive():
            self.process.terminate()
            self.process.join()
        self.conn.close()
        if self.helper is not None:  # it ends when the worker's end of its pipe closes
            self.helper.join(HELPER_CLOSE_TIMEOUT)
            if self.helper.is_alive():
                self.helper.terminate()
                self.helper.join()


class _Local:
    """A shard in this process (``workers=0``), behind the same send/receive interface."""

    def __init__(self, shard: Shard) -> None:
        self.shard = shard
        self._result: Any = None

    def send(self, command: str, *data: Any) -> None:
        try:
            self._result = ("ok", getattr(self.shard, command)(*data))
        except Exception as exc:  # noqa: BLE001 - raised by receive, as a worker's would be
            self._result = ("error", exc)

    def receive(self) -> Any:
        status, payload = self._result
        self._result = None
        if status == "error":
            index = self.shard.current
            if isinstance(payload, InvalidInputError):
                raise InvalidInputError(f"environment {index}: {payload}") from payload
            raise VectorEnvError(
                f"environment {index} failed: {type(payload).__name__}: {payload}"
            ) from payload
        return payload

    def close(self) -> None:
        self.shard.close()


class HapticVectorEnv(VectorEnv):
    """N hapticsim environments of one id, stepped in `workers` processes (shards).

    Made by ``gym.make_vec(env_id, num_envs=N, **kwargs)`` (the ids register this class as their
    vector entry point) or directly. Observations, rewards, flags and infos are batched as by
    Gymnasium's ``SyncVectorEnv`` (infos: a dict of arrays with ``_key`` masks; ``truth``,
    ``estimate`` and ``solid`` as object arrays).

    Errors: bad input raises :class:`InvalidInputError` naming the environment, other failures
    :class:`VectorEnvError`. The shards step at once, so in a step that fails, the environments
    of the other shards (and those before the failed one in its shard) have stepped.

    Args:
        env_id: a hapticsim environment id, e.g. ``"hapticsim/HapticExplore-v0"``.
        num_envs: environments, >= 1.
        workers: worker processes, 0 to step all environments in this process; default one per
            usable CPU core (at most `num_envs`). The shards are contiguous blocks of
            environments, of sizes that differ by at most one (the first ones larger).
        autoreset_mode: ``"next_step"`` (default), ``"same_step"`` or ``"disabled"``
            (:class:`gymnasium.vector.AutoresetMode`).
        copy: return copies of the batched observation (as ``SyncVectorEnv``; default True).
        context: how worker processes start (``"fork"``, ``"spawn"``, ``"forkserver"``); default
            the platform's (as Gymnasium's ``AsyncVectorEnv``). With ``"spawn"`` a script that
            makes the vector environment needs an ``if __name__ == "__main__":`` guard.
        draw_ahead: give each worker a helper process that draws its environments' next
            episodes (the object and its vision estimate, most of a reset's time) at idle
            priority (Linux ``SCHED_IDLE``), while the worker waits for the other shards
            (default True; no effect with ``workers=0``). Results are the same either way, bit
            for bit; a reset whose draw is not ready, or that is seeded or given a shape, draws
            its own.
        batch_scheduling: run the workers as Linux ``SCHED_BATCH`` processes (default True;
            elsewhere no effect): the same share of the cores, but a worker woken by its actions
            does not preempt this process, which so sends every worker its actions before any
            starts (analytic, 2 cores: about 5 % more steps per second).
        **kwargs: the environments' settings (``backend``, ``objects``, ``touch_budget``, ...).
    """

    def __init__(
        self,
        env_id: str,
        num_envs: int,
        workers: int | None = None,
        autoreset_mode: str | AutoresetMode = AutoresetMode.NEXT_STEP,
        copy: bool = True,
        context: str | None = None,
        draw_ahead: bool = True,
        batch_scheduling: bool = True,
        **kwargs: Any,
    ) -> None:
        self._shards: list[Any] = []  # (before any check: Gymnasium's __del__ closes us)
        self.closed = False
        num_envs = positive_int(num_envs, "num_envs")
        if workers is None:
            workers = default_workers(num_envs)
        if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 0:
            raise InvalidInputError(f"`workers` must be None or an int >= 0, got {workers!r}")
        mode = _autoreset_mode(autoreset_mode)
        for name, flag in (("draw_ahead", draw_ahead), ("batch_scheduling", batch_scheduling)):
            if not isinstance(flag, (bool, np.bool_)):
                raise InvalidInputError(f"`{name}` must be True or False, got {flag!r}")
        if context is not None and context not in multiprocessing.get_all_start_methods():
            raise InvalidInputError(
                f"`context` must be None or one of {multiprocessing.get_all_start_methods()}, "
                f"got {context!r}"
            )
        kwargs.pop("max_episode_steps", None)  # make_vec passes the spec's (None here)
        self.env_id = str(env_id)
        self.num_envs = int(num_envs)
        self.workers = min(int(workers), self.num_envs)
        self.copy = bool(copy)
        self.metadata = {"autoreset_mode": mode, "render_modes": ["rgb_array"]}
        self.render_mode = kwargs.get("render_mode")
        count = max(self.workers, 1)
        sizes = [len(b) for b in np.array_split(np.arange(self.num_envs), count)]
        self._bounds = np.concatenate([[0], np.cumsum(sizes)]).astype(int)
        self._constant: list[dict[str, Any]] = [{} for _ in range(self.num_envs)]
        try:
            if self.workers == 0:
                self._shards = [_Local(Shard(self.env_id, kwargs, self.num_envs, mode))]
            else:
                start = multiprocessing.get_context(context)
                for w, size in enumerate(sizes):
                    first = int(self._bounds[w])
                    self._shards.append(_Remote(start, self.env_id, kwargs, size, mode, first,
                                                f"{w}", bool(draw_ahead),
                                                bool(batch_scheduling)))  # fmt: skip
            self._ask("make", [()] * len(self._shards))
            self._shards[0].send("spaces")
            obs_space, action_space, fps = self._shards[0].receive()
        except BaseException:
            self.close_extras()
            raise
        self.single_observation_space = obs_space
        self.single_action_space = action_space
        self.metadata["render_fps"] = fps
        self.observation_space = batch_space(obs_space, self.num_envs)
        self.action_space = batch_space(action_space, self.num_envs)
        self._observations = create_empty_array(
            self.single_observation_space, self.num_envs, fn=np.zeros
        )
        self._env_obs: list[Any] = [None] * self.num_envs

    # ------------------------------------------------------------------ helpers
    def _ask(self, command: str, per_shard: list[tuple]) -> list[Any]:
        """Send a command to every shard (all at once), then gather their answers in order."""
        if self.closed:
            raise InvalidInputError("the vector environment is closed")
        errors: dict[int, HapticsimError] = {}
        sent: dict[int, Any] = {}
        for k, (shard, data) in enumerate(zip(self._shards, per_shard, strict=True)):
            try:
                shard.send(command, *data)
                sent[k] = shard
            except HapticsimError as exc:
                errors[k] = exc
        # Each worker's answer is read (and unpickled) as soon as it is sent, while the other
        # workers still step; all are read, so that the pipes stay in step after an error.
        answers: dict[int, list[Any]] = {}
        waiting = {shard.conn: k for k, shard in sent.items() if isinstance(shard, _Remote)}
        order = [k for k, shard in sent.items() if not isinstance(shard, _Remote)]
        while order or waiting:
            if not order:
                order = [waiting.pop(conn) for conn in wait(list(waiting))]
            k = order.pop(0)
            try:
                answers[k] = sent[k].receive()
            except HapticsimError as exc:
                errors[k] = exc
        if errors:  # the first shard's error, whichever answered first
            raise errors[min(errors)]
        return [item for k in range(len(self._shards)) for item in answers[k]]

    def _split(self, items: Any) -> list[Any]:
        return [items[a:b] for a, b in zip(self._bounds[:-1], self._bounds[1:], strict=True)]

    def _unpack(self, i: int, info: dict[str, Any]) -> dict[str, Any]:
        for key in EPISODE_CONSTANT_INFO:
            if key in info:
                if isinstance(info[key], str) and info[key] == SAME:
                    info[key] = self._constant[i][key]
                else:
                    self._constant[i][key] = info[key]
        return info

    def _batch(self, obs: list[Any]) -> Any:
        self._observations = concatenate(self.single_observation_space, obs, self._observations)
        return deepcopy(self._observations) if self.copy else self._observations

    # ------------------------------------------------------------------ gymnasium API
    def reset(
        self, *, seed: int | list[int | None] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[Any, dict[str, Any]]:
        """Reset all environments (or those of ``options["reset_mask"]``); an int `seed` seeds
        environment i with ``seed + i``, a list one seed per environment."""
        if seed is None:
            seeds: list[int | None] = [None] * self.num_envs
        elif isinstance(seed, (int, np.integer)) and not isinstance(seed, bool):
            seeds = [int(seed) + i for i in range(self.num_envs)]
        else:
            seeds = list(seed)
            if len(seeds) != self.num_envs:
                raise InvalidInputError(
                    f"`seed` must be None, an int or {self.num_envs} seeds, got {len(seeds)}"
                )
        mask = np.ones(self.num_envs, bool)
        if options is not None and "reset_mask" in options:
            mask = np.asarray(options["reset_mask"])
            if mask.shape != (self.num_envs,) or mask.dtype != np.bool_ or not mask.any():
                raise InvalidInputError(
                    f"`options['reset_mask']` must be ({self.num_envs},) bool with a True, got "
                    f"{mask.shape} {mask.dtype}"
                )
        requests = [(s, options, m) for s, m in zip(
            self._split(seeds), self._split(mask.tolist()), strict=True)]  # fmt: skip
        answers = self._ask("reset", requests)
        infos: dict[str, Any] = {}
        obs = []
        for i, answer in enumerate(answers):
            if answer is None:  # not reset: keep its last observation
                obs.append(self._env_obs[i])
                continue
            o, info = answer
            obs.append(o)
            infos = self._add_info(infos, self._unpack(i, info), i)
        self._env_obs = obs
        return self._batch(obs), infos

    def step(self, actions: Any) -> tuple[Any, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        """Step every environment with its action (a batch of the action space)."""
        actions = list(iterate(self.action_space, actions))
        if len(actions) != self.num_envs:
            raise InvalidInputError(f"expected {self.num_envs} actions, got {len(actions)}")
        answers = self._ask("step", [(a,) for a in self._split(actions)])
        rewards = np.zeros(self.num_envs)
        terminations = np.zeros(self.num_envs, bool)
        truncations = np.zeros(self.num_envs, bool)
        infos: dict[str, Any] = {}
        obs = []
        for i, (o, r, te, tr, extra, info) in enumerate(answers):
            obs.append(o)
            rewards[i], terminations[i], truncations[i] = r, te, tr
            if extra:
                extra["final_info"] = self._unpack(i, extra["final_info"])
                infos = self._add_info(infos, extra, i)
            infos = self._add_info(infos, self._unpack(i, info), i)
        self._env_obs = obs
        return self._batch(obs), rewards, terminations, truncations, infos

    def call(self, name: str, *args: Any, **kwargs: Any) -> tuple[Any, ...]:
        """Call a method (or read an attribute) of every environment; one result each."""
        return tuple(self._ask("call", [(name, args, kwargs)] * len(self._shards)))

    def get_attr(self, name: str) -> tuple[Any, ...]:
        """An attribute of every environment."""
        return self.call(name)

    def set_attr(self, name: str, values: list[Any] | tuple[Any, ...] | Any) -> None:
        """Set an attribute of every environment (one value each, or the same for all)."""
        if not isinstance(values, (list, tuple)):
            values = [values] * self.num_envs
        if len(values) != self.num_envs:
            raise InvalidInputError(
                f"`values` must have {self.num_envs} entries, got {len(values)}"
            )
        self._ask("set_attr", [(name, v) for v in self._split(list(values))])

    def render(self) -> tuple[Any, ...] | None:
        """Every environment's picture (``render_mode="rgb_array"``)."""
        return self.call("render")

    def close_extras(self, **kwargs: Any) -> None:
        """Close the environments and stop the workers."""
        for shard in self._shards:
            shard.close()
        self._shards = []
