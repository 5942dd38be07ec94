"""A fingertip stroked across a face: MuJoCo's friction holds it until Coulomb's limit and the
skin's taxels slip there (SPEC §11; issue 38's slip-onset bar).

A tip of the built-in hand's radius and skin, on three slide joints, is pressed onto a box by
a set normal force, then loaded tangentially by a force that rises slowly. With the scene's
no-slip passes (tactile scenes have them) the tip starts to slide at 1.010-1.020 mu N and every
taxel of its pad slips at 1.000-1.010 mu N; without them MuJoCo's soft friction lets it creep
from 0.09-0.435 mu N on, which no skin would call stuck (9 runs, mu 0.2/0.3/0.5 x N
0.3/0.5/1 N: docs/tactile/traction).
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from hapticsim.geometry import Superquadric
from hapticsim.perception.tactile import PadLayout, load_skin, taxel_depths, traction_field
from hapticsim.perception.tactile.traction import TAXEL_SLIP, contact_share
from hapticsim.sim.scene import NOSLIP_ITERATIONS, SKIN_IMPRATIO
from hapticsim.sim.tactile import finger_forces, pad_loads, skin_solref

RADIUS = 0.008
TOP = 0.03  # the box's top face [m] (the tip slides off its edge after the onset)
#: the box's top face as a solid the taxel model reads (a large flat superquadric)
FACE = Superquadric([0.3] * 3, [0.1, 0.1], center=[0, 0, TOP - 0.3])
LAYOUT = PadLayout(21, 21, 0.0006, RADIUS, [0, 0, -1], [0, 1, 0], [0, 0, 0])
TIMESTEP = 0.001


def stroke(mu: float, normal: float, noslip: int, rate: float = 0.5):
    """Press, then load along +x at `rate` mu N per second up to 1.3 mu N: every 10th step the
    applied load over mu N, the tip's speed, and the pad's traction field and states."""
    spec = mujoco.MjSpec()
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    spec.option.timestep = TIMESTEP
    spec.option.gravity = [0, 0, 0]
    spec.option.noslip_iterations = noslip
    spec.option.impratio = SKIN_IMPRATIO if noslip else 1.0  # a tactile scene's, or before
    friction = [mu, 0.005, 0.0001]
    spec.worldbody.add_geom(name="object", type=mujoco.mjtGeom.mjGEOM_BOX,
                            size=[0.08, 0.08, TOP], friction=friction)  # fmt: skip
    body = spec.worldbody.add_body(name="tip", pos=[0, 0, TOP + RADIUS])
    for axis in np.eye(3):
        body.add_joint(type=mujoco.mjtJoint.mjJNT_SLIDE, axis=axis)
    geom = body.add_geom(name="tip", type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[RADIUS, 0, 0],
                         mass=0.02, friction=friction)  # fmt: skip
    skin = load_skin("ideal")
    geom.solref = list(skin_solref(skin, RADIUS))
    model = spec.compile()
    data = mujoco.MjData(model)
    tip = model.body("tip").id
    objects, tips = {model.geom("object").id}, {model.geom("tip").id: 0}
    pos, nrm, area = LAYOUT.taxels
    data.xfrc_applied[tip, 2] = -normal
    for _ in range(int(0.5 / TIMESTEP)):
        mujoco.mj_step(model, data)
    rows = []
    for k in range(int(1.3 / rate / TIMESTEP)):
        load = rate * mu * normal * k * TIMESTEP
        data.xfrc_applied[tip, 0] = load
        mujoco.mj_step(model, data)
        if k % 10:
            continue
        n, shear = finger_forces(model, data, objects, tips, 1)
        share = pad_loads(n, shear, np.eye(3)[None], (LAYOUT,), mu)
        depth = taxel_depths(FACE, pos + data.xpos[tip], nrm, RADIUS)
        field, state = traction_field(skin.skin.pressure(depth)[None], share, mu, area)
        rows.append((load / (mu * normal), float(data.qvel[0]), field[0], state[0]))
    return rows


@pytest.mark.parametrize(("mu", "normal"), [(0.2, 0.3), (0.5, 1.0)])
def test_the_tip_slides_and_the_skin_slips_at_coulombs_limit(mu, normal):
    rows = stroke(mu, normal, NOSLIP_ITERATIONS)
    ratio = np.array([r[0] for r in rows])
    speed = np.array([r[1] for r in rows])
    slipping = np.array([np.mean(r[3][r[3] > 0] == TAXEL_SLIP) if (r[3] > 0).any() else 1.0
                         for r in rows])  # fmt: skip
    sliding = ratio[np.argmax(speed > 1e-3)]  # the tip slides at 1 mm/s
    felt = ratio[np.argmax(slipping == 1.0)]  # every taxel of the contact slips
    assert sliding == pytest.approx(1.0, abs=0.1) and felt == pytest.approx(1.0, abs=0.1)
    # partial slip on the way: the slipping share only grows, stick remains below 0.9 mu N
    before = ratio < 0.9
    assert np.all(np.diff(slipping[before]) >= 0) and np.all(slipping[before] < 1)
    assert 0 < slipping[np.argmax(ratio > 0.5)] < 1
    for _, _, field, state in rows:
        q = np.hypot(field[..., 1], field[..., 2])
        assert np.all(q <= mu * field[..., 0] * (1 + 1e-9) + 1e-9)  # Coulomb on every taxel
        world_x = field[..., 1] * LAYOUT.e_u[0] + field[..., 2] * LAYOUT.up[0]
        assert np.all(world_x[state > 0] <= 0)  # the object's friction opposes the push (+x)


def test_without_no_slip_passes_the_tip_creeps_early():
    """Why tactile scenes run MuJoCo's no-slip passes (module docstring)."""
    rows = stroke(0.3, 0.5, 0)
    ratio = np.array([r[0] for r in rows])
    speed = np.array([r[1] for r in rows])
    assert ratio[np.argmax(speed > 1e-3)] < 0.5


def test_the_contact_share_reads_the_load_back():
    rows = stroke(0.3, 0.5, NOSLIP_ITERATIONS)
    for ratio, _, field, state in rows:
        if 0.05 < ratio < 0.95:
            assert contact_share(field, state, 0.3, LAYOUT.taxels[2])[0] == pytest.approx(
                ratio, abs=0.03)  # fmt: skip
