"""``hapticsim explore``: a simulated haptic exploration, the fit and its score (SPEC §6).

:func:`explore` runs the hand on an object with a named strategy (headless MuJoCo): a paper
body, a superquadric JSON file, a random superquadric drawn from the seed, or a mesh file
(:mod:`hapticsim.data.objects`). The hand plans on a vision estimate
(:func:`hapticsim.perception.vision.vision_estimate`, one noisy depth image). It adds seeded sensor
noise
at the SPEC §5 level, fits a superquadric (:func:`hapticsim.fitting.fit`), scores it against the
truth (:func:`hapticsim.metrics.score`; against the mesh for a mesh object) and writes, in the
output directory:

- ``contacts.npz``: ``points``, ``normals`` (with noise), ``points_clean``, ``normals_clean``,
  ``finger`` (n,) int (the hand description's order, 0 the thumb: thumb, index, middle, ring for
  hapticsim's hand), ``force`` (n,) [N], ``time`` (n,) [s], ``pattern`` (n,) int (pattern id;
  ``pattern_kind`` gives patch/stripe per id), ``free_space`` (f, 3) [m] the fingertip centres along
  the run near the contacts (free space: ``hapticsim fit --method nML --free-space``);
  ``sensing`` (``"exact"`` or ``"tactile"``); with tactile sensing (SPEC §11) ``points``/``normals``
  are the contacts estimated from the taxels (noise added on top only when asked),
  ``points_exact``/``normals_exact``/``force_exact`` MuJoCo's, ``sigma`` (n,) the estimate's
  per-coordinate std [m], ``sigma_normal`` (n,) its normal's [rad], ``area`` (n,) [m^2] and
  ``taxels`` (n,) lit taxels; with a free object (``object_dynamics``, SPEC §12) ``object_pose``
  (n, 7) its true position [m] and quaternion (w first) at each contact;
- ``tactile.npz`` (tactile sensing, compressed): ``images`` (touches, pads, rows, cols) readings
  [Pa], ``depth`` the skin's depth [m], ``slip`` (..., 2) [m/s], ``traction`` (..., 3) the
  skin's pressure and the object's tangential traction along the pad's u and v [Pa],
  ``taxel_state`` (0 free, 1 stick, 2 slip), ``friction`` the contacts' coefficient (SPEC
  §11; :mod:`hapticsim.perception.tactile.traction`), ``finger`` (touches,),
  ``pad_position`` (touches, pads, 3) [m] and ``pad_rotation`` (touches, pads, 3, 3) of the pads'
  carriers, ``taxel_position``/``taxel_normal`` (pads, rows, cols, 3) and ``taxel_area`` in the
  carriers' frames, ``time`` (touches,) [s] and ``skin`` (the preset as JSON);
- ``truth.json`` (a superquadric, SPEC §6, or a union, SPEC §10) or, for a mesh object,
  ``truth.stl`` (world frame, metres): a free object where it rested before the first touch,
  and ``truth_final.json``/``.stl`` where the run left it;
  ``fit.json`` (fit result), ``metrics.json`` (quality measures with their method, contact
  accuracy, the object and what the planner was given: ``vision``), ``report.png`` (truth,
  estimate, contacts with normals) and, with ``render=True``, ``scene.png`` (MuJoCo's
  offscreen renderer, ``MUJOCO_GL=egl``); ``hand.npz``: the hand's geoms and their poses at
  every touch (:mod:`hapticsim.sim.hand_trace`, for ``hapticsim view``); with ``video="mp4"``
  or ``"gif"``,
  ``exploration.mp4``/``.gif`` (:mod:`hapticsim.sim.video`).

The trial runs through the one pipeline (:func:`hapticsim.exploration.pipeline.run_trial`) and
the run directory is written by :func:`hapticsim.data.rundir.write_run`: everything is computed
before the first file is written, and every file is written to a temporary name and renamed, so
a failure leaves no half-written output.
"""

from __future__ import annotations

import io
import json
import os
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from hapticsim.data.rundir import npz_bytes, write_run
from hapticsim.errors import InvalidInputError
from hapticsim.exploration.pipeline import FREE_MARGIN, TrialHooks, TrialRecord, run_trial
from hapticsim.exploration.report import exploration_figure_png, png_bytes, prepare_figures
from hapticsim.exploration.trial import DEFAULT_CONTACTS, Trial

# headless rendering; must be set before mujoco is first imported (hapticsim.sim does it too)
os.environ.setdefault("MUJOCO_GL", "egl")


