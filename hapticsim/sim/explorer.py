"""The explorer: runs fingertip controllers on a scene, moves the palm between them, keeps the
recorded contacts.

Strategies (:mod:`hapticsim.sim.strategies`) talk to the explorer in terms of probes and stripes
planned on the rough object; the explorer picks palm poses (:class:`PalmPlanner` on a planning
scene built from the rough object), moves the palm there along a path that keeps the hand clear
of the object (radially out to a safety sphere, around it over the top, in along the approach),
and steps the controllers until they finish.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import finite_array, finite_float, positive_fields, positive_int
from hapticsim.errors import ChoiceError, InvalidInputError, SimulationError
from hapticsim.geometry.rotations import matrix_to_rotvec, rotvec_to_matrix
from hapticsim.perception.vision import RoughObject
from hapticsim.sim.controllers import (
    FingerTask,
    FollowConfig,
    FollowTask,
    Probe,
    ProbeConfig,
    ProbeTask,
)
from hapticsim.sim.hand import finger_index
from hapticsim.sim.planning import PalmPlanner, PalmPose
from hapticsim.sim.recorder import Recorder
from hapticsim.sim.scene import Scene, SceneConfig, build_planning_scene
from hapticsim.sim.simulator import Simulator

Array = NDArray[np.float64]

#: Mesh resolution of the planning scene (the rough object).
PLANNING_MESH_RESOLUTION: int = 32
#: Ways of moving the palm between patterns (:attr:`ExplorerConfig.transit`).
TRANSITS: tuple[str, ...] = ("teleport", "simulate")
#: Smallest distance [m] between the hand and anything else for a pose to count as clear when
#: the hand is put there without simulating the way (the hand's geoms report contacts within
#: their 1 mm margin, so clear means no contact reported at all).
PLACE_CLEARANCE: float = 0.001


def planning_config(config: SceneConfig) -> SceneConfig:
    """The build options of a planning scene for a scene built with `config`: the same hand, a
    coarser mesh (:data:`PLANNING_MESH_RESOLUTION`), and a workspace that accepts the rough
    object even where the estimate came out larger than an explorable object (the true object
    was checked; palm goals are still checked against the arm's reach)."""
    w = config.workspace
    relaxed = replace(w, max_object_radius=max(2.0 * w.max_object_radius, w.reach), clearance=1e-6)
    return replace(config, mesh_resolution=PLANNING_MESH_RESOLUTION, workspace=relaxed,
                   sensing="exact")  # fmt: skip


#: Shortest stroke worth a contour-following run [m] (:meth:`Explorer.stroke`); a shorter
#: reachable stroke is left to a probe.
MIN_STROKE: float = 0.006
#: Lowest palm-pose score a stroke is planned from (the planner's scores fall far below it for
#: poses that collide or bend the finger backwards).
STROKE_MIN_SCORE: float = -50.0
#: Largest inverse-kinematics error [m] of a fingertip's entry point accepted for a palm pose.
IK_TOLERANCE: float = 0.002


@dataclass(frozen=True)
class ExplorerConfig:
    """Settings of an exploration run.

    Attributes:
        probe: probing parameters.
        follow: contour-following parameters.
        safe_distance: distance [m] the palm keeps from the rough bounding sphere in transit.
        back_off: distance [m] the palm backs off along the approach before and after transit.
        max_sim_time: longest simulated time of one exploration [s].
        pattern_timeout: longest simulated time of one pattern [s].
        max_misses: the exploration gives up after this many probes in a row met nothing.
        patch_misses: a patch gives up after this many of its probes in a row met nothing, and
            the strategy goes on with its next pattern (a patch planned on the rough object
            where the true one has a notch: the L-block's inner corner).
        transit: how the palm gets from one pattern to the next. ``"teleport"`` (default): the
            hand is put at rest at the new pose when it is clear of everything there
            (:meth:`Simulator.place`), or at the entry point `back_off` short of it, from
            where the approach is simulated; the way around the object is free space by
            construction and no contact is recorded on it, so stepping it is not physics.
            ``"simulate"``: every move is stepped (back off, around the object on the safety
            sphere, in), e.g. for a video.
    """

    probe: ProbeConfig = field(default_factory=ProbeConfig)
    follow: FollowConfig = field(default_factory=FollowConfig)
    safe_distance: float = 0.12
    back_off: float = 0.05
    max_sim_time: float = 120.0
    pattern_timeout: float = 20.0
    max_misses: int = 30
    patch_misses: int = 12
    transit: str = "teleport"

    def __post_init__(self) -> None:
        positive_fields(self, ("safe_distance", "back_off", "max_sim_time", "pattern_timeout"))
        positive_int(self.max_misses, "max_misses")
        positive_int(self.patch_misses, "patch_misses")
        if self.transit not in TRANSITS:
            raise ChoiceError("transit", self.transit, TRANSITS)


@dataclass(frozen=True)
class StripeSpec:
    """One stripe of a multi-finger sweep.

    Attributes:
        finger: finger index.
        start: the first probe.
        plane_normal_world: (3,) normal of the stripe's plane.
        direction_world: (3,) initial travel direction.
        length: path length [m].
    """

    finger: int
    start: Probe
    plane_normal_world: Array
    direction_world: Array
    length: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "finger", finger_index(self.finger))
        for name in ("plane_normal_world", "direction_world"):
            v = finite_array(getattr(self, name), name, (3,))
            if np.linalg.norm(v) < 1e-9:
                raise InvalidInputError(f"`{name}` must be a non-zero vector")
            object.__setattr__(self, name, v / np.linalg.norm(v))
        object.__setattr__(self, "length", finite_float(self.length, "length", low=0.0))


