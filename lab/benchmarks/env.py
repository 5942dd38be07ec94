"""Speed of ``hapticsim/HapticExplore-v0``: environment steps per second in one process."""

from __future__ import annotations

import multiprocessing
import os
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import gymnasium as gym
import numpy as np

from hapticsim.envs.haptic_explore_v0 import HapticExploreConfig
from hapticsim.envs.registration import HAPTIC_EXPLORE_ID, register_envs
from hapticsim.envs.vector import default_workers
from hapticsim.errors import InvalidInputError

#: Steps before timing a vector environment (its workers load the compiled code first).
WARMUP_STEPS: int = 20


def _warm_objects(env: Any, backend: str, env_kwargs: dict[str, Any]) -> None:
    """Reset `env` (one environment or a vector of them) once on each object its distribution
    returns as it is (the paper bodies), so that every environment has built its scenes before
    the clock starts: the hand compiles a new object's scene once (~50 ms), and a vector of 8
    environments would otherwise compile 8 times what one environment compiles inside the
    timed steps."""
    for solid in HapticExploreConfig(backend=backend, **env_kwargs).objects.fixed_solids():
        env.reset(options={"shape": solid})


def benchmark_env(
    backend: str = "analytic",
    episodes: int = 3,
    seed: int = 0,
    objects: str = "paper",
    progress: bool = True,
    warmup: int = 1,
    **env_kwargs: Any,
) -> dict[str, Any]:
    """Time random-policy episodes of the environment (default settings otherwise).

    Args:
        backend: ``"analytic"`` or ``"mujoco"``.
        episodes: episodes to run (seeds ``seed .. seed + episodes - 1``), >= 1.
        seed: first seed (environment and actions).
        objects: object distribution kind.
        progress: print a line per episode on stderr.
        warmup: untimed episodes first (seeds from ``seed + episodes`` on): a fresh
            process loads the compiled code in its first fits (the cold and warm first fit are
            timed by ``scripts/bench.py --section startup``).
        **env_kwargs: further environment settings.

    Returns:
        ``steps_per_second`` (wall clock, resets excluded), ``steps_per_cpu_second`` (process
        CPU time, which a loaded machine changes less), the same two with the resets counted
        (``..._with_resets``: what a training loop sees), ``reset_seconds`` per episode, mean
        ``seconds_per_step`` of the touch, the fit and the metrics, and the fraction of steps
        that ran a full fit.
    """

    if episodes < 1:
        raise InvalidInputError(f"`episodes` must be >= 1, got {episodes}")
    register_envs()
    env = gym.make(HAPTIC_EXPLORE_ID, backend=backend, objects=objects, **env_kwargs)
    env.action_space.seed(seed)
    for k in range(warmup):  # untimed: the first steps of a process load the compiled code
        env.reset(seed=seed + episodes + k)
        done = False
        while not done:
            _, _, terminated, truncated, _ = env.step(env.action_space.sample())
            done = terminated or truncated
    steps, full = 0, 0
    parts = {"touch": 0.0, "fit": 0.0, "metrics": 0.0}
    reset_wall = reset_cpu = 0.0
    wall0, cpu0 = time.perf_counter(), time.process_time()
    for ep in range(episodes):
        t, c = time.perf_counter(), time.process_time()
        env.reset(seed=seed + ep)
        reset_wall += time.perf_counter() - t
        reset_cpu += time.process_time() - c
        done = False
        while not done:
            _, _, terminated, truncated, info = env.step(env.action_space.sample())
            for k in parts:
                parts[k] += getattr(info["timings"], k)
            full += info["fit_status"] == "full"
            steps += 1
            done = terminated or truncated
        if progress:
            print(f"bench env {backend}: episode {ep + 1}/{episodes}", file=sys.stderr)
    wall_all = time.perf_counter() - wall0
    cpu_all = time.process_time() - cpu0
    wall, cpu = wall_all - reset_wall, cpu_all - reset_cpu
    env.close()
    return {
        "backend": backend,
        "objects": objects,
        "episodes": episodes,
        "steps": steps,
        "steps_per_second": steps / wall,
        "steps_per_cpu_second": steps / cpu,
        "steps_per_second_with_resets": steps / wall_all,
        "steps_per_cpu_second_with_resets": steps / cpu_all,
        "reset_seconds": reset_wall / episodes,
        "seconds_per_step": {k: v / steps for k, v in parts.items()},
        "full_fit_fraction": full / steps,
    }


