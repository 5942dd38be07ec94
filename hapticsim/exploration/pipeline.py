"""One trial, start to end: explore -> add sensor noise -> estimate -> score.

:func:`run_trial` is the one exploration pipeline: ``hapticsim explore``
(:func:`hapticsim.exploration.explore`), the suites' exploration cases, the tables and the
benchmarks all run their trials through it. It writes nothing; :mod:`hapticsim.exploration.rundir`
writes a run directory from its :class:`TrialRecord`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from hapticsim.constants import DEFAULT_LAMBDA
from hapticsim.errors import SimulationError
from hapticsim.exploration.explorers import ExplorationHooks, explorer_for
from hapticsim.exploration.trial import Trial, TrialSeeds

#: With nML, how far outside the solid the fingertip centres must lie, in fingertip radii (the
#: fingertip's own sphere less a quarter for the first-order distance; docs/nml/README.md).
FREE_MARGIN: float = 0.75

#: A lab's own estimator: ``fitter(points, normals)`` returning a solid.
Fitter = Callable[[np.ndarray, np.ndarray], Any]


@dataclass
class TrialHooks(ExplorationHooks):
    """What a caller watches during a trial (:class:`ExplorationHooks` and more).

    Attributes:
        status: called with a short word of what the trial does now (``"fitting"``, ...).
        before_fit: called with the exploration once the contacts are in, before the estimator
            runs (``explore`` renders the scene and waits there for the fitter's kernels it
            compiles in the background).
    """

    status: Callable[[str], None] | None = None
    before_fit: Callable[[Any], None] | None = None


@dataclass(frozen=True, eq=False)
class TrialRecord:
    """What a trial produced.

    Attributes:
        trial: the trial.
        seeds: the streams it drew from.
        truth: the true object, posed in the world.
        exploration: the exploration (:class:`~hapticsim.sim.session.Exploration`): the
            clean contacts in ``arrays``, the hand's explorer, the vision estimate.
        points: (n, 3) float, the contacts with sensor noise [m, world].
        normals: (n, 3) float, their normals with noise (unit).
        free_space: (f, 3) float, fingertip centres along the run near the contacts [m].
        fit: the estimator's :class:`~hapticsim.fitting.driver.FitResult` (None for a plug-in
            fitter).
        estimate: the estimated solid.
        fit_info: ``fitter``, ``budget``, ``evaluations``, ``fit_status`` of the estimate.
        quality: the volume metrics (:class:`~hapticsim.metrics.score.Score`).
        theta: SPEC §4's theta, where both solids are superquadrics (else None).
        eof: the SPEC §2 EOF of the estimate on the noisy contacts, for a superquadric.
        accuracy: the clean contacts against the true surface
            (:func:`~hapticsim.metrics.accuracy.contact_accuracy`).
        accuracy_exact: with tactile sensing, MuJoCo's exact contacts' accuracy.
        fit_seconds: wall time of the estimate [s].
        seconds: wall time of the trial [s].
        motion: a free object (SPEC §12): how it moved and what the estimate is against its
            final pose (:func:`object_motion`); None for a fixed object.
    """

    trial: Trial
    seeds: TrialSeeds
    truth: Any
    exploration: Any
    points: np.ndarray
    normals: np.ndarray
    free_space: np.ndarray
    fit: Any
    estimate: Any
    fit_info: dict[str, Any]
    quality: Any
    theta: float | None
    eof: float | None
    accuracy: dict[str, Any]
    accuracy_exact: dict[str, Any] | None = None
    fit_seconds: float = 0.0
    seconds: float = 0.0
    motion: dict[str, Any] | None = None

    def metrics(self) -> dict[str, Any]:
        """The estimate's quality measures (:func:`quality_metrics`)."""
        return quality_metrics(self.estimate, self.quality, self.theta, self.eof)


