"""``hapticsim explore``: a simulated haptic exploration, the fit and its score (SPEC §6).

:func:`explore` runs the hand on an object with a named strategy (headless MuJoCo): a paper
body, a superquadric JSON file, a random superquadric drawn from the seed, or a mesh file
(:mod:`hapticsim.data.objects`). The hand plans on a vision estimate
(:func:`hapticsim.sim.rough.vision_estimate`, one noisy depth image). It adds seeded sensor noise
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
  ``taxels`` (n,) lit taxels;
- ``tactile.npz`` (tactile sensing, compressed): ``images`` (touches, pads, rows, cols) readings
  [Pa], ``depth`` the skin's depth [m], ``slip`` (..., 2) [m/s], ``finger`` (touches,),
  ``pad_position`` (touches, pads, 3) [m] and ``pad_rotation`` (touches, pads, 3, 3) of the pads'
  carriers, ``taxel_position``/``taxel_normal`` (pads, rows, cols, 3) and ``taxel_area`` in the
  carriers' frames, ``time`` (touches,) [s] and ``skin`` (the preset as JSON);
- ``truth.json`` (a superquadric, SPEC §6, or a union, SPEC §10) or, for a mesh object,
  ``truth.stl`` (world frame, metres);
  ``fit.json`` (fit result), ``metrics.json`` (quality measures with their method, contact
  accuracy, the object and what the planner was given: ``vision``), ``report.png`` (truth,
  estimate, contacts with normals) and, with ``render=True``, ``scene.png`` (MuJoCo's
  offscreen renderer, ``MUJOCO_GL=egl``); ``hand.npz``: the hand's geoms and their poses at
  every touch (:mod:`hapticsim.sim.hand_trace`, for ``hapticsim view``); with ``video="mp4"``
  or ``"gif"``,
  ``exploration.mp4``/``.gif`` (:mod:`hapticsim.sim.video`).

Everything is computed before the first file is written, and every file is written to a
temporary name and renamed, so a failure leaves no half-written output.
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

from hapticsim._files import OutputSet
from hapticsim._validate import finite_float, positive_int
from hapticsim.constants import MAX_CONTACTS
from hapticsim.envs.exploration import is_policy_strategy, run_policy_exploration
from hapticsim.errors import InvalidInputError, SimulationError
from hapticsim.experiments.explore_report import (
    exploration_figure_png,
    png_bytes,
    prepare_figures,
    write_bytes_atomic,
)
from hapticsim.geometry import Superquadric, matrix_to_quaternion
from hapticsim.sim.free_space import near_contacts

# headless rendering; must be set before mujoco is first imported (hapticsim.sim does it too)
os.environ.setdefault("MUJOCO_GL", "egl")

#: Default number of contacts (paper IV).
DEFAULT_CONTACTS: int = 150
#: With nML, how far outside the solid the fingertip centres must lie, in fingertip radii (the
#: fingertip's own sphere less a quarter for the first-order distance; docs/nml/README.md).
FREE_MARGIN: float = 0.75


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
) -> dict[str, Any]:
    """Explore an object with the simulated hand, fit, score and write the results.

    Args:
        object_name: the object: a paper body name, a superquadric ``.json``, ``random`` or
            ``random_tapered`` (drawn from `seed`), a mesh file (``.stl``, ``.obj``, ``.ply``,
            ``.off``), or an :class:`~hapticsim.data.objects.ObjectSpec`.
        strategy: exploration strategy (``hapticsim.sim.strategies.strategy_names()``), or an
            environment policy choosing each touch from what was felt (``uncertainty``,
            ``learned``, ``learned:PATH``, ``random``: :mod:`hapticsim.envs.exploration`).
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
            (a skin file that does not parse names the key).
        SimulationError: the object is too large or too far for the hand, the simulation went
            unstable, or too few contacts were gathered.
    """
    from hapticsim.data.objects import ObjectSpec, Pose
    from hapticsim.fitting.methods import FIT_METHODS as METHODS
    from hapticsim.sim.session import MIN_CONTACTS

    if isinstance(pose, str):
        pose = Pose.parse(pose)
    if isinstance(object_name, ObjectSpec):
        if scale != 1.0 or pose is not None:
            raise InvalidInputError("give `scale` and `pose` in the ObjectSpec, not beside it")
        spec = object_name
    else:
        spec = ObjectSpec(object_name, scale=scale, pose=pose)
    from hapticsim.sim.strategies import get_strategy

    if not is_policy_strategy(strategy):
        get_strategy(strategy)
    if not isinstance(method, str) or method not in METHODS:
        raise InvalidInputError(f"`method` must be one of {', '.join(METHODS)}, got {method!r}")
    sigma = finite_float(noise, "noise", low=0.0)
    seed = positive_int(seed, "seed", minimum=0)
    count = positive_int(count, "count", minimum=MIN_CONTACTS, maximum=MAX_CONTACTS)
    from hapticsim.sim.scene import SceneConfig
    from hapticsim.sim.video import VideoConfig, check_video_support

    if sensing != "tactile" and (skin is not None or taxel_model != "hapticsim"):
        raise InvalidInputError(
            "`skin` and `taxel_model` are for tactile sensing (--sensing tactile), got "
            f"sensing {sensing!r}"
        )
    scene_config = SceneConfig(
        hand=hand, sensing=sensing, skin="ideal" if skin is None else skin,
        taxel_model=taxel_model,
    )  # fmt: skip
    video_config = None if video is None else VideoConfig(format=video)
    if video_config is not None:
        check_video_support(video_config)
    default = Path("runs") / f"{spec.name}-{strategy}-seed{seed}"
    out = Path(out_dir) if out_dir is not None else default
    if out.exists() and not out.is_dir():
        raise InvalidInputError(f"`out_dir` {out} exists and is not a directory")
    # the object's own stream: spawn(4)[:3] are the streams of the simulation, noise and fit
    truth = spec.resolve(np.random.default_rng(np.random.SeedSequence(seed).spawn(4)[3]))
    return _explore(truth, spec, strategy, sigma, method, seed, out, render, progress, count,
                    scene_config=scene_config, video_config=video_config)  # fmt: skip


def _explore(
    truth: Any, spec: Any, strategy: str, sigma: float, method: str, seed: int,
    out: Path, render: bool, progress: bool, count: int, scene_config: Any = None,
    video_config: Any = None,
) -> dict[str, Any]:  # fmt: skip
    from tqdm import tqdm

    from hapticsim.data.io import FREE_SPACE_KEY
    from hapticsim.data.noise import add_noise
    from hapticsim.data.objects import truth_file as truth_file_of
    from hapticsim.fitting import fit
    from hapticsim.fitting.kernels import start_background
    from hapticsim.fitting.methods import uses_normals
    from hapticsim.fitting.ml import MLOptions
    from hapticsim.metrics import score, theta
    from hapticsim.metrics.accuracy import contact_accuracy
    from hapticsim.sim.hand_trace import HandTrace
    from hapticsim.sim.session import run_exploration
    from hapticsim.sim.video import ExplorationVideo

    start = time.perf_counter()
    # A fresh installation compiles the fitter's kernels in worker processes while the hand
    # explores (hapticsim.fitting.kernels); the fit below waits for them.
    compiling = start_background(method, stream=sys.stderr if progress else io.StringIO())
    object_name = spec.name
    seeds = np.random.SeedSequence(seed).spawn(3)
    sim_rng, noise_rng = (np.random.default_rng(s) for s in seeds[:2])
    fit_seed = int(seeds[2].generate_state(1)[0])
    bar = tqdm(total=count, desc=f"explore {object_name}", unit="contact", file=sys.stderr,
               disable=not progress, leave=False)  # fmt: skip
    picture: dict[str, bytes] = {}
    video = None if video_config is None else ExplorationVideo(video_config)
    hand_trace = HandTrace()  # the hand at every touch: hand.npz, for `hapticsim view`

    def on_progress(n: int) -> None:
        bar.update(n - bar.n)

    def on_pattern_end(explorer: Any) -> None:
        kinds = explorer.recorder.pattern_kinds
        if render and "scene" not in picture and kinds[-1:] == ["stripe"]:
            from hapticsim.sim.render import render_scene

            picture["scene"] = png_bytes(render_scene(explorer.sim))

    try:
        try:
            if is_policy_strategy(strategy):  # an environment policy chooses every touch
                run = run_policy_exploration(truth, strategy, count, sim_rng, scene_config,
                                             progress=on_progress, video=video,
                                             hand_trace=hand_trace)  # fmt: skip
            else:
                run = run_exploration(truth, strategy, count, sim_rng, scene_config=scene_config,
                                      progress=on_progress, on_pattern_end=on_pattern_end,
                                      video=video, hand_trace=hand_trace)  # fmt: skip
        except SimulationError as exc:
            raise SimulationError(
                f"{exc} [object {object_name!r}, strategy {strategy!r}, seed {seed}; to "
                f"reproduce: hapticsim explore --object {spec.source} --strategy {strategy} "
                f"--seed {seed} --count {count}{_placement_args(spec)}{_hand_args(scene_config)}]"
            ) from exc
        if render and "scene" not in picture:
            from hapticsim.sim.render import render_scene

            picture["scene"] = png_bytes(render_scene(run.explorer.sim))
        if video is not None:
            bar.set_postfix_str("encoding the video")
            picture["video"] = video.finish()
        a = run.arrays
        tactile = scene_config.sensing == "tactile"
        points, normals = add_noise(
            a["points_clean"], a["normals_clean"], sigma, truth.size, noise_rng
        )
        if compiling is not None:
            bar.set_postfix_str("compiling the fitter's kernels (once per installation)")
            prepare_figures()  # meanwhile: this process is idle
            compiling.wait(say=lambda line: bar.set_postfix_str(line.removeprefix("hapticsim: ")),
                           load=True)  # fmt: skip
        bar.set_postfix_str("fitting")
        # nML keeps the solid out of where the fingertips have been: their centres, by 0.75 of
        # the smallest fingertip radius (docs/nml/README.md: free space).
        free_space = near_contacts(run.free_space, a["points_clean"])
        radius = min(f.tip_radius for f in run.explorer.scene.hand.description.fingers)
        ml = {"free": free_space, "options": MLOptions(free_margin=FREE_MARGIN * radius)}
        if tactile:  # each estimate weighs in by its own uncertainties
            ml["sigma"], ml["sigma_normal"] = a["sigma"], a["sigma_normal"]
        extra = ml if method == "nML" else {"free": free_space} if method == "multi" else {}
        result = fit(points, normals, method=method, rng=fit_seed, **extra)
        bar.set_postfix_str("scoring")
        estimate = result.solid  # multi's union; the superquadric of every other method
        quality = score(estimate, truth, rng=seed)
        accuracy = contact_accuracy(truth, a["points_clean"], a["normals_clean"])
        accuracy_exact = (
            contact_accuracy(truth, a["points_exact"], a["normals_exact"]) if tactile else None
        )
        th = (  # theta needs the EOFs of superquadrics: undefined for other solids
            float(theta(estimate, truth, points, normals if uses_normals(method) else None))
            if isinstance(truth, Superquadric) and isinstance(estimate, Superquadric)
            else None
        )  # fmt: skip
        truth_file = truth_file_of(truth)
        sensed = f", {scene_config.skin.name} skin" if tactile else ""
        hand_description = run.explorer.scene.hand.description
        report = exploration_figure_png(
            truth, estimate, a["points_clean"], a["normals_clean"], a["finger"],
            f"{object_name} touched by the {hand_description.name} hand, {strategy} exploration "
            f"({run.count} contacts{sensed}, sigma_N = {sigma}), {method} fit: epsilon = "
            f"{quality.epsilon:.3f}, IoU = {quality.iou:.3f}",
            tactile=_report_images(run) if tactile else None,
            finger_names=[f.name for f in hand_description.fingers],
        )  # fmt: skip
    except BaseException:
        if compiling is not None:  # nothing to fit: the workers go too
            compiling.stop()
        raise
    finally:
        bar.close()
        if video is not None:
            video.close()

    hand_name = run.explorer.scene.hand.description.name
    metrics = {
        **quality.to_dict(),
        "theta": th,
        "contact_accuracy": accuracy,
        "contacts": run.count,
        **_completeness(run),
        "noise": sigma,
        "method": method,
        "strategy": strategy,
        "object": object_name,
        "object_spec": spec.to_dict(),
        "truth": truth_file[0],
        "hand": hand_name,
        "seed": seed,
        "vision": run.rough.to_dict(),
        "collision": run.explorer.scene.collision_method,
    }
    sim_stats = {
        "sim_time": run.sim_time,
        "steps": run.steps,
        "wall_time": run.wall_time,
        "steps_per_second": run.steps_per_second,
        "patterns": {k: run.pattern_kinds.count(k) for k in ("patch", "stripe")},
    }
    metrics["simulation"] = sim_stats
    metrics["sensing"] = scene_config.sensing
    if tactile:
        metrics["skin"] = scene_config.skin.to_dict()
        metrics["taxel_model"] = scene_config.taxel_model
        metrics["contact_accuracy_exact"] = accuracy_exact
        metrics["tactile"] = _tactile_summary(run)

    out.mkdir(parents=True, exist_ok=True)
    keys = ("points_clean", "normals_clean", "finger", "force", "time", "pattern")
    if tactile:
        keys += ("points_exact", "normals_exact", "force_exact", "sigma", "sigma_normal", "area",
                 "taxels")  # fmt: skip
    extra = {k: a[k] for k in keys}
    extra["pattern_kind"] = np.array([run.pattern_kinds[p] for p in a["pattern"]])
    extra[FREE_SPACE_KEY] = free_space  # fingertip centres: free space for nML
    extra["sensing"] = np.array(scene_config.sensing)
    tactile_file = _tactile_file(run, scene_config.skin) if tactile else None
    hand_file = _npz_bytes(hand_trace.arrays())
    with OutputSet():  # all files or none, even on Ctrl-C
        files = _write_outputs(out, points, normals, extra, truth_file, result, metrics,
                               report, picture, video_config, tactile_file, hand_file)  # fmt: skip
    return {
        "out_dir": str(out),
        "files": {k: str(v) for k, v in files.items()},
        "object": object_name,
        "strategy": strategy,
        "hand": hand_name,
        "method": method,
        "noise": sigma,
        "seed": seed,
        "contacts": run.count,
        **_completeness(run),
        "metrics": quality.to_dict() | {"theta": th},
        "contact_accuracy": accuracy,
        "sensing": scene_config.sensing,
        **({"skin": scene_config.skin.name, "unfelt": run.unfelt} if tactile else {}),
        "fit": {
            "eof": result.eof,
            "evaluations": result.evaluations,
            "seconds": result.seconds,
            "setup_seconds": result.setup_seconds,
        },
        "simulation": sim_stats,
        "seconds": time.perf_counter() - start,
    }


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
        "pads": int(run.tactile["images"].shape[1]),
        "grid": list(run.tactile["images"].shape[2:]),
    }  # fmt: skip


def _npz_bytes(arrays: dict[str, Any]) -> bytes:
    """Arrays as the bytes of a compressed ``.npz`` file."""

    buf = io.BytesIO()
    np.savez_compressed(buf, **arrays)
    return buf.getvalue()


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
    arrays["skin"] = np.array(json.dumps(skin.to_dict()))
    return _npz_bytes(arrays)


def _report_images(run: Any, count: int = 8) -> dict[str, Any]:
    """Pressure images of up to `count` touches spread over a run, each from the pad of the
    finger that recorded it (for the report picture)."""
    n = run.count
    picks = np.unique(np.linspace(0, n - 1, min(count, n)).round().astype(int))
    finger = run.arrays["finger"]
    images = run.tactile["images"][picks, finger[picks]]
    names = run.explorer.scene.hand.finger_names
    return {"images": images, "labels": [f"#{i + 1} {names[finger[i]]}" for i in picks]}


def _write_outputs(
    out: Path, points: Any, normals: Any, extra: dict[str, Any], truth_file: tuple[str, bytes],
    result: Any, metrics: dict[str, Any], report: bytes, picture: dict[str, bytes],
    video_config: Any, tactile_file: bytes | None = None, hand_file: bytes | None = None,
) -> dict[str, Path]:  # fmt: skip
    """Write the run's files in `out`; returns them by kind."""
    from hapticsim.data.io import Contacts, write_contacts, write_json

    files = {
        "contacts": write_contacts(out / "contacts.npz", Contacts(points, normals, extra)),
        "truth": write_bytes_atomic(out / truth_file[0], truth_file[1]),
        "fit": write_json(out / "fit.json", result.to_dict()),
        "metrics": write_json(out / "metrics.json", metrics),
        "report": write_bytes_atomic(out / "report.png", report),
    }
    if tactile_file is not None:
        files["tactile"] = write_bytes_atomic(out / "tactile.npz", tactile_file)
    if hand_file is not None:
        files["hand"] = write_bytes_atomic(out / "hand.npz", hand_file)
    if "scene" in picture:
        files["scene"] = write_bytes_atomic(out / "scene.png", picture["scene"])
    if "video" in picture:
        name = f"exploration.{video_config.format}"
        files["video"] = write_bytes_atomic(out / name, picture["video"])
    return files