def benchmark_touch(
    episodes: int = 20,
    seed: int = 0,
    hand: str = "hapticsim",
    progress: bool = True,
    **env_kwargs: Any,
) -> dict[str, Any]:
    """The MuJoCo backend's share of a step: the touch and the reset (issue 9 item 5).

    Random actions on ``HapticExplore-v0(backend="mujoco")``, default settings otherwise.
    The first episode of each paper body compiles its scene (~0.1 s); later ones reuse it
    (:class:`~hapticsim.sim.scene.SceneCache`), so the reset is given per episode and amortised
    over all episodes.

    Args:
        episodes: episodes (seeds ``seed .. seed + episodes - 1``), >= 1.
        seed: first seed (environment and actions).
        hand: the hand.
        progress: print a line per episode on stderr.
        **env_kwargs: further environment settings.

    Returns:
        ``touch_seconds`` (median, mean, p90 of ``info["timings"].touch``), ``reset_seconds``
        (median, mean = amortised, first, max), ``step_seconds`` (median), ``cpu_seconds``
        (process CPU time of the touch, of the environment's reset and of the backend's part of
        it, which a loaded machine inflates less), ``steps``, ``touch_statuses`` (counts) and
        the ``load_average`` before and after.
    """

    if episodes < 1:
        raise InvalidInputError(f"`episodes` must be >= 1, got {episodes}")
    register_envs()
    load = list(os.getloadavg()) if hasattr(os, "getloadavg") else None
    env = gym.make(HAPTIC_EXPLORE_ID, backend="mujoco", hand=hand, **env_kwargs)
    env.action_space.seed(seed)
    touch, step, reset = [], [], []
    # process CPU time of the backend's touch and reset: on a loaded machine the wall clock
    # counts the other processes too
    cpu: dict[str, list[float]] = {"touch": [], "reset": [], "backend_reset": []}
    backend = env.unwrapped._backend

    def timed(name: str, method: Any) -> Any:
        def call(*args: Any, **kwargs: Any) -> Any:
            t = time.process_time()
            try:
                return method(*args, **kwargs)
            finally:
                cpu[name].append(time.process_time() - t)

        return call

    backend.touch = timed("touch", backend.touch)
    backend.reset = timed("backend_reset", backend.reset)
    statuses: dict[str, int] = {}
    for ep in range(episodes):
        t, c = time.perf_counter(), time.process_time()
        env.reset(seed=seed + ep)
        reset.append(time.perf_counter() - t)
        cpu["reset"].append(time.process_time() - c)
        done = False
        while not done:
            _, _, terminated, truncated, info = env.step(env.action_space.sample())
            touch.append(info["timings"].touch)
            step.append(info["timings"].step)
            statuses[info["touch_status"]] = statuses.get(info["touch_status"], 0) + 1
            done = terminated or truncated
        if progress:
            print(f"bench touch ({hand}): episode {ep + 1}/{episodes}", file=sys.stderr)
    env.close()
    return {
        "backend": "mujoco",
        "hand": hand,
        "episodes": episodes,
        "steps": len(touch),
        "touch_seconds": {"median": float(np.median(touch)), "mean": float(np.mean(touch)),
                          "p90": float(np.percentile(touch, 90))},
        "reset_seconds": {"median": float(np.median(reset)), "mean": float(np.mean(reset)),
                          "first": reset[0], "max": float(np.max(reset))},
        "step_seconds": {"median": float(np.median(step))},
        "cpu_seconds": {
            "touch_median": float(np.median(cpu["touch"])),
            "touch_mean": float(np.mean(cpu["touch"])),
            "reset_mean": float(np.mean(cpu["reset"])),
            "reset_median": float(np.median(cpu["reset"])),
            "backend_reset_mean": float(np.mean(cpu["backend_reset"])),
            "backend_reset_median": float(np.median(cpu["backend_reset"])),
        },
        "touch_statuses": statuses,
        "load_average": {"before": load, "after": list(os.getloadavg()) if load else None},
    }  # fmt: skip