def quality_metrics(
    estimate: Any, quality: Any, theta: float | None, eof: float | None
) -> dict[str, Any]:
    """epsilon, alpha, beta, IoU, Chamfer, theta and EOF of an estimate (what
    :func:`score_estimate` gives); ``parts`` where it is not one superquadric."""
    from hapticsim.geometry import Superquadric

    q = quality
    out = {
        "epsilon": q.epsilon, "alpha": q.alpha, "beta": q.beta, "iou": q.iou,
        "chamfer": q.chamfer, "theta": theta, "eof": eof,
    }  # fmt: skip
    if not isinstance(estimate, Superquadric):
        out["parts"] = len(estimate.components)
    return out


def run_trial(
    trial: Trial,
    seeds: TrialSeeds | None = None,
    hooks: TrialHooks | None = None,
    fitter: Fitter | None = None,
    truth: Any = None,
) -> TrialRecord:
    """Run one trial (module docstring).

    Args:
        trial: the trial (validated when made).
        seeds: its streams (default :meth:`TrialSeeds.from_seed` of ``trial.seed``).
        hooks: progress, frames and status callbacks (change no result).
        fitter: a lab's estimator replacing ``trial.estimator``: ``fitter(points, normals)``
            returning a solid (the caller wraps the lab's function so that it checks the value;
            the estimate is scored as ``trial.estimator``'s would be).
        truth: the truth when the caller has resolved it already (default
            ``trial.resolve(seeds)``).

    Returns:
        the :class:`TrialRecord`.

    Raises:
        SimulationError: the object is out of reach, the simulation went unstable, or too few
            contacts were gathered (the message says how to reproduce the trial).
    """
    from hapticsim.data.noise import add_noise
    from hapticsim.metrics.accuracy import accuracy_checked
    from hapticsim.sim.free_space import near_contacts

    start = time.perf_counter()
    seeds = TrialSeeds.from_seed(trial.seed) if seeds is None else seeds
    h = hooks or TrialHooks()
    truth = trial.resolve(seeds) if truth is None else truth
    explorer = explorer_for(trial.explorer)
    try:
        run = explorer.explore(truth, trial.count, seeds.generator("sim"), trial.scene, h)
    except SimulationError as exc:
        raise SimulationError(f"{exc} [{reproduce_hint(trial)}]") from exc
    truth = run.truth  # a free object: where it rested before the first touch (SPEC §12)
    a = run.arrays
    points, normals = add_noise(a["points_clean"], a["normals_clean"], trial.noise, truth.size,
                                seeds.generator("noise"))  # fmt: skip
    free_space = near_contacts(run.free_space, a["points_clean"])
    if h.before_fit is not None:
        h.before_fit(run)
    _say(h, "fitting")
    fit_start = time.perf_counter()
    if fitter is None:
        result, estimate, info = _estimate(trial, seeds, run, points, normals, free_space)
    else:  # a lab's estimator: the caller checks what it returns
        result, estimate = None, fitter(points.copy(), normals.copy())
        info = {"fitter": None, "budget": None, "evaluations": None, "fit_status": None}
    fit_seconds = time.perf_counter() - fit_start
    _say(h, "scoring")
    quality, theta, eof = score_estimate(estimate, truth, points, normals, trial.estimator,
                                         seeds.rng("score"))  # fmt: skip
    # the trial was validated once when made: the metrics' checked entries do not check again
    accuracy = accuracy_checked(truth, a["points_clean"], a["normals_clean"])
    accuracy_exact = (
        accuracy_checked(truth, a["points_exact"], a["normals_exact"])
        if trial.scene.sensing == "tactile" else None
    )  # fmt: skip
    motion = None
    if run.truth_final is not None:
        motion = object_motion(run, estimate, result, seeds.rng("score"))
    return TrialRecord(trial, seeds, truth, run, points, normals, free_space, result, estimate,
                       info, quality, theta, eof, accuracy, accuracy_exact, fit_seconds,
                       time.perf_counter() - start, motion)  # fmt: skip


