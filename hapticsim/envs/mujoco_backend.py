"""The MuJoCo touch backend: each action is executed by the simulated hand's scripted controllers.

A thin adapter from a :class:`~hapticsim.envs.touch.Touch` to :mod:`hapticsim.sim`:

- the episode's scene (:func:`~hapticsim.sim.scene.build_scene`: hand, table, object mesh) and an
  :class:`~hapticsim.sim.explorer.Explorer` whose palm planner works on a *rough object*: the
  environment's vision estimate (:func:`~hapticsim.perception.vision.vision_estimate`: a box or an
  ellipsoid fitted to one noisy depth image) at its rough position;
- the aim of a touch is where the approach ray (from far along ``d`` towards the rough position)
  meets the rough object;
- a **probe**: one :class:`~hapticsim.sim.controllers.ProbeTask` probe at the aim, moving along
  ``-d``, with a palm pose planned for the chosen finger (:meth:`Explorer.probe_patch`);
- a **stroke**: a :class:`~hapticsim.sim.controllers.FollowTask` (contour following in the plane
  spanned by the rough normal at the aim and the stroke direction, as in the analytic backend),
  starting with a probe at the aim along ``-d``. The palm pose puts the finger, in a hook posture,
  over the middle of the stroke as predicted on the rough object, its flexion plane in the
  stroke's plane; the stroke is cut to the part the finger can reach from there (inverse
  kinematics on the planning scene);
- an aim where a fingertip would hit the stand holding the object is unreachable
  (``"blocked"``, the rule of the analytic backend, :class:`~hapticsim.envs.support.Support`);
  a touch that records nothing is ``"missed"``; a simulation error (unreachable palm goal,
  instability) is ``"failed"`` and the hand goes home.

Recorded contacts are MuJoCo's (SPEC §7), with sensor noise added afterwards (SPEC §5).
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import finite_float
from hapticsim.envs.support import Support
from hapticsim.envs.touch import Touch, TouchBackend, TouchResult
from hapticsim.errors import HapticsimError, InvalidInputError
from hapticsim.geometry import Superquadric
from hapticsim.geometry.sections import section_walk, stroke_plane
from hapticsim.geometry.solid import Solid
from hapticsim.perception.vision import RoughObject, vision_estimate

Array = NDArray[np.float64]

#: Lead of the contour-following target along the tangent in a stroke [m]. It sets the sliding
#: speed: about 10 cm/s here against 5 cm/s at :class:`~hapticsim.sim.controllers.FollowConfig`'s
#: 0.002 (which the sim's own explorations keep), 40 % fewer control ticks per stroke. Measured on
#: seeded random-touch episodes: same contact counts and accuracy (median distance ~1e-5 m,
#: normal angle p95 < 1.7 deg, max < 2 deg) as at 0.002.
FOLLOW_LEAD: float = 0.004


class MujocoBackend(TouchBackend):
    """Touches executed by the MuJoCo hand (see the module docstring).

    Args:
        noise: relative sensor noise sigma_N (SPEC §5).
        stroke_spacing: distance between recorded contacts along a stroke [m].
        scene_config: scene options (:class:`hapticsim.sim.scene.SceneConfig`), default ones
            if None; its hand is replaced by `hand` when that is given.
        hand: the hand: a shipped name (``"hapticsim"``, ``"shadow"``, ``"adroit"``), a TOML
            description path or a :class:`~hapticsim.sim.hand_description.HandDescription`
            (default: the scene configuration's, hapticsim's own four-fingered hand).
        sensing: ``"exact"`` (MuJoCo's contacts) or ``"tactile"`` (estimated from the hand's
            taxel pads, :mod:`hapticsim.sim.tactile`); None: the scene configuration's.
        skin: with tactile sensing, the skin (a preset name, a ``.toml`` file or a
            :class:`~hapticsim.perception.tactile.SkinPreset`); None: the scene configuration's.

    Raises:
        InvalidInputError: an unknown or invalid hand (the message names the problem).
    """

    def __init__(
        self,
        noise: float = 0.0,
        stroke_spacing: float = 0.005,
        scene_config=None,  # noqa: ANN001 - hapticsim.sim.scene.SceneConfig
        hand=None,  # noqa: ANN001 - str | Path | HandDescription
        sensing: str | None = None,
        skin=None,  # noqa: ANN001 - str | Path | SkinPreset
    ) -> None:
        from hapticsim.sim.scene import PlanningSceneCache, SceneCache, SceneConfig

        self.noise = finite_float(noise, "noise", 0.0, 1.0)
        self.stroke_spacing = finite_float(stroke_spacing, "stroke_spacing", 1e-3, 0.05)
        config = SceneConfig() if scene_config is None else scene_config
        if hand is not None:
            config = replace(config, hand=hand)
        if sensing is not None:
            config = replace(config, sensing=sensing)
        if skin is not None:
            config = replace(config, skin=skin)
        self.scene_config = config
        #: number of fingers of the hand (action component 4 selects one; 0 is the thumb).
        self.n_fingers = len(config.hand.fingers)
        #: compiled scenes of the objects seen so far (a paper body comes back every few
        #: episodes; its scene is compiled once).
        self._scenes = SceneCache()
        #: planning scenes of the rough objects (a primitive resized in place every episode).
        self._planning = PlanningSceneCache()
        self._truth: Solid | None = None
        self._rng: np.random.Generator | None = None
        self._explorer = None
        self._support: Support | None = None
        self._renderer = None
        self._render_model = None

    @property
    def explorer(self) -> Any:
        """The simulation's explorer of the current episode (None before the first reset)."""
        return self._explorer

    @property
    def pad_shape(self) -> tuple[int, int, int]:
        """(pads, rows, cols) of the hand's readings with tactile sensing: a pad per finger,
        the hand's grid laid out at the skin's own pitch where it has one."""
        from hapticsim.perception.tactile import PadLayout

        config = self.scene_config
        if config.sensing != "tactile":
            raise InvalidInputError("the hand has no pads without tactile sensing")
        rows, cols, pitch = config.hand.pad_grid
        grid = PadLayout(rows, cols, pitch, None, [0, 0, 1], [0, 1, 0], [0, 0, 0])
        if config.skin.pitch is not None:
            grid = grid.resampled(config.skin.pitch)
        return (self.n_fingers, *grid.shape)

    # ------------------------------------------------------------------ episode
    def reset(
        self, shape: Solid, rng: np.random.Generator, rough: RoughObject | None = None,
        prepared: Any = None,
    ) -> Solid:  # fmt: skip
        """Build the scene for `shape` (placed as given, on a stand above the table).

        Args:
            shape: the object.
            rng: the episode's sensor stream (noise, tactile readings; the vision estimate
                when `rough` is None).
            rough: what the palm planner knows (the environment's vision estimate at its rough
                position); None: a vision estimate of its own
                (:func:`~hapticsim.perception.vision.vision_estimate`).
            prepared: unused (the hand's scene comes from its own cache).

        Returns:
            the ground truth: `shape` itself, or a free object where it came to rest in its
            cradle (SPEC §12).

        Raises:
            SimulationError: the object is too large or too far for the hand.
        """
        from hapticsim.sim.explorer import Explorer, ExplorerConfig, planning_config
        from hapticsim.sim.recorder import Recorder

        self.close()
        scene = self._scenes.scene(shape, self.scene_config)
        if rough is None:
            rough = vision_estimate(shape, rng)
        planning = self._planning.scene(rough.shape, planning_config(scene.config))
        # the skin's sensor draws from a stream of its own (exact sensing draws nothing here)
        tactile_rng = (
            np.random.default_rng(int(rng.integers(2**63)))
            if scene.config.sensing == "tactile" else None
        )  # fmt: skip
        self._explorer = Explorer(
            scene, rough, Recorder(None), ExplorerConfig(), planning_scene=planning,
            tactile_rng=tactile_rng,
        )  # fmt: skip
        stand = scene.stand_geom_id
        foot = scene.model.geom_pos[stand].copy()
        foot[2] = scene.model.geom_pos[stand][2] + scene.model.geom_size[stand][1] - 0.002
        self._support = Support("stand", foot, float(scene.model.geom_size[stand][0]))
        self._truth = scene.truth  # a free object: where it rests before the first touch
        self._rng = rng
        return scene.truth

    def touch(self, touch: Touch, origin: Array) -> TouchResult:
        """Execute one probe or stroke aimed at `origin` (3,) [m, world] with the hand.

        Raises:
            InvalidInputError: before :meth:`reset`, or for a finger the hand does not have.
        """
        self._check_touch(touch, self._explorer is not None)
        start = time.perf_counter()
        ex = self._explorer
        assert ex is not None
        if ex.lost is not None:  # a free object that tipped over or left: nothing to touch
            return TouchResult.empty("failed", time.perf_counter() - start, ex.lost)
        aim, failed = self._approach(ex.rough.shape, touch, origin, start, "no rough surface")
        if aim is None:
            return failed  # type: ignore[return-value]
        before = len(ex.recorder)
        pose = ex.sim.object_pose()
        message = ""
        try:
            if touch.is_probe or not self._stroke(touch, aim):
                self._probe(touch, aim)
        except HapticsimError as exc:  # SimulationError: unreachable goal, instability
            message = str(exc)
            ex.home()
        new = ex.recorder.arrays(before)  # this touch's contacts only
        k = len(ex.recorder) - before
        seconds = time.perf_counter() - start
        moved = {}
        if pose is not None:
            from hapticsim.sim.dynamics import pose_change

            shift, angle = pose_change(ex.sim.object_pose(), pose)
            moved = {"object_moved": shift, "object_turned": angle}
        if k == 0:
            status = "failed" if message else "missed"
            return replace(TouchResult.empty(status, seconds, message or "no contact recorded"),
                           **moved)  # fmt: skip
        pts_clean, nrm_clean = new["points_clean"], new["normals_clean"]
        pts, nrm = self._noisy(pts_clean, nrm_clean)
        tactile = {}
        if ex.recorder.tactile:
            pads = ex.recorder.tactile_arrays(before)
            tactile = dict(
                images=pads["images"], sigma=new["sigma"], traction=pads["traction"],
                taxel_state=pads["taxel_state"], points_exact=new["points_exact"],
                normals_exact=new["normals_exact"],
            )  # fmt: skip
        return TouchResult(
            points=pts, normals=nrm, points_clean=pts_clean, normals_clean=nrm_clean,
            finger=new["finger"], force=new["force"], time=new["time"],
            status="ok", seconds=seconds, message=message, **tactile, **moved,
        )  # fmt: skip

    def _probe(self, touch: Touch, aim: Array) -> None:
        from hapticsim.sim.controllers import Probe

        assert self._explorer is not None
        self._explorer.probe_patch(touch.finger, [Probe(aim, -touch.approach)])

    def _stroke(self, touch: Touch, aim: Array) -> bool:
        """Plan and run a stroke; False when no useful stroke can be planned (then probe)."""
        from hapticsim.sim.controllers import Probe

        ex = self._explorer
        assert ex is not None
        rough = ex.rough.shape
        n_steps = int(round(touch.stroke_length / self.stroke_spacing))
        path = section_walk(rough, aim, touch.stroke_angle, n_steps, self.stroke_spacing,
                            self._reachable)  # fmt: skip
        direction, plane = stroke_plane(rough, aim, touch.stroke_angle)
        follow = replace(ex.config.follow, spacing=self.stroke_spacing, lead=FOLLOW_LEAD)
        return ex.stroke(touch.finger, Probe(aim, -touch.approach), np.asarray(path), plane,
                         direction, follow)  # fmt: skip

    # ------------------------------------------------------------------ rendering
    def render(
        self, estimate: Superquadric | None, points: Array, width: int, height: int
    ) -> NDArray[np.uint8]:
        """The scene with the hand (camera ``overview``), contacts in red and the estimate as a
        cloud of translucent blue dots."""
        import mujoco

        from hapticsim.envs.rendering import ESTIMATE_RGBA, add_markers

        if self._explorer is None:
            raise InvalidInputError("call `reset` before `render`")
        sim = self._explorer.sim
        if self._renderer is None or self._render_model is not sim.model:
            if self._renderer is not None:
                self._renderer.close()
            self._renderer = mujoco.Renderer(sim.model, height, width)
            self._render_model = sim.model
        self._renderer.update_scene(sim.data, camera="overview")
        # no shadow maps: on a CPU renderer they are 90 % of a picture (0.45 s against 0.05 s)
        self._renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = False
        add_markers(self._renderer.scene, points)
        if estimate is not None:
            eta = np.linspace(-np.pi / 2, np.pi / 2, 15).repeat(24)
            omega = np.tile(np.linspace(-np.pi, np.pi, 24, endpoint=False), 15)
            add_markers(self._renderer.scene, estimate.surface(eta, omega)[0], ESTIMATE_RGBA)
        return self._renderer.render().copy()

    def close(self) -> None:
        """Free the renderer and the simulation."""
        if self._renderer is not None:
            self._renderer.close()
        self._renderer = None
        self._render_model = None
        self._explorer = None