def explore(
    object_name: Any = "cube",
    strategy: str = "paper",
    noise: float = 0.0,
    method: str = "nH",
    seed: int = 0,
    out_dir: str | Path | None = None,
    render: bool = False,
    progress: bool = True,
    count: int = DEFAULT_CONTACTS,
    scale: float = 1.0,
    pose: Any = None,
    hand: str | Path = "hapticsim",
    video: str | None = None,
    sensing: str = "exact",
    skin: Any = None,
    taxel_model: str = "hapticsim",
    steer_on: str = "skin",
    holes: bool = False,
    object_dynamics: Any = "fixed",
    force_limit: float | None = None,
) -> dict[str, Any]:
    """Explore an object with the simulated hand, fit, score and write the results.

    Args:
        object_name: the object: a paper body name, a superquadric ``.json``, ``random`` or
            ``random_tapered`` (drawn from `seed`), a mesh file (``.stl``, ``.obj``, ``.ply``,
            ``.off``), or an :class:`~hapticsim.data.objects.ObjectSpec`.
        strategy: exploration strategy (``hapticsim.sim.strategies.strategy_names()``), or an
            environment policy choosing each touch from what was felt (``uncertainty``,
            ``learned``, ``learned:PATH``, ``random``: :mod:`hapticsim.exploration.explorers`).
        noise: relative sensor noise sigma_N (SPEC §5), >= 0.
        method: fitting method, ``LS``, ``H``, ``nLS`` or ``nH``, or ``nML`` (which also keeps
            the solid :data:`FREE_MARGIN` fingertip radii away from the fingertip centres along
            the run, the contacts file's ``free_space``, and with tactile sensing weighs each
            contact by its estimate's ``sigma``).
        seed: seed of everything random (rough object, strategy, noise, fit, score).
        out_dir: output directory (default ``runs/<object>-<strategy>-seed<seed>``).
        render: also write ``scene.png`` from MuJoCo's offscreen renderer.
        progress: show a progress bar on stderr.
        count: number of contacts to gather.
        scale: factor from the object file's units to metres (0.001 for millimetres).
        pose: placement of the object, a :class:`~hapticsim.data.objects.Pose` or its text
            ``"x,y,z[,qw,qx,qy,qz]"`` (default: a superquadric where its parameters put it, a
            mesh with its centroid at the origin).
        hand: the hand, ``"hapticsim"`` (default), ``"shadow"``, ``"adroit"`` (the optional
            extra ``hands``) or the path of a TOML hand description (``docs/hands.md``).
        video: also write a video of the exploration, ``"mp4"`` (the optional extra ``video``)
            or ``"gif"``; None: no video.
        sensing: ``"exact"`` (MuJoCo's contacts, default) or ``"tactile"`` (contacts estimated
            from a taxel pad on every fingertip; :mod:`hapticsim.sim.tactile`).
        skin: with tactile sensing, a skin preset (``"ideal"``, default; ``"vision"``,
            ``"capacitive"``) or a ``.toml`` skin file.
        taxel_model: with tactile sensing, ``"hapticsim"`` (its own taxel model, default) or
            ``"mujoco"`` (MuJoCo's ``<tactile>`` sensor).
        steer_on: with tactile sensing, what the controllers steer on: ``"skin"`` (default:
            each touching pad's estimated contact, a frame every 3 control ticks) or ``"contacts"``
            (MuJoCo's contact point and normal; :class:`~hapticsim.sim.scene.SceneConfig`).
        holes: with ``method="multi"``, also fit a supertoroid and keep it where it explains
            the contacts better (:func:`hapticsim.fitting.fit`'s ``holes``).
        object_dynamics: how the object is held (SPEC §12): ``"fixed"`` (default),
            ``"resting"`` (free, in a cradle, under gravity) or ``"held"`` (a stiff clamp), or an
            :class:`~hapticsim.sim.dynamics.ObjectDynamics` with its mass or density and clamp.
            A free object's contacts carry its pose (``object_pose``), ``truth_final.json``
            holds it where the run left it and ``metrics.json`` how far it moved
            (``object_motion``).
        force_limit: the largest normal force [N] a fingertip presses with (gentle
            exploration; :class:`~hapticsim.sim.scene.SceneConfig`), None for none.

    Returns:
        A JSON-ready summary: the output files, contact count, quality measures, contact
        accuracy, simulation statistics and the fit's EOF and evaluations. ``complete`` is
        False when fewer than `count` contacts were gathered; then ``stop_reason`` says why
        (``requested`` is `count`).

    Raises:
        InvalidInputError: unknown object, strategy or method (the message lists the choices),
            a mesh that is empty, not watertight or of an unknown format, or a bad noise level,
            seed, scale or pose, an unknown or invalid hand (naming the element), a video
            format whose encoder is not installed, or an unknown sensing, skin or taxel model
            (a skin file that does not parse names the key), or a steering without tactile sensing.
        SimulationError: the object is too large or too far for the hand, the simulation went
            unstable, or too few contacts were gathered.
    """
    from hapticsim.data.objects import ObjectSpec, Pose
    from hapticsim.sim.scene import SceneConfig
    from hapticsim.sim.video import VideoConfig, check_video_support

    if isinstance(pose, str):
        pose = Pose.parse(pose)
    if isinstance(object_name, ObjectSpec):
        if scale != 1.0 or pose is not None:
            raise InvalidInputError("give `scale` and `pose` in the ObjectSpec, not beside it")
        spec = object_name
    else:
        spec = ObjectSpec(object_name, scale=scale, pose=pose)
    if sensing != "tactile" and (skin is not None or taxel_model != "hapticsim"
                                 or steer_on != "skin"):  # fmt: skip
        raise InvalidInputError(
            "`skin`, `taxel_model` and `steer_on` are for tactile sensing (--sensing tactile), "
            f"got sensing {sensing!r}"
        )
    scene = SceneConfig(hand=hand, sensing=sensing, skin="ideal" if skin is None else skin,
                        taxel_model=taxel_model, steer_on=steer_on,
                        object_dynamics=object_dynamics,
                        force_limit=force_limit)  # fmt: skip
    trial = Trial(object=spec, explorer=strategy, count=count, noise=noise, estimator=method,
                  seed=seed, scene=scene, holes=holes)  # fmt: skip
    video_config = None if video is None else VideoConfig(format=video)
    if video_config is not None:
        check_video_support(video_config)
    default = Path("runs") / f"{spec.name}-{strategy}-seed{trial.seed}"
    out = Path(out_dir) if out_dir is not None else default
    if out.exists() and not out.is_dir():
        raise InvalidInputError(f"`out_dir` {out} exists and is not a directory")
    return _explore(trial, out, render, progress, video_config)


