"""Tactile sensing in the simulation: pads on every hand, MuJoCo's sensor against hapticsim's
own taxel model, contacts estimated from the taxels (issue 19).

The figures the thresholds stand on are measured in ``docs/tactile/README.md``
(``scripts/tactile_depth_agreement.py``, ``scripts/tactile_table.py``).
"""

from __future__ import annotations

import textwrap

import mujoco
import numpy as np
import pytest

from hapticsim.data import get_body
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Superquadric
from hapticsim.geometry.rotations import rotvec_to_matrix
from hapticsim.metrics.accuracy import contact_accuracy
from hapticsim.perception.tactile import PadLayout, taxel_depths
from hapticsim.sim.hand_description import HandDescriptionError, load_hand
from hapticsim.sim.scene import SceneConfig, build_scene
from hapticsim.sim.session import run_exploration
from hapticsim.sim.tactile import add_mujoco_pads, pad_layouts
from tests.sim.test_hands import SPHERE, TWO_FINGERS, _gymnasium_robotics

RADIUS = 0.008


def _free_tip_model(object_geom: dict, layout: PadLayout) -> mujoco.MjModel:
    spec = mujoco.MjSpec()
    spec.worldbody.add_geom(name="object", **object_geom)
    body = spec.worldbody.add_body(name="tip")
    body.add_freejoint()
    body.add_geom(name="tip", type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[RADIUS, 0, 0], mass=0.02)
    add_mujoco_pads(spec, [("tip", np.zeros(3), np.array([1.0, 0, 0, 0]), layout)])
    return spec.compile()


@pytest.mark.parametrize(
    ("geom", "solid", "normal"),
    [
        (
            {"type": mujoco.mjtGeom.mjGEOM_SPHERE, "size": [0.02, 0, 0]},
            Superquadric([0.02] * 3, [1.0, 1.0]),
            None,
        ),
        (
            {"type": mujoco.mjtGeom.mjGEOM_ELLIPSOID, "size": [0.03, 0.02, 0.015]},
            Superquadric([0.03, 0.02, 0.015], [1.0, 1.0]),
            None,
        ),
        (
            {"type": mujoco.mjtGeom.mjGEOM_BOX, "size": [0.03, 0.03, 0.03]},
            Superquadric([0.3] * 3, [0.1, 0.1], center=[0, 0, -0.27]),
            np.array([0, 0, 1.0]),
        ),
    ],
    ids=["sphere", "ellipsoid", "box-face"],
)
def test_mujoco_tactile_agrees_with_the_own_model_on_primitives(geom, solid, normal) -> None:  # noqa: ANN001
    """MuJoCo's <tactile> reads a primitive's analytic distance; the own model the same
    solid's (the box's top face: a large flat superquadric whose face z = 0.03 is the box's).
    Measured (scripts/tactile_depth_agreement.py, 120 presses each): away from edges within
    6.1 % of the penetration; here 20 presses each, the bound 8 %."""
    layout = PadLayout(21, 21, 0.0015, RADIUS, [0, 0, -1], [0, 1, 0], [0, 0, 0])
    model = _free_tip_model(geom, layout)
    data = mujoco.MjData(model)
    rng = np.random.default_rng(0)
    pos, nrm, _ = layout.taxels
    checked = 0
    for _ in range(20):
        if normal is None:
            n = rng.normal(size=3)
            n /= np.linalg.norm(n)
            surface = n / np.sqrt(np.sum((n / solid.a) ** 2))  # the ellipsoid's ray point
            n = solid.normals(surface[None])[0]
        else:
            surface = np.array([*rng.uniform(-0.01, 0.01, 2), 0.03])
            n = normal
        delta = rng.uniform(2e-4, 1e-3)
        z = -n
        x = np.cross([0.3, 0.5, 0.8], z)
        x /= np.linalg.norm(x)
        rot = rotvec_to_matrix(rng.normal(size=3) * 0.4) @ np.column_stack(
            [x, np.cross(z, x), z]) @ np.diag([1, -1, -1])  # fmt: skip
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, rot.ravel())
        centre = surface + (RADIUS - delta) * n
        data.qpos[:3], data.qpos[3:7] = centre, quat
        mujoco.mj_forward(model, data)
        penetration = -float(data.contact.dist.min())
        mj = np.asarray(data.sensordata[: layout.count]).reshape(layout.shape)
        own = taxel_depths(solid, pos @ rot.T + centre, nrm @ rot.T, RADIUS)
        lit = (mj > 0) | (own > 0)
        assert lit.any()
        assert np.abs(own - mj)[lit].max() <= 0.08 * penetration
        checked += 1
    assert checked == 20


