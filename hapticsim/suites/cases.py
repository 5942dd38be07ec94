"""Running one case: make its data, fit or explore, and score the estimate against the truth.

:func:`run_case` is the module-level function the executor maps over a suite's cases. Every
random choice comes from the case's seeds: the *data seed* is keyed by the case's data
parameters (so LS and nH of one run fit the same contacts, and every policy of one run meets the
same object and noise), the *case seed* by all its parameters. Nothing depends on the process,
the engine or the order, so a case gives the same record, bit for bit, wherever it runs.

A case whose fit, exploration or plug-in fails (raises, or returns something that is not a
superquadric) is recorded with ``status = "failed"`` and the error; the run goes on.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from hapticsim.errors import InvalidInputError
from hapticsim.geometry import random_rotation
from hapticsim.parallel import key_of, seed_sequence
from hapticsim.suites.plugins import as_solid, load_fitter, load_policy, make_plugin_policy
from hapticsim.suites.suite import Case

#: Quality measures of every case (SPEC §4), in table order.
QUALITY: tuple[str, ...] = ("epsilon", "alpha", "beta", "iou", "chamfer", "theta")
#: Keys of a case record that hold wall-clock times (left out of the metrics digest).
TIMING_KEYS: tuple[str, ...] = ("seconds", "fit_seconds", "cpu_seconds")
#: Values of a case record's ``status``.
STATUSES: tuple[str, ...] = ("ok", "failed")


@dataclass(frozen=True)
class CaseTask:
    """What a worker needs to run one case (picklable).

    Attributes:
        case: the case.
        fitter: ``MODULE:FUNCTION`` of a plug-in fitter replacing the case's method, or None.
        policy: ``MODULE:CLASS`` of a plug-in policy replacing the case's policy, or None.
    """

    case: Case
    fitter: str | None = None
    policy: str | None = None

    @property
    def label(self) -> str:
        """The case in messages: ``"case 'cube/nH/noise=0.1/run=3' of fit-v1"``."""
        return f"case {self.case.id!r} of {self.case.suite}"


class _PluginError(Exception):
    """A plug-in raised or returned garbage (the case fails; the run goes on)."""


def _seeds(case: Case) -> tuple[np.random.SeedSequence, np.random.SeedSequence]:
    """(data seed, case seed) of a case."""
    data = seed_sequence(case.seed, *key_of({"kind": case.kind, **case.data_params()}))
    full = seed_sequence(case.seed, *key_of({"kind": case.kind, **case.params}))
    return data, full


def _finite(value: Any) -> Any:
    """JSON-safe: non-finite floats become None (NaN is not JSON)."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def run_case(task: CaseTask) -> dict[str, Any]:
    """Run one case; never raises for a failing fit, exploration or plug-in.

    Returns:
        the case record: ``id``, ``group``, ``params``, ``status`` (``"ok"``/``"failed"``),
        ``error`` (None or one line), ``metrics`` (quality measures and what produced them;
        empty when failed), ``estimate`` and ``truth`` (SPEC §6 dicts, or None), ``seconds``
        (wall time of the case [s]), ``fit_seconds`` (of the fit alone [s], None without
        a fit) and ``cpu_seconds`` (CPU time of the worker process during the case [s]: on a
        shared machine the figure that does not grow with the load).
    """
    case = task.case
    start, cpu_start = time.perf_counter(), time.process_time()
    record: dict[str, Any] = {
        "id": case.id, "group": case.group, "params": case.params, "status": "ok",
        "error": None, "metrics": {}, "estimate": None, "truth": None,
    }  # fmt: skip
    timing: dict[str, float | None] = {"fit": None}
    try:
        metrics, estimate = _RUNNERS[case.kind](case, task, timing)
        record["truth"] = metrics.pop("truth")
        record["metrics"] = {k: _finite(v) for k, v in metrics.items()}
        record["estimate"] = None if estimate is None else estimate.to_dict()
    except _PluginError as exc:
        record.update(status="failed", error=str(exc))
    except Exception as exc:  # noqa: BLE001 - a failing case is a result, not a crash
        detail = " ".join(str(exc).split())
        record.update(status="failed", error=f"{type(exc).__name__}: {detail}")
    record["seconds"] = time.perf_counter() - start
    record["fit_seconds"] = timing["fit"]
    record["cpu_seconds"] = time.process_time() - cpu_start
    return record