def _explore(
    trial: Trial, out: Path, render: bool, progress: bool, video_config: Any
) -> dict[str, Any]:
    """Run `trial` with a progress bar, pictures and the hand's trace; write the run directory."""
    from tqdm import tqdm

    from hapticsim.fitting.kernels import start_background
    from hapticsim.sim.hand_trace import HandTrace
    from hapticsim.sim.video import ExplorationVideo

    start = time.perf_counter()
    # A fresh installation compiles the fitter's kernels in worker processes while the hand
    # explores (hapticsim.fitting.kernels); the fit waits for them.
    compiling = start_background(trial.estimator,
                                 stream=sys.stderr if progress else io.StringIO())  # fmt: skip
    bar = tqdm(total=trial.count, desc=f"explore {trial.name}", unit="contact", file=sys.stderr,
               disable=not progress, leave=False)  # fmt: skip
    picture: dict[str, bytes] = {}
    video = None if video_config is None else ExplorationVideo(video_config)

    def on_pattern_end(explorer: Any) -> None:
        kinds = explorer.recorder.pattern_kinds
        if render and "scene" not in picture and kinds[-1:] == ["stripe"]:
            from hapticsim.sim.render import render_scene

            picture["scene"] = png_bytes(render_scene(explorer.sim))

    def before_fit(run: Any) -> None:
        if render and "scene" not in picture:
            from hapticsim.sim.render import render_scene

            picture["scene"] = png_bytes(render_scene(run.explorer.sim))
        if video is not None:
            bar.set_postfix_str("encoding the video")
            picture["video"] = video.finish()
        if compiling is not None:
            bar.set_postfix_str("compiling the fitter's kernels (once per installation)")
            prepare_figures()  # meanwhile: this process is idle
            compiling.wait(say=lambda line: bar.set_postfix_str(line.removeprefix("hapticsim: ")),
                           load=True)  # fmt: skip

    hooks = TrialHooks(
        progress=lambda n: bar.update(n - bar.n), on_pattern_end=on_pattern_end, video=video,
        hand_trace=HandTrace(), status=bar.set_postfix_str, before_fit=before_fit,
    )  # fmt: skip
    try:
        record = run_trial(trial, hooks=hooks)
        report = _report_png(record)
    except BaseException:
        if compiling is not None:  # nothing to fit: the workers go too
            compiling.stop()
        raise
    finally:
        bar.close()
        if video is not None:
            video.close()
    run = record.exploration
    summary = {
        "out_dir": str(out),
        "files": {},
        "object": trial.name,
        "strategy": trial.explorer,
        "hand": run.explorer.scene.hand.description.name,
        "method": trial.estimator,
        "noise": trial.noise,
        "seed": trial.seed,
        "contacts": run.count,
        **_completeness(run),
        "metrics": record.quality.to_dict() | {"theta": record.theta},
        "contact_accuracy": record.accuracy,
        "sensing": trial.scene.sensing,
        **({"skin": trial.scene.skin.name, "unfelt": run.unfelt}
           if trial.scene.sensing == "tactile" else {}),  # fmt: skip
        "fit": {
            "eof": record.fit.eof,
            "evaluations": record.fit.evaluations,
            "seconds": record.fit.seconds,
            "setup_seconds": record.fit.setup_seconds,
        },
        "simulation": _sim_stats(run),
        **({} if record.motion is None else {"object_motion": record.motion}),
    }
    files = _write(out, record, report, picture, video_config, hooks.hand_trace)
    summary["files"] = {k: str(v) for k, v in files.items()}
    summary["seconds"] = time.perf_counter() - start
    return summary


