"""Fingertip contacts read from MuJoCo's contact data (SPEC §7).

For a contact between a fingertip sphere and the object:

- ``contact.frame[:3]`` points from ``contact.geom[0]`` to ``contact.geom[1]``; geoms are ordered
  by type, so the sphere is usually ``geom[0]`` and the normal then points *into* the object. It is
  flipped so that ``normal_world`` always points out of the object.
- ``contact.pos`` is the midpoint between the two surfaces and ``contact.dist`` their signed
  distance (< 0: penetration). With ``n`` outward, the fingertip's surface point is the object's
  surface point plus ``dist * n``, so the object's surface point is ``pos - 0.5 * dist * n``.
- The normal force is the first component of ``mj_contactForce`` (contact frame) [N]. A hand
  with a tactile skin (:mod:`hapticsim.sim.tactile`) feels instead the skin's elastic force of
  the fingertip's penetration ``delta = -dist``, its sphere's force on a flat face
  (:meth:`~hapticsim.perception.tactile.SkinModel.sphere_force`: ``pi E R_f delta^2 / h`` under
  the Winkler law): what its controllers press
  against; MuJoCo's force, which follows the skin's integrated pressure
  (:meth:`~hapticsim.sim.tactile.TactileHand.follow_skin`), is kept as ``force_exact``.
"""

from __future__ import annotations

from collections.abc import Callable, Collection
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from hapticsim.sim.hand import Hand

Array = NDArray[np.float64]


@dataclass(frozen=True)
class FingertipContact:
    """One fingertip touching the object.

    Attributes:
        finger: finger index (0 thumb, 1 index, 2 middle, 3 ring).
        point_world: (3,) float, contact point on the object's surface [m, world].
        normal_world: (3,) float, unit normal pointing out of the object [world].
        force: normal force [N] (>= 0).
        dist: signed distance between the surfaces [m] (< 0: penetration).
        time: simulation time [s].
        force_exact: MuJoCo's normal force [N] when `force` is a skin's (else equal to it).
    """

    finger: int
    point_world: Array
    normal_world: Array
    force: float
    dist: float
    time: float
    force_exact: float | None = None


@dataclass(frozen=True)
class ContactState:
    """All hand/object contacts at one instant.

    Attributes:
        tips: per finger (index order), the strongest fingertip/object contact or None.
        other_object: number of contacts between the object and a non-tip part of the hand.
        table: number of contacts between the hand and the table or the stand (contacts
            between parts of the hand, which some models pair explicitly, are not counted).
    """

    tips: tuple[FingertipContact | None, ...]
    other_object: int
    table: int


def fingertip_contacts(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    hand: Hand,
    object_geom_id: int | Collection[int],
    skin_force: Callable[[int, float], float] | None = None,
) -> ContactState:
    """Collect the fingertip/object contacts of the current state (call after a step).

    Contacts within the margin but without force (``dist`` > 0) are reported with force 0.
    When a fingertip has several contacts the one with the largest normal force is kept.

    Args:
        model, data: MuJoCo model and data.
        hand: hand ids of `model`.
        object_geom_id: id of the object geom, or the ids of all its geoms (the convex parts
            of a non-convex mesh).
        skin_force: the skin's force [N] of a finger at a penetration [m]: each fingertip
            then feels ``skin_force(finger, max(-dist, 0))`` (module docstring); None:
            MuJoCo's force.

    Returns:
        The contact state.
    """
    n_fingers = len(hand.fingers)
    best: list[FingertipContact | None] = [None] * n_fingers
    ncon = int(data.ncon)
    if ncon == 0:
        return ContactState(tuple(best), 0, 0)
    # Called every control tick with a handful of contacts: a loop over plain ints beats numpy's
    # per-call overhead here (each attribute of ``data.contact`` is a fresh (ncon, k) copy).
    con = data.contact
    tip_finger, hand_geoms = hand.tip_finger_of_geom, hand.hand_geom_set
    other = table = 0
    tips: list[tuple[int, int, bool]] = []
    objects = {object_geom_id} if isinstance(object_geom_id, int) else set(object_geom_id)
    for i, (g0, g1) in enumerate(con.geom.tolist()):
        if g0 in objects or g1 in objects:
            first = g0 in objects
            finger = tip_finger.get(g1 if first else g0, -1)
            if finger < 0:
                other += 1
            else:
                tips.append((i, finger, first))
        elif (g0 in hand_geoms) != (g1 in hand_geoms):  # not the hand's own contact pairs
            table += 1
    if not tips:
        return ContactState(tuple(best), other, table)
    force6 = np.zeros(6)
    now = float(data.time)
    frames, positions, dists, efc = con.frame, con.pos, con.dist, con.efc_address
    for i, finger, first in tips:
        # the frame points from geom[0] to geom[1]: outward when the object is geom[0]
        normal = frames[i, :3] if first else -frames[i, :3]
        dist = float(dists[i])
        point = positions[i] - 0.5 * dist * normal
        force = 0.0
        if efc[i] >= 0:
            mujoco.mj_contactForce(model, data, i, force6)
            force = max(float(force6[0]), 0.0)
        exact = force
        if skin_force is not None:
            force = skin_force(finger, max(-dist, 0.0))
        current = best[finger]
        if current is None or force > current.force:
            best[finger] = FingertipContact(
                finger=finger, point_world=point, normal_world=normal, force=force, dist=dist,
                time=now, force_exact=None if skin_force is None else exact,
            )  # fmt: skip
    return ContactState(tuple(best), other, table)


__all__ = ["ContactState", "FingertipContact", "fingertip_contacts"]