def _single_steps(
    backend: str, seed: int, steps: int, env_kwargs: dict[str, Any], barrier: Any = None
) -> tuple[list[float], float, float, list[float]]:
    """Wall time [s] of each of `steps` random steps of one environment (a reset inside the
    step that needs it, as a vector environment's autoreset does), after a warm-up; the clock
    at the start and end of the timed steps; and the reset's share of each step time [s] (0
    without one). With a `barrier`, the timed steps start when
    every party has warmed up (several processes running at once)."""

    register_envs()
    env = gym.make(HAPTIC_EXPLORE_ID, backend=backend, **env_kwargs)
    env.action_space.seed(seed)
    _warm_objects(env, backend, env_kwargs)
    env.reset(seed=seed)
    for _ in range(WARMUP_STEPS):  # the first fits load the compiled code
        env.step(env.action_space.sample())
    env.reset(seed=seed)
    if barrier is not None:
        barrier.wait()
    times = []
    resets = []
    begin = time.perf_counter()
    for _ in range(steps):
        t = time.perf_counter()
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        r = time.perf_counter()
        if terminated or truncated:
            env.reset()
        times.append(time.perf_counter() - t)
        resets.append(time.perf_counter() - r)
    end = time.perf_counter()
    env.close()
    return times, begin, end, resets


def _free_running(args: tuple[str, int, int, dict[str, Any], Any]) -> tuple[int, float, float]:
    """One of several independent single environments started together: (steps, start, end)."""
    backend, seed, steps, env_kwargs, barrier = args
    _, begin, end, _ = _single_steps(backend, seed, steps, env_kwargs, barrier)
    return steps, begin, end


def lockstep_bound(step_seconds: Any, num_envs: int, draws: int = 200, seed: int = 0) -> float:
    """The speed-up a lockstep vector environment can reach at most with these step times.

    A vector step waits for the slowest of its `num_envs` environments, so with independent
    step times X its rate is ``num_envs / E[max(X_1..X_n)]`` against ``1 / E[X]`` for one
    environment (with one core per environment and no communication cost). The expectation is
    taken over random groupings of the measured times.
    """

    x = np.asarray(step_seconds, dtype=float)
    gen = np.random.default_rng(seed)
    slowest = np.mean(
        [np.max([gen.permutation(x) for _ in range(num_envs)], axis=0).mean() for _ in range(draws)]
    )
    return float(num_envs * x.mean() / slowest)


def shard_estimate(step_seconds: Any, reset_seconds: Any, num_envs: int, shards: int,
                draws: int = 400, seed: int = 0) -> float:  # fmt: skip
    """The speed-up N environments in `shards` processes (N / shards each, one core per
    process) would reach with these step times, were the environments' step times independent.

    A vector step waits for the slowest shard, whose time is the sum of its environments' step
    times: the rate is ``N / (E[max_w sum_{i in w} X_i] + N / shards * E[R])`` against
    ``1 / E[X + R]`` for one environment, X a step's time without its reset and R the reset's
    (0 in most steps). The expectation over X is taken over random draws of the measured times;
    resets count as balanced, since episodes of one length end in the same vector step. In a
    vector environment the step times of its environments are not independent (they are at the
    same touch, and full fits come at the same touch counts), which balances the shards a
    little better than this estimate.

    Args:
        step_seconds: (k,) float, measured step times [s], resets included.
        reset_seconds: (k,) float, the reset's share of each [s].
        num_envs: environments N.
        shards: worker processes.
    """

    r = np.asarray(reset_seconds, dtype=float)
    x = np.asarray(step_seconds, dtype=float) - r
    gen = np.random.default_rng(seed)
    sizes = [len(b) for b in np.array_split(np.arange(num_envs), shards)]
    slowest = np.mean([max(gen.choice(x, k).sum() for k in sizes) for _ in range(draws)])
    return float(num_envs * (x.mean() + r.mean()) / (slowest + max(sizes) * r.mean()))


#: Vector environments :func:`benchmark_vector_env` can time.
VECTOR_VARIANTS: tuple[str, ...] = ("native", "native_plain", "async", "threads")