def test_every_shipped_hand_description_has_pads_on_its_fingertips() -> None:
    scene = build_scene(SPHERE, SceneConfig(sensing="tactile"))
    pads = pad_layouts(scene.model, scene.hand, scene.config.skin)
    assert len(pads) == 4
    for kind, ident, layout, reach in pads:
        assert kind == "geom" and layout.curved and layout.radius == pytest.approx(0.008)
        assert layout.shape == (31, 31) and layout.pitch == 0.001 and reach == layout.radius
        assert ident in scene.hand.tip_finger_of_geom


@pytest.fixture(scope="module")
def cube_run():  # noqa: ANN201
    return run_exploration(get_body("cube"), "paper", 150, 0,
                           scene_config=SceneConfig(sensing="tactile"))  # fmt: skip


def test_tactile_contacts_are_estimated_from_the_taxels(cube_run) -> None:  # noqa: ANN001
    """Measured (cube, ideal skin, seed 0): distance to the surface median 0.005 mm, p95
    0.056 mm; normal angle median 0.22 deg, p95 3.3 deg; every touch felt."""
    a = cube_run.arrays
    acc = contact_accuracy(cube_run.truth, a["points_clean"], a["normals_clean"])
    assert acc["distance_median"] < 3e-5 and acc["distance_p95"] < 3e-4
    assert acc["angle_median_deg"] < 1.0 and acc["angle_p95_deg"] < 8.0
    assert cube_run.explorer.recorder.unfelt <= 10
    # MuJoCo's exact contacts beside them, a different thing
    assert not np.array_equal(a["points_clean"], a["points_exact"])
    assert np.max(np.linalg.norm(a["points_clean"] - a["points_exact"], axis=1)) < 0.003
    assert np.all(a["sigma"] > 0) and np.all(a["taxels"] >= 1) and np.all(a["area"] > 0)


def test_every_pad_is_read_at_every_recorded_contact(cube_run) -> None:  # noqa: ANN001
    t = cube_run.explorer.recorder.tactile_arrays()
    n = cube_run.count
    assert t["images"].shape == (n, 4, 31, 31) and t["depth"].shape == (n, 4, 31, 31)
    assert t["slip"].shape == (n, 4, 31, 31, 2) and t["pad_rotation"].shape == (n, 4, 3, 3)
    finger = cube_run.arrays["finger"]
    assert np.all(t["images"][np.arange(n), finger].reshape(n, -1).max(axis=1) > 0)
    np.testing.assert_allclose(t["time"], cube_run.arrays["time"])


def test_the_skin_force_is_what_the_controllers_press_against(cube_run) -> None:  # noqa: ANN001
    """The probe records at 0.5 N of the skin's force (pi E R delta^2 / h of MuJoCo's
    penetration) or more, once the press has settled."""
    a = cube_run.arrays
    probes = cube_run.explorer.recorder.pattern_kinds
    patch = np.array([probes[p] == "patch" for p in a["pattern"]])
    assert np.median(a["force"][patch]) > 0.4
    assert np.all(np.isfinite(a["force_exact"])) and np.all(a["force_exact"] >= 0)


def test_mujocos_force_is_the_skins_at_settled_touches(cube_run) -> None:  # noqa: ANN001
    """One contact law (issue 38 item 1): the force MuJoCo applies at a recorded touch is the
    skin's integrated pressure. Measured (paper bodies, seeds 0-2, hapticsim's hand,
    docs/tactile/force): settled probes |skin / MuJoCo - 1| median 0.004, p95 0.022; every touch
    with the strokes' sliding ones median 0.004, p95 0.036; here one cube run, bounds with a
    margin of 5 to 12."""
    a = cube_run.arrays
    error = np.abs(a["force"] / np.maximum(a["force_exact"], 1e-9) - 1.0)
    probes = cube_run.explorer.recorder.pattern_kinds
    patch = np.array([probes[p] == "patch" for p in a["pattern"]])
    assert np.median(error[patch]) < 0.05 and np.percentile(error[patch], 95) < 0.2
    assert np.median(error) < 0.05 and np.percentile(error, 95) < 0.3


def test_a_reset_gives_the_fingertips_their_resting_softness() -> None:
    """The skin's law changes the fingertips' contact time constant while they touch; a new
    run on the same (cached) scene starts from the skin's resting softness."""
    from hapticsim.sim.simulator import Simulator
    from hapticsim.sim.tactile import skin_solref

    scene = build_scene(get_body("cube"), SceneConfig(sensing="tactile"))
    sim = Simulator(scene)
    tips = [f.tip_geom_id for f in scene.hand.fingers]
    scene.model.geom_solref[tips, 0] = 0.05  # as a touching run leaves them
    sim.reset(np.array([0.0, 0.0, 0.4]), np.eye(3))
    rest = skin_solref(scene.config.skin, scene.hand.fingers[0].tip_radius)
    np.testing.assert_allclose(scene.model.geom_solref[tips], [rest] * len(tips))