# ----------------------------------------------------------------------------- fitting
def _fit(
    points: Any, normals: Any, method: str, budget: int | str, rng: np.random.Generator,
    fitter: str | None, timing: dict[str, float | None],
) -> tuple[Any, dict[str, Any]]:  # fmt: skip
    """The estimate of the case's method, or of the plug-in fitter; and what the fit reported."""
    start = time.perf_counter()
    if fitter is None:
        from hapticsim.fitting import fit
        from hapticsim.fitting.driver import method_budget

        evaluations = method_budget(method) if budget == "default" else budget
        result = fit(points, normals, method=method, budget=evaluations, rng=rng)
        timing["fit"] = time.perf_counter() - start
        return result.solid, {
            "fitter": method, "budget": int(evaluations), "evaluations": result.evaluations,
            "fit_status": result.status,
        }  # fmt: skip

    estimate = _plugin_fitter(fitter)(points.copy(), normals.copy())
    timing["fit"] = time.perf_counter() - start
    return estimate, {"fitter": fitter, "budget": None, "evaluations": None, "fit_status": None}


def _quality(
    estimate: Any, truth: Any, points: Any, normals: Any | None, rng: np.random.Generator
) -> dict[str, Any]:
    """epsilon, alpha, beta, IoU, Chamfer, and for superquadrics theta and the EOF of `estimate`
    (SPEC §2, §4; None where a solid has no EOF: a union, a mesh truth's theta); ``parts``
    (the pipeline's scorer, :func:`hapticsim.exploration.score_estimate`)."""
    from hapticsim.exploration.pipeline import quality_metrics, score_estimate

    return quality_metrics(estimate, *score_estimate(estimate, truth, points, normals, None, rng))


def _truth(body: str, rng: np.random.Generator) -> Any:
    """A paper body, or a random (tapered) superquadric in a random orientation."""
    if body not in ("random", "random_tapered"):
        from hapticsim.data.bodies import get_body

        return get_body(body)
    from hapticsim.data.distributions import ObjectDistribution

    shape = ObjectDistribution(kind=body).sample(rng)
    return shape.transformed(random_rotation(rng), np.zeros(3))


def _run_fit(case: Case, task: CaseTask, timing: dict) -> tuple[dict[str, Any], Any]:
    from hapticsim.data.synthetic import paper_dataset
    from hapticsim.fitting.methods import uses_normals

    p = case.params
    data_ss, case_ss = _seeds(case)
    shape_rng, contacts_rng = (np.random.default_rng(s) for s in data_ss.spawn(2))
    fit_rng, score_rng = (np.random.default_rng(s) for s in case_ss.spawn(2))
    truth = _truth(p["body"], shape_rng)
    contacts = paper_dataset(truth, noise=p["noise"], rng=contacts_rng, count=p["count"])
    estimate, info = _fit(
        contacts.points, contacts.normals, p["method"], p["budget"], fit_rng, task.fitter, timing
    )
    normals = contacts.normals if uses_normals(p["method"]) else None
    metrics = _quality(estimate, truth, contacts.points, normals, score_rng)
    return {**metrics, **info, "truth": truth.to_dict()}, estimate


def _run_explore(case: Case, task: CaseTask, timing: dict) -> tuple[dict[str, Any], Any]:
    from hapticsim.data.bodies import get_body
    from hapticsim.exploration import TrialSeeds

    seeds = TrialSeeds.from_case(*_seeds(case), shape_first=False)
    truth = get_body(case.params["body"])
    metrics, estimate = _run_trial(task, seeds, truth, timing)
    return {**metrics, "truth": truth.to_dict()}, estimate


#: Quality measures of an episode that ended without any fit (the environment's convention).
_NO_FIT: dict[str, Any] = {
    "epsilon": 1.0, "alpha": 0.0, "beta": 1.0, "iou": 0.0, "chamfer": None, "theta": None,
    "eof": None,
}  # fmt: skip


def _run_policy(case: Case, task: CaseTask, timing: dict) -> tuple[dict[str, Any], Any]:
    from hapticsim.envs.episodes import run_episode
    from hapticsim.envs.haptic_explore_v0 import HapticExploreEnv
    from hapticsim.envs.policies import make_policy

    p = case.params
    data_ss, case_ss = _seeds(case)
    env_seed = int(data_ss.generate_state(1)[0])
    policy_seed, score_seed = (int(s.generate_state(1)[0]) for s in case_ss.spawn(2))
    env = HapticExploreEnv(
        backend=p["backend"], objects=p["objects"], touch_budget=p["touches"], noise=p["noise"]
    )
    try:
        if task.policy is None:
            policy: Any = make_policy(p["policy"], env, rng=policy_seed)
        else:
            policy = _plugin_policy(task.policy, env, policy_seed)
        try:
            record = run_episode(env, policy, seed=env_seed, policy_seed=policy_seed)
        except Exception as exc:
            if task.policy is None:
                raise
            detail = " ".join(str(exc).split())
            raise _PluginError(
                f"the episode with policy {task.policy} failed: {type(exc).__name__}: {detail}"
            ) from None
        core = env.unwrapped
        estimate, truth, contacts = core.estimate, core.truth, core.contacts
    finally:
        env.close()
    if estimate is None:
        metrics = dict(_NO_FIT)
    else:
        metrics = _quality(
            estimate, truth, contacts.points, contacts.normals, np.random.default_rng(score_seed)
        )
    return {
        **metrics, "policy": task.policy or p["policy"], "contacts": int(len(contacts)),
        "epsilon_curve": [float(e) for e in record.epsilon], "truth": truth.to_dict(),
        "fitted": estimate is not None,
    }, estimate  # fmt: skip