def _thread_rate(backend: str, num_envs: int, steps: int, seed: int,
                 env_kwargs: dict[str, Any]) -> float:  # fmt: skip
    """Steps per second of N environments in this process, each vector step's N environment
    steps run by a pool of one thread per core (the compiled kernels release the GIL)."""
    envs = [gym.make(HAPTIC_EXPLORE_ID, backend=backend, **env_kwargs) for _ in range(num_envs)]
    for k, env in enumerate(envs):
        env.action_space.seed(seed + k)
        _warm_objects(env, backend, env_kwargs)
        env.reset(seed=seed + k)

    def one(env: gym.Env) -> None:
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            env.reset()

    with ThreadPoolExecutor(default_workers(num_envs)) as pool:
        for _ in range(WARMUP_STEPS):
            list(pool.map(one, envs))
        rounds = max(1, steps // num_envs)
        start = time.perf_counter()
        for _ in range(rounds):
            list(pool.map(one, envs))
        rate = rounds * num_envs / (time.perf_counter() - start)
    for env in envs:
        env.close()
    return rate


def _parse_variant(variant: str) -> tuple[str, int | None]:
    """The kind of a variant and the workers it names (``"native:W"``), or an error."""
    kind, _, count = variant.partition(":")
    if kind in VECTOR_VARIANTS and not count:
        return kind, None
    if kind == "native" and count.isdigit():
        return kind, int(count)
    raise InvalidInputError(
        f"`variants` must be among {VECTOR_VARIANTS} or 'native:W', got {variant!r}"
    )


def _vector_rate(
    variant: str, backend: str, num_envs: int, steps: int, seed: int, workers: int | None,
    env_kwargs: dict[str, Any],
) -> float:  # fmt: skip
    """Environment steps per second of one vector environment (after its warm-up steps)."""
    kind, own_workers = _parse_variant(variant)
    if kind == "threads":
        return _thread_rate(backend, num_envs, steps, seed, env_kwargs)
    if kind in ("native", "native_plain"):
        workers = workers if own_workers is None else own_workers
        plain = {"draw_ahead": False, "batch_scheduling": False} if kind == "native_plain" else {}
        vec = gym.make_vec(HAPTIC_EXPLORE_ID, num_envs=num_envs, backend=backend,
                           workers=workers, **plain, **env_kwargs)  # fmt: skip
    else:
        vec = gym.make_vec(HAPTIC_EXPLORE_ID, num_envs=num_envs, vectorization_mode="async",
                           backend=backend, **env_kwargs)  # fmt: skip
    vec.action_space.seed(seed)
    _warm_objects(vec, backend, env_kwargs)
    vec.reset(seed=seed)
    for _ in range(WARMUP_STEPS):  # each worker loads the compiled code in its first fits
        vec.step(vec.action_space.sample())
    rounds = max(1, steps // num_envs)
    start = time.perf_counter()
    for _ in range(rounds):
        vec.step(vec.action_space.sample())
    rate = rounds * num_envs / (time.perf_counter() - start)
    vec.close()
    return rate


def benchmark_vector_env(
    backend: str = "analytic",
    num_envs: int = 8,
    steps: int = 1600,
    seed: int = 0,
    variants: tuple[str, ...] = VECTOR_VARIANTS,
    workers: int | None = None,
    repeats: int = 2,
    free_running: bool = True,
    progress: bool = True,
    **env_kwargs: Any,
) -> dict[str, Any]:
    """Steps per second of vector environments against one environment, in the same run.

    The variants and one environment in this process run in turn, `repeats` times (single,
    each variant, single, ...), on the same number of environment steps (resets included, as a
    vector environment resets itself), so that their ratios are measured under the same machine
    load; the medians are reported. Every environment first resets once on each object of its
    distribution that comes back as it is (:func:`_warm_objects`), then steps `WARMUP_STEPS`.
    Variants: ``"native"``, hapticsim's vector environment
    (:class:`~hapticsim.envs.vector.HapticVectorEnv`, `workers` processes of N / workers
    environments each, with its defaults: episodes drawn ahead, batch scheduling);
    ``"native_plain"``, the same without either (``draw_ahead=False,
    batch_scheduling=False``); ``"async"``, Gymnasium's ``AsyncVectorEnv`` (one process per
    environment); ``"threads"``, the N environments in this process, stepped by a pool of one
    thread per core (no vector environment of ours: how far the GIL lets threads go). Optionally
    also two independent single environments in two processes at once
    (*free running*: what the cores give when nobody waits for anybody), and from the single
    environment's step times the *lockstep bound* (:func:`lockstep_bound`): a vector environment
    whose every environment has a core of its own waits for its slowest environment at every
    step, so its speed-up is at most that.

    Args:
        backend: ``"analytic"`` or ``"mujoco"``.
        num_envs: environments of the vector environments, >= 1.
        steps: environment steps to time in each (``steps / num_envs`` vector steps).
        seed: seed of the environments and actions.
        variants: vector environments to time (:data:`VECTOR_VARIANTS`; ``"native:W"`` is
            the native one with W workers).
        workers: worker processes of ``"native"`` (None: one per core).
        repeats: rounds of single + variants, >= 1.
        free_running: also time two free-running processes.
        progress: a line per round on stderr.
        **env_kwargs: further environment settings.

    Returns:
        ``single_steps_per_second`` (median and each round), per variant its
        ``steps_per_second``, ``speedup`` (median over median single) and each round's rate;
        ``free_running_speedup`` (two processes), ``lockstep_bound`` (at `num_envs`, one core
        each), ``shard_estimate`` (:func:`shard_estimate`, the native variant's workers) and the
        single environment's step times (``single_step_ms``: mean, median, p90, max).
    """

    if num_envs < 1 or steps < num_envs or repeats < 1:
        raise InvalidInputError(
            f"need num_envs >= 1, steps >= num_envs and repeats >= 1, got {num_envs}, {steps}, "
            f"{repeats}"
        )
    for variant in variants:  # every name checked before anything runs
        _parse_variant(variant)
    register_envs()
    singles: list[float] = []
    rates: dict[str, list[float]] = {v: [] for v in variants}
    times: list[float] = []
    resets: list[float] = []
    for _ in range(repeats):
        step_times, begin, end, reset_times = _single_steps(backend, seed, steps, env_kwargs)
        times += step_times
        resets += reset_times
        singles.append(steps / (end - begin))
        for variant in variants:
            rates[variant].append(
                _vector_rate(variant, backend, num_envs, steps, seed, workers, env_kwargs)
            )
        if progress:
            line = ", ".join(f"{v} {r[-1]:.1f}" for v, r in rates.items())
            load = os.getloadavg()[0]
            print(f"{backend} round {len(singles)}/{repeats}: single {singles[-1]:.1f}, {line} "
                  f"steps/s (load {load:.2f})", file=sys.stderr, flush=True)  # fmt: skip
    single_rate = float(np.median(singles))
    out: dict[str, Any] = {
        "backend": backend,
        "num_envs": num_envs,
        "steps": int(steps),
        "repeats": repeats,
        "single_steps_per_second": single_rate,
        "single_rounds": singles,
    }
    for variant, values in rates.items():
        out[variant] = {
            "steps_per_second": float(np.median(values)),
            "speedup": float(np.median(values) / single_rate),
            "rounds": values,
        }
    out["native_workers"] = workers
    if free_running:
        context = multiprocessing.get_context("spawn")
        with context.Manager() as manager:
            barrier = manager.Barrier(2)
            jobs = [(backend, seed + k, steps // 2, env_kwargs, barrier) for k in range(2)]
            with context.Pool(2) as pool:
                runs = pool.map(_free_running, jobs)
        out["free_running_speedup"] = sum(n / (e - b) for n, b, e in runs) / single_rate
    ms = np.asarray(times) * 1e3
    out["lockstep_bound"] = lockstep_bound(times, num_envs)
    cores = default_workers(num_envs)
    out["shard_estimate"] = shard_estimate(times, resets, num_envs, workers or cores)
    out["cores"] = cores
    out["single_step_ms"] = {
        "mean": float(ms.mean()), "median": float(np.median(ms)),
        "p90": float(np.percentile(ms, 90)), "max": float(ms.max()),
    }  # fmt: skip
    out["actions"] = "random"
    return out


def step_components(
    backend: str = "analytic", num_envs: int = 8, steps: int = 400, seed: int = 0,
    **env_kwargs: Any,
) -> dict[str, np.ndarray]:  # fmt: skip
    """Where each environment step's time goes, for `num_envs` environments run one after the
    other (seeds ``seed + i``, random actions, a reset inside the step that needs it).

    Returns:
        (num_envs, steps) arrays: ``step`` (wall time [s], reset included), ``touch``, ``fit``
        (the step's timings), ``full`` (bool: the fit was a full one).
    """

    register_envs()
    out: dict[str, list[list[Any]]] = {k: [] for k in ("step", "touch", "fit", "full")}
    for i in range(num_envs):
        env = gym.make(HAPTIC_EXPLORE_ID, backend=backend, **env_kwargs)
        env.action_space.seed(seed + i)
        _warm_objects(env, backend, env_kwargs)
        env.reset(seed=seed + i)
        for _ in range(WARMUP_STEPS):  # the first fits load the compiled code
            env.step(env.action_space.sample())
        env.reset(seed=seed + i)
        rows: dict[str, list[Any]] = {k: [] for k in out}
        for _ in range(steps):
            start = time.perf_counter()
            _, _, terminated, truncated, info = env.step(env.action_space.sample())
            if terminated or truncated:
                env.reset()
            rows["step"].append(time.perf_counter() - start)
            rows["touch"].append(info["timings"].touch)
            rows["fit"].append(info["timings"].fit)
            rows["full"].append(info["fit_status"] == "full")
        env.close()
        for k, v in rows.items():
            out[k].append(v)
    return {k: np.asarray(v) for k, v in out.items()}


def schedule_estimates(components: dict[str, np.ndarray], shards: int = 2,
                       job_cost: float = 1e-4) -> dict[str, float]:  # fmt: skip
    """How busy `shards` cores would be, over the vector steps of these environments' step times,
    under three ways of running a lockstep vector step.

    Each is the efficiency ``sum of all step times / shards / simulated wall time`` (1: no core
    ever waits); the speed-up over one environment is about the free-running speed-up times it.

    - ``static``: contiguous shards, each stepping its environments one after the other (the
      native vector environment today).
    - ``fit_sharing_full`` / ``fit_sharing_all``: as static, but the full fits (or every fit over
      0.3 ms) of a vector step go to a common pool once the shard has touched with all its
      environments; a shard with nothing left takes its own largest pending fit, else another's
      (paying `job_cost` [s] to be handed a fit, and twice more to move one: there and back),
      and the owner finishes the step (metrics, observation) when the fit is back.
    - ``whole_steps``: whole environment steps handed out largest first to whichever core is
      free (environments that could run anywhere: threads without a GIL).

    Args:
        components: :func:`step_components`'s arrays.
        shards: cores (and shards), contiguous blocks of sizes that differ by at most one.
        job_cost: seconds of one message between processes (a fit handed out, or moved one
            way).
    """

    step, touch, fit, full = (np.asarray(components[k]) for k in ("step", "touch", "fit", "full"))
    post = step - touch - fit
    n, count = step.shape
    blocks = np.array_split(np.arange(n), shards)
    owner = np.concatenate([[w] * len(b) for w, b in enumerate(blocks)])

    def shared(s: int, pooled: np.ndarray) -> float:
        clock = np.zeros(shards)
        pending: list[tuple[float, int]] = []
        for i in range(n):  # each shard touches first; fits not pooled run in place
            clock[owner[i]] += touch[i, s]
            if pooled[i]:
                pending.append((fit[i, s], i))
            else:
                clock[owner[i]] += fit[i, s] + post[i, s]
        pending.sort(reverse=True)
        back: list[tuple[float, int]] = []
        while pending:
            w = int(np.argmin(clock))
            own = [job for job in pending if owner[job[1]] == w]
            seconds, i = own[0] if own else pending[0]
            pending.remove((seconds, i))
            clock[w] += seconds + job_cost + (0.0 if owner[i] == w else 2 * job_cost)
            back.append((float(clock[w]), i))
        for ready, i in sorted(back):
            clock[owner[i]] = max(clock[owner[i]], ready) + post[i, s]
        return float(clock.max())

    def whole(s: int) -> float:
        clock = np.zeros(shards)
        for seconds in sorted(step[:, s], reverse=True):
            clock[int(np.argmin(clock))] += seconds
        return float(clock.max())

    ideal = step.sum() / shards
    walls = {
        "static": sum(max(step[b, s].sum() for b in blocks) for s in range(count)),
        "fit_sharing_full": sum(shared(s, full[:, s]) for s in range(count)),
        "fit_sharing_all": sum(shared(s, fit[:, s] > 3e-4) for s in range(count)),
        "whole_steps": sum(whole(s) for s in range(count)),
    }
    return {k: float(ideal / v) for k, v in walls.items()}