def _hand_args(scene_config: Any) -> str:
    """The ``--hand`` (and sensing) options that reproduce the scene's hand ('' for the
    default hand, exact sensing)."""
    hand = getattr(scene_config, "hand", None)
    text = ""
    if hand is not None and hand.name != "hapticsim":
        text = f" --hand {hand.source if hand.source is not None else hand.name}"
    if getattr(scene_config, "sensing", "exact") == "tactile":
        text += f" --sensing tactile --skin {scene_config.skin.name}"
        if scene_config.taxel_model != "hapticsim":
            text += f" --taxel-model {scene_config.taxel_model}"
    return text


def _placement_args(spec: Any) -> str:
    """The ``--scale``/``--pose`` options that reproduce a spec's placement ('' if none)."""
    text = "" if spec.scale == 1.0 else f" --scale {spec.scale}"
    if spec.pose is not None:

        values = [*spec.pose.position, *matrix_to_quaternion(spec.pose.rotation)]
        text += " --pose " + ",".join(f"{v:.9g}" for v in values)
    return text


def _completeness(run: Any) -> dict[str, Any]:
    """``complete``, ``requested`` and ``stop_reason`` of a run (SPEC §6: a run that gathers
    fewer contacts than asked says so)."""
    return {"complete": run.complete, "requested": run.requested, "stop_reason": run.stop_reason}


__all__ = ["DEFAULT_CONTACTS", "explore"]