def _plugin_policy(spec: str, env: Any, seed: int) -> Any:
    load_policy(spec)  # bad input (an import, a signature) is the run's, not the case's
    try:
        policy = make_plugin_policy(spec, env, seed)
    except Exception as exc:  # noqa: BLE001
        detail = " ".join(str(exc).split())
        raise _PluginError(f"the policy {spec} raised {type(exc).__name__}: {detail}") from None
    return policy


def _object_truth(name: str, rng: np.random.Generator) -> Any:
    """An ``objects`` case's truth: an example mesh, or what an object spec resolves to (a
    random kind drawn from `rng`)."""
    from hapticsim.data.example_meshes import EXAMPLE_MESHES
    from hapticsim.data.objects import ObjectSpec

    if name in EXAMPLE_MESHES:
        return EXAMPLE_MESHES[name]()
    return ObjectSpec(name).resolve(rng)


def _run_objects(case: Case, task: CaseTask, timing: dict) -> tuple[dict[str, Any], Any]:
    from hapticsim.exploration import TrialSeeds

    seeds = TrialSeeds.from_case(*_seeds(case), shape_first=True)
    truth = _object_truth(case.params["object"], seeds.generator("object"))
    metrics, estimate = _run_trial(task, seeds, truth, timing)
    truth_dict = truth.to_dict() if truth.kind != "mesh" else {"mesh": case.params["object"]}
    return {**metrics, "truth": truth_dict}, estimate


def _run_trial(
    task: CaseTask, seeds: Any, truth: Any, timing: dict
) -> tuple[dict[str, Any], Any]:
    """An ``explore`` or ``objects`` case through the one pipeline
    (:func:`hapticsim.exploration.run_trial`): the case's strategy, count and noise on `truth`
    with the built-in hand, its method (or the plug-in fitter) without free space, as the
    suites were made."""
    from hapticsim.exploration import Trial, run_trial

    p = task.case.params
    trial = Trial(object=truth, explorer=p["strategy"], count=p["count"], noise=p["noise"],
                  estimator=p["method"], free_space=False)  # fmt: skip
    plugin = None if task.fitter is None else _plugin_fitter(task.fitter)
    record = run_trial(trial, seeds, fitter=plugin, truth=truth)
    timing["fit"] = record.fit_seconds
    info = record.fit_info if plugin is None else {**record.fit_info, "fitter": task.fitter}
    metrics = record.metrics()
    accuracy = record.accuracy
    run = record.exploration
    return {
        **metrics, **info, "contacts": run.count, "complete": run.count >= p["count"],
        "distance_median": accuracy["distance_median"],
        "angle_median_deg": accuracy["angle_median_deg"],
    }, record.estimate  # fmt: skip


def _plugin_fitter(spec: str) -> Any:
    """A lab's ``MODULE:FUNCTION`` as the pipeline's fitter: its failures and values that are
    not solids fail the case (:class:`_PluginError`), not the run."""
    func = load_fitter(spec)

    def fitter(points: Any, normals: Any) -> Any:
        try:
            value = func(points, normals)
        except Exception as exc:  # noqa: BLE001 - the plug-in's failure is the case's result
            detail = " ".join(str(exc).split())
            raise _PluginError(
                f"the fitter {spec} raised {type(exc).__name__}: {detail}"
            ) from None
        try:
            return as_solid(value)
        except InvalidInputError as exc:
            raise _PluginError(str(exc)) from None

    return fitter


_RUNNERS = {"fit": _run_fit, "explore": _run_explore, "policy": _run_policy,
            "objects": _run_objects}  # fmt: skip


def case_cost(task: CaseTask) -> float:
    """A rough run-time estimate of a case (start the slow ones first; changes no result)."""
    p = task.case.params
    if task.case.kind == "policy":
        return (3.0 if p["backend"] == "mujoco" else 1.0) * p["touches"]
    if task.case.kind in ("explore", "objects"):
        return 10.0
    return 2.0 if p["method"] in ("H", "nH") else 1.0