def test_mujocos_taxel_model_reads_the_scene() -> None:
    config = SceneConfig(sensing="tactile", taxel_model="mujoco")
    run = run_exploration(get_body("ellipsoid"), "paper", 20, 0, scene_config=config)
    a = run.arrays
    acc = contact_accuracy(run.truth, a["points_clean"], a["normals_clean"])
    assert run.count == 20 and acc["distance_median"] < 1e-4
    assert run.explorer.sim.model.nsensor == 4 + 4  # the hand's touch sensors and the pads


def test_a_skin_preset_with_its_own_pitch_regrids_the_pads() -> None:
    scene = build_scene(SPHERE, SceneConfig(sensing="tactile", skin="capacitive"))
    pads = pad_layouts(scene.model, scene.hand, scene.config.skin)
    assert {p[2].shape for p in pads} == {(9, 9)} and pads[0][2].pitch == 0.004


def test_a_user_hand_without_pad_tables_gets_default_pads(tmp_path) -> None:  # noqa: ANN001
    path = tmp_path / "pinch.toml"
    path.write_text(textwrap.dedent(TWO_FINGERS))
    run = run_exploration(SPHERE, "patch", 20, 0,
                          scene_config=SceneConfig(hand=path, sensing="tactile"))  # fmt: skip
    assert run.count == 20
    acc = contact_accuracy(run.truth, run.arrays["points_clean"], run.arrays["normals_clean"])
    assert acc["distance_median"] < 1e-4


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ('pad = { on = "nowhere" }', "pad: no geom or site 'nowhere'"),
        ('pad = { on = "index_link1" }', "not on the fingertip body"),
        ('pad = { colour = "red" }', r"unknown keys \['colour'\]"),
        ("pad = { normal = [0, 0, 0] }", "non-zero vector"),
        ("pad = { flat = true, radius = 0.01 }", "a flat pad has no `radius`"),
    ],
)
def test_bad_pads_in_a_hand_description_name_the_problem(tmp_path, change, message) -> None:  # noqa: ANN001
    text = textwrap.dedent(TWO_FINGERS).replace(
        "sweep = [0.0, 0.35, 1.75]", f"sweep = [0.0, 0.35, 1.75]\n{change}"
    )
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(HandDescriptionError, match=message):
        load_hand(path)


def test_a_grid_of_zero_is_refused(tmp_path) -> None:  # noqa: ANN001
    path = tmp_path / "grid.toml"
    path.write_text(textwrap.dedent(TWO_FINGERS) + "\n[pad]\nrows = 0\n")
    with pytest.raises(HandDescriptionError, match=r"\[pad\]: `rows` must be a whole number"):
        load_hand(path)


def test_a_pad_that_does_not_fit_its_fingertip_is_refused(tmp_path) -> None:  # noqa: ANN001
    path = tmp_path / "big.toml"
    path.write_text(textwrap.dedent(TWO_FINGERS) + "\n[pad]\nrows = 61\ncols = 61\npitch = 0.002\n")
    with pytest.raises(InvalidInputError, match="deg from its centre"):
        build_scene(SPHERE, SceneConfig(hand=path, sensing="tactile"))


def test_exact_sensing_keeps_its_hand_and_its_contacts() -> None:
    """Tactile sensing changes the touching geoms only in its own scenes."""
    exact = build_scene(SPHERE, SceneConfig())
    tactile = build_scene(SPHERE, SceneConfig(sensing="tactile"))
    g = exact.hand.fingers[1].tip_geom_id
    assert exact.model.geom_margin[g] == pytest.approx(0.001)
    assert tactile.model.geom_margin[g] == 0.0
    run = run_exploration(SPHERE, "patch", 20, 0)
    assert "points_exact" not in run.arrays and not run.explorer.recorder.tactile_arrays()


@pytest.mark.parametrize("hand", ["shadow", "adroit"])
def test_the_gymnasium_robotics_hands_sense_through_their_pads(hand: str) -> None:
    _gymnasium_robotics()
    run = run_exploration(SPHERE, "patch", 30, 0,
                          scene_config=SceneConfig(hand=hand, sensing="tactile"))  # fmt: skip
    acc = contact_accuracy(run.truth, run.arrays["points_clean"], run.arrays["normals_clean"])
    assert run.count == 30 and acc["distance_median"] < 1e-4 and acc["angle_p95_deg"] < 5.0
    images = run.explorer.recorder.tactile_arrays()["images"]
    assert images.shape[1:] == (5, 33, 33)