def _report_png(record: TrialRecord) -> bytes:
    """The report picture: truth, estimate, contacts with normals (and pad images)."""
    trial, run, a = record.trial, record.exploration, record.exploration.arrays
    tactile = trial.scene.sensing == "tactile"
    sensed = f", {trial.scene.skin.name} skin" if tactile else ""
    hand = run.explorer.scene.hand.description
    q = record.quality
    return exploration_figure_png(
        record.truth, record.estimate, a["points_clean"], a["normals_clean"], a["finger"],
        f"{trial.name} touched by the {hand.name} hand, {trial.explorer} exploration "
        f"({run.count} contacts{sensed}, sigma_N = {trial.noise}), {trial.estimator} fit: "
        f"epsilon = {q.epsilon:.3f}, IoU = {q.iou:.3f}",
        tactile=_report_images(run) if tactile else None,
        finger_names=[f.name for f in hand.fingers],
    )  # fmt: skip


def _sim_stats(run: Any) -> dict[str, Any]:
    return {
        "sim_time": run.sim_time,
        "steps": run.steps,
        "wall_time": run.wall_time,
        "steps_per_second": run.steps_per_second,
        "patterns": {k: run.pattern_kinds.count(k) for k in ("patch", "stripe")},
    }


def _write(
    out: Path, record: TrialRecord, report: bytes, picture: dict[str, bytes], video_config: Any,
    hand_trace: Any,
) -> dict[str, Path]:  # fmt: skip
    """The run directory of `record` (:mod:`hapticsim.data.rundir`)."""
    from hapticsim.data.io import FREE_SPACE_KEY, Contacts
    from hapticsim.data.objects import truth_file as truth_file_of

    trial, run, a = record.trial, record.exploration, record.exploration.arrays
    tactile = trial.scene.sensing == "tactile"
    spec = trial.object
    truth_file = truth_file_of(record.truth)
    metrics = {
        **record.quality.to_dict(),
        "theta": record.theta,
        "contact_accuracy": record.accuracy,
        "contacts": run.count,
        **_completeness(run),
        "noise": trial.noise,
        "method": trial.estimator,
        "strategy": trial.explorer,
        "object": trial.name,
        "object_spec": spec.to_dict(),
        "truth": truth_file[0],
        "hand": run.explorer.scene.hand.description.name,
        "seed": trial.seed,
        "vision": run.rough.to_dict(),
        "collision": run.explorer.scene.collision_method,
        "simulation": _sim_stats(run),
        "sensing": trial.scene.sensing,
    }
    if record.motion is not None:  # a free object (SPEC §12): pose_drift at the top level
        metrics["object_motion"] = {k: v for k, v in record.motion.items() if k != "pose_drift"}
        if "pose_drift" in record.motion:
            metrics["pose_drift"] = record.motion["pose_drift"]
    if trial.scene.force_limit is not None:
        metrics["force_limit"] = trial.scene.force_limit
    repair = getattr(record.truth, "repair", None)
    if repair is not None:  # a mesh object: what its loader mended (SPEC §10)
        metrics["mesh_repair"] = repair
    if tactile:
        metrics["skin"] = trial.scene.skin.to_dict()
        metrics["taxel_model"] = trial.scene.taxel_model
        metrics["steer_on"] = trial.scene.steer_on
        metrics["contact_accuracy_exact"] = record.accuracy_exact
        metrics["tactile"] = _tactile_summary(run)
    keys = ("points_clean", "normals_clean", "finger", "force", "time", "pattern")
    if "object_pose" in a:
        keys += ("object_pose",)
    if tactile:
        keys += ("points_exact", "normals_exact", "force_exact", "sigma", "sigma_normal", "area",
                 "taxels")  # fmt: skip
    extra = {k: a[k] for k in keys}
    extra["pattern_kind"] = np.array([run.pattern_kinds[p] for p in a["pattern"]])
    extra[FREE_SPACE_KEY] = record.free_space  # fingertip centres: free space for nML
    extra["sensing"] = np.array(trial.scene.sensing)
    files = {"report": ("report.png", report)}
    if run.truth_final is not None:
        name, data = truth_file_of(run.truth_final)
        files["truth_final"] = (name.replace("truth", "truth_final"), data)
    if tactile:
        files["tactile"] = ("tactile.npz", _tactile_file(run, trial.scene.skin))
    files["hand"] = ("hand.npz", npz_bytes(hand_trace.arrays()))
    if "scene" in picture:
        files["scene"] = ("scene.png", picture["scene"])
    if "video" in picture:
        files["video"] = (f"exploration.{video_config.format}", picture["video"])
    return write_run(out, Contacts(record.points, record.normals, extra), truth_file,
                     record.fit.to_dict(), metrics, files)  # fmt: skip