def force_limited(config: ExplorerConfig, limit: float | None) -> ExplorerConfig:
    """`config` with its controllers pressing below a force limit [N] (None: as it is): probes
    record at 60 % of the limit (at most their own threshold) and approach at a quarter of
    the speed; contour following presses with half the limit (at most its own force) and
    records between a quarter of it and the limit."""
    if limit is None:
        return config
    probe, follow = config.probe, config.follow
    probe = replace(probe, force_threshold=min(probe.force_threshold, 0.6 * limit),
                    speed=0.25 * probe.speed)  # fmt: skip
    low = min(follow.band[0], 0.25 * limit)
    follow = replace(follow, force=min(follow.force, 0.5 * limit), band=(low, limit))
    return replace(config, probe=probe, follow=follow)


class Explorer:
    """Runs an exploration on a scene.

    Args:
        scene: the scene with the true object.
        rough: what the controllers know about the object.
        recorder: where contacts go (its capacity ends the exploration).
        config: settings.
        progress: called with the number of recorded contacts after every pattern.
        on_pattern_end: called with the explorer after every pattern, fingers still on the
            object (e.g. to take a picture).
        planning_scene: the scene the palm planner works on; it must hold the rough object
            (default: :func:`~hapticsim.sim.scene.build_planning_scene` of ``rough.shape``).
        tactile_rng: with tactile sensing, the generator of the skin's sensor model (its fixed
            pattern and noise; default seed 0).
    """

    def __init__(
        self,
        scene: Scene,
        rough: RoughObject,
        recorder: Recorder,
        config: ExplorerConfig | None = None,
        progress: Callable[[int], None] | None = None,
        on_pattern_end: Callable[[Explorer], None] | None = None,
        planning_scene: Scene | None = None,
        tactile_rng: np.random.Generator | None = None,
    ) -> None:
        self.scene = scene
        self.rough = rough
        self.recorder = recorder
        self.config = force_limited(ExplorerConfig() if config is None else config,
                                    scene.config.force_limit)  # fmt: skip
        self.progress = progress
        self.on_pattern_end = on_pattern_end
        self.sim = Simulator(scene, tactile_rng=tactile_rng)
        if planning_scene is None:
            planning_scene = build_planning_scene(rough.shape, planning_config(scene.config))
        self.planner = PalmPlanner(planning_scene)
        self.patterns_run = 0
        self.log: list[dict[str, object]] = []
        self._approach = np.array([0.0, 0.0, -1.0])
        self.misses = 0
        #: why a free object can no longer be explored (it tipped over or left), else None.
        self.lost: str | None = None
        self._watch = None
        if scene.free:
            recorder.pose_source = self.sim.object_pose
        self.home()

    # ------------------------------------------------------------------ palm motion
    @property
    def safe_radius(self) -> float:
        """Radius [m] of the sphere about the rough centre the palm keeps to in transit."""
        return self.rough.radius + self.config.safe_distance

    def home(self) -> None:
        """Reset the simulation with the palm above the object, palm down, fingers tucked."""
        pos = self.rough.center + np.array([0.0, 0.0, self.safe_radius])
        self.sim.reset(pos, np.eye(3))
        self._approach = np.array([0.0, 0.0, -1.0])

    @property
    def out_of_time(self) -> bool:
        """True when the simulated-time budget is used up or too many probes in a row missed."""
        return (self.sim.time > self.config.max_sim_time or self.misses >= self.config.max_misses
                or self.lost is not None)  # fmt: skip

    @property
    def stop_reason(self) -> str | None:
        """Why the exploration ended short of the recorder's capacity; None when it is full."""
        if self.recorder.full:
            return None
        cfg = self.config
        if self.lost is not None:
            return self.lost
        if self.sim.time > cfg.max_sim_time:
            return f"the simulated-time budget of {cfg.max_sim_time:g} s was used up (max_sim_time)"
        if self.misses >= cfg.max_misses:
            return f"{self.misses} probes in a row met nothing (max_misses)"
        return "the strategy ran out of patterns"

    def _go(
        self, position: Array, rotation: Array, settle: bool = False, transit: bool = False
    ) -> None:
        """Move the palm (mocap) to a pose; no controller runs, so no contacts are read.

        Args:
            position: (3,) float, palm goal [m, world].
            rotation: (3, 3) float, palm goal rotation.
            settle: then wait (up to 0.15 s) for the palm itself to get there.
            transit: free-space speeds (:attr:`ServoConfig.transit_speed`): only between the
                back-off and entry points (out to the safety sphere, on it, in to the entry),
                fingers tucked.
        """
        sim = self.sim
        sim.set_palm_goal(position, rotation, transit=transit)
        limit = sim.time + 5.0
        while not sim.palm_at_goal():
            sim.tick(read=False)
            if sim.time > limit:
                raise SimulationError("the palm did not reach its goal within 5 s")
        if settle:
            until = sim.time + 0.15
            while sim.time < until:
                sim.tick(read=False)
                pos, _ = sim.palm_pose()
                if np.linalg.norm(pos - position) < 5e-4 and sim.time > until - 0.1:
                    break

    def _arc(self, start: Array, end: Array) -> list[Array]:
        """Waypoints from `start` to `end` on the safety sphere, over the top of the object."""
        c, radius = self.rough.center, self.safe_radius
        u0, u1 = (start - c) / np.linalg.norm(start - c), (end - c) / np.linalg.norm(end - c)
        up = np.array([0.0, 0.0, 1.0])
        path = [u0]
        if u0 @ u1 < 0.0 or min(u0[2], u1[2]) < 0.0:
            path.append(up)  # go over the top rather than under the object
        path.append(u1)
        points: list[Array] = []
        for a, b in zip(path[:-1], path[1:], strict=True):
            angle = float(np.arccos(np.clip(a @ b, -1.0, 1.0)))
            steps = max(1, int(np.ceil(angle / np.radians(20.0))))
            for k in range(1, steps + 1):
                s = k / steps
                if angle < 1e-6:
                    v = b
                else:
                    v = (np.sin((1 - s) * angle) * a + np.sin(s * angle) * b) / np.sin(angle)
                points.append(c + radius * v / np.linalg.norm(v))
        return points

    def move_palm(
        self, pose: PalmPose, approach_world: Array, postures: Mapping[int, Array]
    ) -> None:
        """Move the palm to a planned pose along a collision-avoiding path.

        The fingers freeze, the palm backs off along its current approach direction, the fingers
        tuck, the palm travels around the object on the safety sphere (turning on the way), the
        fingers named in `postures` unfold, and the palm moves in along `approach_world`.

        With ``config.transit == "teleport"`` the way out and around is not stepped (see
        :class:`ExplorerConfig`): the hand is put at rest at the goal, or at the entry point
        from where the approach is stepped; only when both are blocked is every move stepped.

        Args:
            pose: the goal.
            approach_world: (3,) main approach direction of the coming pattern.
            postures: joint postures [rad] by finger index to take before moving in.
        """
        d_new = np.asarray(approach_world, float) / np.linalg.norm(approach_world)
        if self.config.transit == "teleport" and self._place(pose, d_new, postures):
            self._approach = d_new
            return
        self._simulated_move(pose, d_new, postures)
        self._approach = d_new

    def _place(self, pose: PalmPose, d_new: Array, postures: Mapping[int, Array]) -> bool:
        """Put the hand at the goal, else at the entry and step the approach; False (state
        unchanged) when both are blocked."""
        sim = self.sim
        saved = sim.get_state()
        sim.place(pose.position, pose.rotation, postures)
        if sim.hand_clearance() >= PLACE_CLEARANCE:
            return True
        entry = pose.position - d_new * self.config.back_off
        sim.place(entry, pose.rotation, postures)
        if sim.hand_clearance() >= PLACE_CLEARANCE:
            self._go(pose.position, pose.rotation, settle=True)
            return True
        sim.set_state(saved)
        return False

    def _simulated_move(self, pose: PalmPose, d_new: Array, postures: Mapping[int, Array]) -> None:
        sim, c = self.sim, self.rough.center
        for f in self.scene.hand.fingers:
            sim.set_posture(f.index, sim.hand.finger_qpos(sim.data, f.index))
        pos, rot = sim.mocap_pose()
        back = pos - self._approach * self.config.back_off
        self._go(back, rot)
        for f in self.scene.hand.fingers:
            sim.set_posture(f.index, f.posture("tucked"))
        entry = pose.position - d_new * self.config.back_off
        far = c + (entry - c) * max(1.0, self.safe_radius / np.linalg.norm(entry - c))
        out = c + (back - c) * max(1.0, self.safe_radius / np.linalg.norm(back - c))
        # out to the safety sphere, around the object on it (turning the palm gradually on the
        # way) and in to the entry point, back_off short of the goal: free space with the
        # fingers tucked, so at the transit speeds
        self._go(out, rot, transit=True)
        turn = matrix_to_rotvec(rot.T @ pose.rotation)
        waypoints = self._arc(out, far)
        fractions = np.arange(1, len(waypoints) + 1) / len(waypoints)
        turns = rotvec_to_matrix(fractions[:, None] * turn[None, :])  # one batched call
        for w, turn_k in zip(waypoints, turns, strict=True):
            self._go(w, rot @ turn_k, transit=True)
        self._go(far, pose.rotation, transit=True)
        self._go(entry, pose.rotation, transit=True)
        for f, q in postures.items():
            sim.set_posture(f, q)
        self._go(pose.position, pose.rotation, settle=True)

    # ------------------------------------------------------------------ running controllers
    def run(self, tasks: Sequence[FingerTask]) -> None:
        """Step the controllers until all are done, the recorder is full or time runs out."""
        sim = self.sim
        for t in tasks:
            sim.hand.finger_index(t.finger)  # a finger the hand has
        limit = sim.time + self.config.pattern_timeout
        while not all(t.done for t in tasks):
            contacts = sim.tick()
            for t in tasks:
                if not t.done:
                    t.update(sim, contacts)
            if self.scene.free:
                self.check_object()
            if self.recorder.full or sim.time > limit or self.out_of_time:
                for t in tasks:
                    if not t.done:
                        t.finish(sim, "stopped")
                break
        # hold the fingers where they are
        for t in tasks:
            sim.set_tip_target(t.finger, sim.tip_world(t.finger))
        self.patterns_run += 1
        for t in tasks:
            if t.recorded > 0:
                self.misses = 0
            elif isinstance(t, ProbeTask):
                self.misses += t.failed
            else:
                self.misses += 1
        for t in tasks:
            self.log.append(
                {"task": type(t).__name__, "finger": t.finger, "recorded": t.recorded,
                 "message": t.message, "time": round(sim.time, 4)}
            )  # fmt: skip
        if self.progress is not None:
            self.progress(len(self.recorder))
        if self.on_pattern_end is not None:
            self.on_pattern_end(self)

    def check_object(self) -> str | None:
        """With a free object, whether it tipped over or left its place
        (:class:`~hapticsim.sim.dynamics.MotionWatch`); the reason is kept in :attr:`lost` and
        ends the exploration."""
        if self.scene.free and self.lost is None:
            from hapticsim.sim.dynamics import MotionWatch

            initial = self.sim.initial_object_pose
            if self._watch is None or self._watch.initial is not initial:
                self._watch = MotionWatch(initial, self.scene.object_body_id)
            self.lost = self._watch.reason(self.sim.data)
        return self.lost

    # ------------------------------------------------------------------ patterns
    def probe_patch(
        self, finger: int, probes: Sequence[Probe], posture: Array | None = None
    ) -> int:
        """Probe a patch with one finger; probes are grouped by palm pose.

        Args:
            finger: finger index.
            probes: the probes.
            posture: (n,) joint angles [rad] whose tip the palm pose puts on the patch
                (default: the finger's ``probe`` posture).

        Returns:
            Number of contacts recorded.
        """
        finger = self.scene.hand.finger_index(finger)
        if posture is None:
            posture = self.scene.hand.posture(finger, "probe")
        radius = self.scene.hand.fingers[finger].tip_radius
        standoff = self.config.probe.standoff
        remaining = list(probes)
        before = len(self.recorder)
        pattern = self.recorder.new_pattern("patch")
        start_misses = self.misses
        while remaining and not self.recorder.full and not self.out_of_time:
            patch_left = self.config.patch_misses - (self.misses - start_misses)
            if patch_left <= 0:
                break  # this patch meets nothing: leave it to the next pattern
            mean_aim = np.mean([p.aim_world for p in remaining], axis=0)
            mean_dir = np.mean([p.approach_world for p in remaining], axis=0)
            mean_dir /= np.linalg.norm(mean_dir)
            # tip of the nominal posture on the surface near the patch centre
            first = min(remaining, key=lambda p: np.linalg.norm(p.aim_world - mean_aim))
            tip = first.aim_world - mean_dir * radius
            pose = self.planner.probe_poses(finger, tip, mean_dir, posture)[0]
            group, rest = [], []
            for p in remaining:
                pts = [p.start(standoff, radius), p.aim_world + p.approach_world * 0.004]
                ok, _ = self.planner.reachable(finger, pose, pts, posture)
                (group if ok else rest).append(p)
            if not group:  # the nominal posture itself reaches `first`'s aim
                group, rest = [first], [p for p in remaining if p is not first]
            # move in with the tip already at the first probe's start point
            q, err = self.planner.kin.ik(
                finger, group[0].start(standoff, radius), pose.position, pose.rotation, posture
            )
            self.move_palm(pose, mean_dir, {finger: q if err < IK_TOLERANCE else posture})
            limit = min(self.config.max_misses - self.misses, patch_left)
            self.run([ProbeTask(finger, group, self.recorder, pattern, self.config.probe, limit)])
            remaining = rest
        return len(self.recorder) - before

    def sweep(
        self,
        pose: PalmPose,
        approach_world: Array,
        stripes: Sequence[StripeSpec],
        postures: Mapping[int, Array],
        extra: Sequence[tuple[int, Sequence[Probe]]] = (),
        follow: FollowConfig | None = None,
    ) -> int:
        """Several fingers follow contours at once from one palm pose; optionally other fingers
        probe meanwhile (e.g. the thumb on a corner).

        Args:
            pose: palm pose.
            approach_world: (3,) direction the palm comes in along.
            stripes: one per following finger.
            postures: finger postures to take before moving in.
            extra: (finger, probes) patches probed at the same time.
            follow: the contour following of these stripes (default ``config.follow``).

        Returns:
            Number of contacts recorded.
        """
        follow = self.config.follow if follow is None else follow
        before = len(self.recorder)
        self.move_palm(pose, approach_world, postures)
        tasks: list[FingerTask] = []
        for s in stripes:
            pattern = self.recorder.new_pattern("stripe")
            tasks.append(
                FollowTask(s.finger, s.start, s.plane_normal_world, s.direction_world, s.length,
                           self.recorder, pattern, follow, self.config.probe)
            )  # fmt: skip
        for finger, probes in extra:
            pattern = self.recorder.new_pattern("patch")
            tasks.append(ProbeTask(finger, probes, self.recorder, pattern, self.config.probe,
                                   self.config.max_misses))  # fmt: skip
        self.run(tasks)
        return len(self.recorder) - before

    def stroke(
        self,
        finger: int,
        first: Probe,
        path_world: Array,
        plane_normal_world: Array,
        direction_world: Array,
        follow: FollowConfig | None = None,
    ) -> bool:
        """One finger strokes along a planned path from a first probe: the palm pose that keeps
        the longest reachable start of the path, then a contour-following run over it.

        Args:
            finger: the stroking finger.
            first: the probe that starts the stroke (its target on the surface).
            path_world: (k, 3) points on the (rough) surface the stroke should pass, from the
                first probe's target on [m].
            plane_normal_world, direction_world: (3,) the stroke's plane and initial direction.
            follow: the contour following (default ``config.follow``).

        Returns:
            False when no stroke of at least :data:`MIN_STROKE` can be planned (nothing moved).
        """
        path = np.asarray(path_world, dtype=np.float64)
        if len(path) < 2:
            return False
        normals = self.rough.shape.normals(path)
        hand = self.scene.hand
        radius = hand.fingers[finger].tip_radius
        sweep_q = hand.posture(finger, "sweep")
        tips = path + radius * normals
        mid = len(path) // 2
        entry = first.start(self.config.probe.standoff, radius)
        best: tuple[int, PalmPose, Array] | None = None
        poses = self.planner.probe_poses(
            finger, tips[mid], -normals[mid], sweep_q, flexion_axis_world=plane_normal_world
        )
        for pose in poses:
            if pose.score < STROKE_MIN_SCORE:
                continue
            q, err = self.planner.kin.ik(finger, entry, pose.position, pose.rotation, sweep_q)
            if err > IK_TOLERANCE:
                continue
            _, ok = self.planner.reachable(finger, pose, list(tips), sweep_q)
            last = 0
            while last + 1 < len(ok) and ok[last + 1]:
                last += 1
            if ok[0] and (best is None or last > best[0]):
                best = (last, pose, q)
        if best is None:
            return False
        last, pose, q = best
        length = float(np.sum(np.linalg.norm(np.diff(path[: last + 1], axis=0), axis=1)))
        if length < MIN_STROKE:
            return False
        stripe = StripeSpec(finger, first, plane_normal_world, direction_world, length)
        self.sweep(pose, -normals[mid], [stripe], {finger: q}, follow=follow)
        return True


__all__ = [
    "IK_TOLERANCE",
    "MIN_STROKE",
    "STROKE_MIN_SCORE",
    "Explorer",
    "ExplorerConfig",
    "StripeSpec",
    "TRANSITS",
    "planning_config",
]