def object_motion(run: Any, estimate: Any, result: Any, rng: Any) -> dict[str, Any]:
    """How a free object moved and what the estimate is against it (SPEC §12, ``metrics.json``'s
    ``object_motion``): its dynamics and mass; ``moved`` (``position_m``, ``angle_deg`` of its
    centre and attitude) at the last contact and at the end, from where it rested before the
    first touch (the truth the quality measures score against: ``truth.json``); ``rest_pose``,
    the object body's pose then (7: position [m], quaternion w first; ``contacts.npz``'s
    ``object_pose`` is the same body's at each contact); ``final_pose``,
    the estimate's IoU and epsilon against the object where the run left it (a tracking fit's
    estimate carried there by its last tracked pose); with a tracking fit, ``pose_drift``: its
    last tracked pose against the truth's (:func:`~hapticsim.fitting.track.pose_drift`, with
    ADD and ADD-S)."""
    from hapticsim.fitting.track import pose_drift, true_poses
    from hapticsim.geometry.rotations import quaternion_to_matrix
    from hapticsim.metrics.score import score_checked
    from hapticsim.sim.dynamics import pose_change

    scene, sim = run.explorer.scene, run.explorer.sim
    initial = sim.initial_object_pose
    poses = run.arrays["object_pose"]
    last = poses[-1] if len(poses) else initial
    out: dict[str, Any] = {
        **scene.config.object_dynamics.to_dict(),
        "mass_kg": float(scene.model.body_mass[scene.object_body_id]),
        "moved": {
            "last_contact": _moved(pose_change(last, initial)),
            "end": _moved(pose_change(sim.object_pose(), initial)),
        },
        "rest_pose": [float(v) for v in initial],
        "truth_initial": "the object at rest before the first touch (truth.json; the quality "
        "measures)",
        "truth_final": "the object where the exploration left it (truth_final.json)",
    }  # fmt: skip
    carried = estimate
    tracked = getattr(result, "poses", None)
    if tracked is not None:
        truth = true_poses(poses[-1:], initial)[0]  # the last contact's only
        out["pose_drift"] = pose_drift(tracked[-1], truth, run.truth.center, run.truth)
        rot = quaternion_to_matrix(tracked[-1][3:])
        carried = estimate.transformed(rot, tracked[-1][:3])
    final = score_checked(carried, run.truth_final, rng)
    out["final_pose"] = {"iou": final.iou, "epsilon": final.epsilon}
    return out


def _moved(change: tuple[float, float]) -> dict[str, float]:
    return {"position_m": change[0], "angle_deg": change[1]}





def _say(hooks: TrialHooks, text: str) -> None:
    if hooks.status is not None:
        hooks.status(text)


def _estimate(
    trial: Trial, seeds: TrialSeeds, run: Any, points: np.ndarray, normals: np.ndarray,
    free_space: np.ndarray,
) -> tuple[Any, Any, dict[str, Any]]:  # fmt: skip
    """The trial's estimator on the noisy contacts: (fit result, solid, fit info)."""
    from hapticsim.fitting import fit
    from hapticsim.fitting.driver import method_budget
    from hapticsim.fitting.ml import MLOptions

    extra: dict[str, Any] = {}
    if trial.free_space and trial.estimator == "nML":
        # nML keeps the solid out of where the fingertips have been: their centres, by 0.75 of
        # the smallest fingertip radius (docs/nml/README.md: free space).
        radius = min(f.tip_radius for f in run.explorer.scene.hand.description.fingers)
        extra = {"free": free_space, "options": MLOptions(free_margin=FREE_MARGIN * radius)}
        if trial.scene.sensing == "tactile":  # each estimate weighs in by its own uncertainty
            extra["sigma"], extra["sigma_normal"] = run.arrays["sigma"], run.arrays["sigma_normal"]
    elif trial.free_space and trial.estimator == "multi":
        extra = {"free": free_space}
    if trial.holes:
        extra["holes"] = True
    budget = method_budget(trial.estimator, extra.get("options"))
    result = fit(points, normals, method=trial.estimator, budget=budget,
                 rng=seeds.rng("fit"), **extra)  # fmt: skip
    info = {"fitter": trial.estimator, "budget": int(budget),
            "evaluations": result.evaluations, "fit_status": result.status}  # fmt: skip
    return result, result.solid, info


