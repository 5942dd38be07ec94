"""Edge-crossing sweeps: up to three fingers follow parallel contours across an edge of the rough
object while, optionally, the thumb probes the corner at the end of that edge (paper IV: "a thumb
touching the cube's corner while moving three fingers in parallel across its side face")."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hapticsim.sim.controllers import Probe
from hapticsim.sim.explorer import Explorer, StripeSpec
from hapticsim.sim.planning import PalmPose
from hapticsim.sim.strategies.geometry import EdgeContour, corner_probes, edge_contour

Array = NDArray[np.float64]

#: Largest stripe extent on either side of the edge [m].
MAX_HALF_STRIPE: float = 0.03
#: Shortest useful extent on either side of the edge [m].
MIN_HALF_STRIPE: float = 0.008


@dataclass(frozen=True)
class SweepPlan:
    """A planned sweep.

    Attributes:
        pose: palm pose.
        approach_world: (3,) direction the palm comes in along (inward edge bisector).
        stripes: one per finger that can do its stripe.
        postures: joint postures [rad] to take before moving in, by finger.
        contour: the middle finger's contour.
    """

    pose: PalmPose
    approach_world: Array
    stripes: tuple[StripeSpec, ...]
    postures: dict[int, Array]
    contour: EdgeContour

    @property
    def total_length(self) -> float:
        """Sum of the stripe lengths [m]."""
        return float(sum(s.length for s in self.stripes))


def _half_length(
    explorer: Explorer, point: Array, inward: Array, axis: Array
) -> tuple[float, float]:
    """Distances [m] from a point just inside an edge to the rough surface along +axis, -axis."""
    shape = explorer.rough.shape
    p = point - inward * 0.004
    out = []
    for sign in (1.0, -1.0):
        s = np.linspace(0.0, 2 * explorer.rough.radius, 400)
        pts = p + np.outer(s, sign * axis)
        inside = shape.inside_outside(pts) < 1.0
        out.append(float(s[np.argmin(inside)]) if not inside.all() else float(s[-1]))
    return out[0], out[1]


def plan_sweep(
    explorer: Explorer,
    face_a: tuple[int, float],
    face_b: tuple[int, float],
    fingers: Sequence[int] | None = None,
    max_half: float = MAX_HALF_STRIPE,
) -> SweepPlan | None:
    """Plan a sweep across the edge between two faces of the rough object (see
    :func:`~hapticsim.sim.strategies.geometry.edge_contour` for the face convention).

    The palm pose puts the hand's middle sweeping finger (:attr:`Hand.middle`), in its
    ``sweep`` (hook) posture, on the edge with its radial direction along the inward edge
    bisector and its flexion axis along the edge; each finger's stripe is trimmed to the part of
    its contour it can reach (inverse kinematics on the planning scene). Returns None when no
    finger can do a useful stripe.

    Args:
        explorer: the explorer.
        face_a, face_b: the faces, (body axis, sign).
        fingers: the sweeping fingers (default: the hand's :attr:`Hand.sweep_fingers`).
        max_half: longest stripe on either side of the edge [m].
    """
    planner, rough = explorer.planner, explorer.rough
    hand = explorer.scene.hand
    fingers = hand.sweep_fingers if fingers is None else tuple(fingers)
    middle = hand.middle if hand.middle in fingers else fingers[len(fingers) // 2]
    sweep_q = {f: hand.posture(f, "sweep") for f in {*fingers, middle}}
    contour = edge_contour(rough, face_a, face_b)
    edge_point = contour.points_world[contour.edge_index]
    bisector = contour.normals_world[contour.edge_index]
    u = contour.plane_normal_world
    plus, minus = _half_length(explorer, edge_point, bisector, u)
    s_edge = contour.edge_arc
    s_lo = max(s_edge - max_half, contour.face_a_end + 0.15 * (s_edge - contour.face_a_end))
    s_hi = min(s_edge + max_half, contour.face_b_end - 0.15 * (contour.face_b_end - s_edge))
    arcs = np.linspace(s_lo, s_hi, 13)
    best: SweepPlan | None = None
    tip_edge = edge_point + bisector * hand.fingers[middle].tip_radius
    standoff = explorer.config.probe.standoff
    poses = planner.probe_poses(middle, tip_edge, -bisector, sweep_q[middle], flexion_axis_world=u)
    for pose in poses:
        if pose.score < -50:
            continue
        bases = {f: planner.kin.base_and_tip(f, sweep_q[f], pose.position, pose.rotation)[0]
                 for f in {*fingers, middle}}  # fmt: skip
        mid_base = bases[middle]
        stripes, postures = [], {}
        for f in fingers:
            offset = float((bases[f] - mid_base) @ u)
            limit = (plus if offset > 0 else minus) - 0.006
            offset = float(np.sign(offset) * min(abs(offset), max(limit, 0.0)))
            # each finger follows the contour of its own plane (round sections differ)
            own = contour if abs(offset) < 1e-4 else edge_contour(rough, face_a, face_b, offset)
            s_edge_f = own.edge_arc
            arcs_f = arcs - s_edge + s_edge_f
            radius = hand.fingers[f].tip_radius
            tips = [own.at(s)[0] + own.at(s)[1] * radius for s in arcs_f]
            _, ok = planner.reachable(f, pose, tips, sweep_q[f])
            k_edge = int(np.argmin(np.abs(arcs_f - s_edge_f)))
            if not ok[k_edge]:
                continue
            lo = k_edge
            while lo > 0 and ok[lo - 1]:
                lo -= 1
            hi = k_edge
            while hi < len(arcs) - 1 and ok[hi + 1]:
                hi += 1
            if s_edge_f - arcs_f[lo] < MIN_HALF_STRIPE or arcs_f[hi] - s_edge_f < MIN_HALF_STRIPE:
                continue
            p0, n0 = own.at(arcs_f[lo])
            p1, _ = own.at(arcs_f[lo] + 0.002)
            start = Probe(p0, -n0)
            q, err = planner.kin.ik(f, start.start(standoff, radius), pose.position,
                                    pose.rotation, sweep_q[f])  # fmt: skip
            if err > 0.002:
                continue
            postures[f] = q
            stripes.append(StripeSpec(f, start, u, p1 - p0, float(arcs[hi] - arcs[lo])))
        if stripes and planner.collision_count(pose.position, pose.rotation, postures):
            continue  # some link would touch the rough object at the stripes' starts
        if stripes and (best is None or sum(s.length for s in stripes) > best.total_length):
            best = SweepPlan(pose, -bisector, tuple(stripes), postures, contour)
    return best


def thumb_corner_probes(
    explorer: Explorer,
    plan: SweepPlan,
    corner_signs: Sequence[tuple[float, float, float]],
    count: int,
    rng: np.random.Generator,
) -> tuple[list[Probe], Array | None]:
    """Corner-patch probes the thumb can reach from a sweep's palm pose (best corner).

    Returns:
        The reachable probes (at most `count`) and the thumb posture to move in with.
    """
    planner = explorer.planner
    hand = explorer.scene.hand
    thumb = hand.thumb
    probe_q, radius = hand.posture(thumb, "probe"), hand.fingers[thumb].tip_radius
    standoff = explorer.config.probe.standoff
    best: tuple[list[Probe], Array | None] = ([], None)
    for signs in corner_signs:
        candidates = corner_probes(explorer.rough, signs, 3 * count, rng)
        kept = []
        for p in candidates:
            pts = [p.start(standoff, radius), p.aim_world + p.approach_world * 0.004]
            ok, _ = planner.reachable(thumb, plan.pose, pts, probe_q)
            if ok:
                kept.append(p)
            if len(kept) >= count:
                break
        if len(kept) > len(best[0]):
            q, _ = planner.kin.ik(thumb, kept[0].start(standoff, radius), plan.pose.position,
                                  plan.pose.rotation, probe_q)  # fmt: skip
            best = (kept, q)
    return best


def run_sweep_plan(
    explorer: Explorer,
    plan: SweepPlan,
    face_a: tuple[int, float],
    face_b: tuple[int, float],
    thumb_probes: int = 0,
    rng: np.random.Generator | None = None,
) -> int:
    """Run a planned sweep, with the thumb probing a corner at the end of the edge when asked
    and able (at least 3 reachable probes).

    Returns:
        Number of contacts recorded.
    """
    extra: list[tuple[int, list[Probe]]] = []
    postures = dict(plan.postures)
    if thumb_probes > 0 and rng is not None:
        k = 3 - face_a[0] - face_b[0]
        corners = []
        for sk in (1.0, -1.0):
            signs = [0.0, 0.0, 0.0]
            signs[face_a[0]], signs[face_b[0]], signs[k] = face_a[1], face_b[1], sk
            corners.append((signs[0], signs[1], signs[2]))
        probes, q = thumb_corner_probes(explorer, plan, corners, thumb_probes, rng)
        thumb = explorer.scene.hand.thumb
        if len(probes) >= 3 and q is not None and thumb not in postures:
            extra.append((thumb, probes))
            postures[thumb] = q
    return explorer.sweep(plan.pose, plan.approach_world, plan.stripes, postures, extra)


def run_sweep(
    explorer: Explorer,
    face_a: tuple[int, float],
    face_b: tuple[int, float],
    fingers: Sequence[int] | None = None,
    thumb_probes: int = 0,
    rng: np.random.Generator | None = None,
) -> int:
    """Plan and run one sweep (see :func:`plan_sweep`, :func:`run_sweep_plan`).

    Returns:
        Number of contacts recorded (0 when the sweep could not be planned).
    """
    plan = plan_sweep(explorer, face_a, face_b, fingers)
    if plan is None:
        return 0
    return run_sweep_plan(explorer, plan, face_a, face_b, thumb_probes, rng)


__all__ = ["SweepPlan", "plan_sweep", "run_sweep", "run_sweep_plan", "thumb_corner_probes"]