def _tactile_summary(run: Any) -> dict[str, Any]:
    """What the skin did in a run (metrics.json)."""
    a = run.arrays
    ratio = a["force"] / np.maximum(a["force_exact"], 1e-12)
    return {
        "unfelt": run.unfelt,
        "lit_taxels_median": float(np.median(a["taxels"])),
        "sigma_median": float(np.median(a["sigma"])),
        "area_median": float(np.median(a["area"])),
        "force_median": float(np.median(a["force"])),
        "force_to_mujoco_median": float(np.median(ratio[a["force_exact"] > 0]))
        if np.any(a["force_exact"] > 0) else None,
        "slipping_median": _slipping_median(run),
        "pads": int(run.tactile["images"].shape[1]),
        "grid": list(run.tactile["images"].shape[2:]),
    }  # fmt: skip


def _slipping_median(run: Any) -> float:
    """The median over touches of the share of the recording pad's contact taxels that slip."""
    finger = run.arrays["finger"]
    state = run.tactile["taxel_state"][np.arange(len(finger)), finger]
    touching = (state > 0).reshape(len(finger), -1)
    slipping = (state == 2).reshape(len(finger), -1)
    return float(np.median(slipping.sum(axis=1) / np.maximum(touching.sum(axis=1), 1)))


def _tactile_file(run: Any, skin: Any) -> bytes:
    """The compressed ``tactile.npz`` of a run (module docstring)."""

    tactile = run.explorer.sim.tactile
    layouts = [p.layout for p in tactile.pads]
    arrays = dict(run.tactile)
    arrays["finger"] = run.arrays["finger"]
    arrays["taxel_position"] = np.stack([lay.taxels[0] for lay in layouts])
    arrays["taxel_normal"] = np.stack([lay.taxels[1] for lay in layouts])
    arrays["taxel_area"] = np.stack([lay.taxels[2] for lay in layouts])
    arrays["carrier"] = np.array([p.carrier for p in tactile.pads])
    arrays["friction"] = np.array(tactile.friction)
    arrays["skin"] = np.array(json.dumps(skin.to_dict()))
    return npz_bytes(arrays)


def _report_images(run: Any, count: int = 8) -> dict[str, Any]:
    """Pressure images of up to `count` touches spread over a run, each from the pad of the
    finger that recorded it (for the report picture)."""
    n = run.count
    picks = np.unique(np.linspace(0, n - 1, min(count, n)).round().astype(int))
    finger = run.arrays["finger"]
    images = run.tactile["images"][picks, finger[picks]]
    names = run.explorer.scene.hand.finger_names
    return {"images": images, "labels": [f"#{i + 1} {names[finger[i]]}" for i in picks]}


def _completeness(run: Any) -> dict[str, Any]:
    """``complete``, ``requested`` and ``stop_reason`` of a run (SPEC §6: a run that gathers
    fewer contacts than asked says so)."""
    return {"complete": run.complete, "requested": run.requested, "stop_reason": run.stop_reason}


__all__ = ["DEFAULT_CONTACTS", "FREE_MARGIN", "explore"]