def score_estimate(
    estimate: Any, truth: Any, points: np.ndarray, normals: np.ndarray, estimator: str | None,
    rng: np.random.Generator | int,
) -> tuple[Any, float | None, float | None]:  # fmt: skip
    """The volume metrics of `estimate` against `truth` (SPEC §4), theta where both are
    superquadrics and the SPEC §2 EOF of a superquadric estimate on the contacts (with their
    normals when `estimator` uses them, or is None)."""
    from hapticsim.fitting.methods import uses_normals
    from hapticsim.geometry import Superquadric
    from hapticsim.geometry.eof import error_of_fit
    from hapticsim.metrics.score import score_checked
    from hapticsim.metrics.theta import theta_checked

    quality = score_checked(estimate, truth, rng)
    with_normals = normals if estimator is None or uses_normals(estimator) else None
    single = isinstance(estimate, Superquadric)
    e = estimate
    eof = (
        float(error_of_fit(points, with_normals, e.a, e.eps, e.taper, e.rotation, e.center,
                           DEFAULT_LAMBDA)) if single else None
    )  # fmt: skip
    th = (
        float(theta_checked(estimate, truth, points, with_normals, DEFAULT_LAMBDA))
        if single and isinstance(truth, Superquadric) else None
    )  # fmt: skip
    return quality, th, eof


def reproduce_hint(trial: Trial) -> str:
    """The trial in a message: what it explored, and the command that runs it again."""
    from hapticsim.data.objects import ObjectSpec
    from hapticsim.geometry import matrix_to_quaternion

    text = f"object {trial.name!r}, strategy {trial.explorer!r}, seed {trial.seed}"
    spec = trial.object
    if not isinstance(spec, ObjectSpec):
        return text
    args = f" --scale {spec.scale}" if spec.scale != 1.0 else ""
    if spec.pose is not None:
        values = [*spec.pose.position, *matrix_to_quaternion(spec.pose.rotation)]
        args += " --pose " + ",".join(f"{v:.9g}" for v in values)
    scene = trial.scene
    if scene.hand.name != "hapticsim":
        args += f" --hand {scene.hand.source if scene.hand.source is not None else scene.hand.name}"
    dynamics = scene.object_dynamics
    if dynamics.free:
        args += f" --object-dynamics {dynamics.kind}"
        args += (f" --object-mass {dynamics.mass:.9g}" if dynamics.mass is not None
                 else f" --object-density {dynamics.density:.9g}")  # fmt: skip
        if dynamics.kind == "held":
            args += f" --clamp-stiffness {dynamics.clamp_stiffness:.9g}"
    if scene.force_limit is not None:
        args += f" --force-limit {scene.force_limit:.9g}"
    if scene.sensing == "tactile":
        args += f" --sensing tactile --skin {scene.skin.name}"
        if scene.taxel_model != "hapticsim":
            args += f" --taxel-model {scene.taxel_model}"
        if scene.steer_on != "skin":
            args += f" --steer-on {scene.steer_on}"
    return (f"{text}; to reproduce: hapticsim explore --object {spec.source} --strategy "
            f"{trial.explorer} --seed {trial.seed} --count {trial.count}{args}")  # fmt: skip


__all__ = ["FREE_MARGIN", "TrialHooks", "TrialRecord", "quality_metrics", "reproduce_hint",
           "run_trial", "score_estimate"]  # fmt: skip
