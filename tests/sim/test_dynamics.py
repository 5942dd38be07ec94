"""Objects that move (SPEC §12): the free object's scene, its settling, its pose, the stop
reasons and the force limit. Properties only: where a finger's push sends a free object is a
chaotic trajectory (scripts/free_objects.py measures it over families)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import mujoco
import numpy as np
import pytest

from hapticsim.data import get_body
from hapticsim.data.objects import random_composite
from hapticsim.errors import InvalidInputError, SimulationError
from hapticsim.geometry.rotations import quaternion_to_matrix
from hapticsim.sim.dynamics import (
    CRADLE_PREFIX,
    MotionWatch,
    ObjectDynamics,
    object_pose,
    pose_change,
    relative_motion,
    tilt_deg,
)
from hapticsim.sim.explorer import ExplorerConfig, force_limited
from hapticsim.sim.scene import SceneConfig, build_scene
from hapticsim.sim.session import run_exploration


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"kind": "wobbly"}, "object_dynamics"),
        ({"kind": "resting", "mass": 0.0}, "object mass must be positive"),
        ({"kind": "resting", "mass": -1.0}, "object mass must be positive"),
        ({"kind": "resting", "density": float("nan")}, "object density"),
        ({"kind": "held", "clamp_stiffness": 0}, "clamp stiffness must be positive"),
        ({"kind": "held", "mass": "heavy"}, "must be a number"),
    ],
)
def test_bad_dynamics_are_one_clear_line(kwargs: dict, match: str) -> None:
    with pytest.raises(InvalidInputError, match=match) as exc:
        ObjectDynamics(**kwargs)
    assert "\n" not in str(exc.value)


@pytest.mark.parametrize("limit", [0.0, -1.0, float("nan"), 11.0, True])
def test_a_bad_force_limit_is_refused(limit: float) -> None:
    with pytest.raises(InvalidInputError, match="force_limit"):
        SceneConfig(force_limit=limit)


def test_a_fixed_scene_has_no_joint_no_cradle_and_the_default_solver() -> None:
    scene = build_scene(get_body("cube"))
    model = scene.model
    assert model.body_jntnum[scene.object_body_id] == 0
    assert model.opt.noslip_iterations == 0
    assert not model.opt.enableflags & mujoco.mjtEnableBit.mjENBL_SLEEP
    assert not any(model.geom(g).name.startswith(CRADLE_PREFIX) for g in range(model.ngeom))
    assert scene.placed is None and not scene.free


def _settled_motion(scene, seconds: float = 1.0) -> tuple[float, float]:
    """How far the object moves in `seconds` from its reference pose, the hand far above."""
    model = scene.model
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    start = object_pose(model, data, scene.object_body_id)
    far = start[:3] + [0.0, 0.0, 0.6]
    data.qpos[scene.hand.palm_qpos_adr : scene.hand.palm_qpos_adr + 3] = far
    data.mocap_pos[scene.hand.mocap_id] = far
    mujoco.mj_step(model, data, nstep=int(seconds / model.opt.timestep))
    return pose_change(object_pose(model, data, scene.object_body_id), start)


@pytest.mark.parametrize("name", ["cube", "ellipsoid"])
def test_a_resting_object_has_its_mass_and_stays_at_rest_in_its_cradle(name: str) -> None:
    truth = get_body(name)  # the ellipsoid stands on its tip: the cradle holds it
    scene = build_scene(truth, SceneConfig(object_dynamics="resting"))
    mass = scene.model.body_mass[scene.object_body_id]
    assert mass == pytest.approx(500.0 * truth.volume, rel=1e-9)
    moved, turned = _settled_motion(scene)
    assert moved < 1e-3 and turned < 1.0
    # the truth is where it settled, close to where it was placed
    assert scene.placed is truth
    assert np.linalg.norm(scene.truth.center - truth.center) < 2e-3


def test_a_resting_object_sleeps_untouched_and_a_push_wakes_it() -> None:
    scene = build_scene(get_body("cube"), SceneConfig(object_dynamics="resting"))
    model, tree = scene.model, scene.model.body_treeid[scene.object_body_id]
    data = mujoco.MjData(model)
    hand = slice(scene.hand.palm_qpos_adr, scene.hand.palm_qpos_adr + 3)
    above = scene.truth.center + [0.0, 0.0, 0.6]
    data.qpos[hand] = data.mocap_pos[scene.hand.mocap_id] = above
    mujoco.mj_step(model, data, nstep=200)
    assert data.tree_asleep[tree] >= 0  # asleep: its pins are out of the collision
    assert not any(scene.object_body_id in (model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2])
                   for c in data.contact[: data.ncon])  # fmt: skip
    start = object_pose(model, data, scene.object_body_id)
    data.xfrc_applied[scene.object_body_id, :3] = [0.0, 0.0, -5.0]  # a press wakes it
    mujoco.mj_step(model, data)
    assert data.tree_asleep[tree] < 0
    data.xfrc_applied[:] = 0.0
    mujoco.mj_step(model, data, nstep=200)
    assert pose_change(object_pose(model, data, scene.object_body_id), start)[0] < 1e-3


def test_a_held_object_hangs_where_it_was_placed() -> None:
    truth = get_body("cylinder")
    scene = build_scene(truth, SceneConfig(object_dynamics=ObjectDynamics("held", mass=0.5)))
    assert scene.model.body_mass[scene.object_body_id] == pytest.approx(0.5)
    moved, turned = _settled_motion(scene)
    assert moved < 1e-4 and turned < 0.1  # the springs carry its weight


def test_an_object_that_topples_before_the_first_touch_is_said_so() -> None:
    truth = random_composite(1)  # its centre of mass overhangs its foot
    with pytest.raises(SimulationError, match="topples before the first touch") as exc:
        build_scene(truth, SceneConfig(object_dynamics="resting"))
    assert "\n" not in str(exc.value)


def test_motion_measures() -> None:
    initial = np.array([0.1, 0.0, 0.2, 1.0, 0.0, 0.0, 0.0])
    half = math.radians(15.0)
    yaw = np.array([0.1, 0.01, 0.2, math.cos(half), 0.0, 0.0, math.sin(half)])  # 30 deg about z
    assert tilt_deg(yaw, initial) == pytest.approx(0.0, abs=1e-5)
    assert pose_change(yaw, initial) == pytest.approx((0.01, 30.0))
    rotation, translation = relative_motion(yaw, initial)
    assert np.allclose(rotation @ initial[:3] + translation, yaw[:3])
    watch = MotionWatch(initial, 0)

    def reason(pose: np.ndarray) -> str | None:  # MjData's body 0 at `pose`
        data = SimpleNamespace(xmat=quaternion_to_matrix(pose[3:]).reshape(1, 9),
                               xpos=pose[None, :3])  # fmt: skip
        return watch.reason(data)

    assert reason(yaw) is None
    tipped = np.array([0.1, 0.0, 0.2, math.cos(0.2), math.sin(0.2), 0.0, 0.0])  # 23 deg
    assert "tipped over" in reason(tipped)
    gone = initial + [0.06, 0, 0, 0, 0, 0, 0]
    assert "left its place" in reason(gone)


def test_a_force_limit_lowers_what_the_controllers_press_with() -> None:
    config = ExplorerConfig()
    assert force_limited(config, None) is config
    gentle = force_limited(config, 0.3)
    assert gentle.probe.force_threshold == pytest.approx(0.18)
    assert gentle.follow.force == pytest.approx(0.15)
    assert gentle.follow.band == (pytest.approx(0.075), 0.3)
    assert gentle.probe.speed < config.probe.speed


def test_a_resting_exploration_records_the_object_pose_at_every_contact() -> None:
    dynamics = ObjectDynamics("resting", mass=0.4)
    scene = SceneConfig(object_dynamics=dynamics, force_limit=0.3)
    run = run_exploration(get_body("cube"), "paper", 30, 0, scene_config=scene)
    poses = run.arrays["object_pose"]
    assert poses.shape == (run.count, 7)
    assert np.allclose(np.linalg.norm(poses[:, 3:], axis=1), 1.0)
    initial = run.explorer.sim.initial_object_pose
    assert np.allclose(initial[:3], run.truth.pose[1], atol=1e-6)  # the truth at rest
    # the final truth is the rest truth moved as the object moved
    rotation, translation = relative_motion(run.explorer.sim.object_pose(), initial)
    assert np.allclose(run.truth_final.center, rotation @ run.truth.center + translation)
    if run.stop_reason is not None:  # a run may end early, but only for a stated reason
        assert run.stop_reason.startswith(("the object", "the simulated-time"))


def test_a_fixed_exploration_records_no_pose() -> None:
    run = run_exploration(get_body("cube"), "paper", 20, 0)
    assert "object_pose" not in run.arrays and run.truth_final is None


# ----------------------------------------------------------------------------- command line
def _cli(capsys, *argv: str) -> tuple[int, str, str]:
    from hapticsim.cli import main

    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (["--object-dynamics", "resting", "--object-mass", "0"], "object mass must be positive"),
        (["--object-dynamics", "resting", "--object-density", "-1"], "object density"),
        (["--object-dynamics", "held", "--clamp-stiffness", "0"], "clamp stiffness"),
        (["--object-dynamics", "wobbly"], "invalid choice: 'wobbly'"),
        (["--object-mass", "0.2"], "is for a free object"),
        (["--object-dynamics", "resting", "--clamp-stiffness", "9"], "for --object-dynamics held"),
        (["--force-limit", "0"], "force_limit"),
        (["--object", "random_composite", "--seed", "7", "--object-dynamics", "resting"],
         "topples before the first touch"),
    ],
)
def test_explore_refuses_bad_dynamics_in_one_line(capsys, tmp_path, args: list, match: str) -> None:
    argv = ["explore", *(["--object", "cube"] if "--object" not in args else []), *args,
            "--quiet", "--out", str(tmp_path / "run")]  # fmt: skip
    try:
        code, out, err = _cli(capsys, *argv)
    except SystemExit as exc:  # argparse's own errors
        code, (out, err) = exc.code, capsys.readouterr()
    assert code == 2 and out == ""
    lines = err.splitlines()
    assert len(lines) == 1 and match in lines[0] and "Traceback" not in err
    assert not (tmp_path / "run").exists()  # nothing half-written


def test_explore_a_resting_object_with_tracking_writes_the_spec_files(capsys, tmp_path) -> None:
    import json

    out = tmp_path / "run"
    code, stdout, _ = _cli(capsys, "explore", "--object", "cube", "--object-dynamics", "resting",
                           "--object-mass", "0.4", "--force-limit", "0.3", "--method", "nH+track",
                           "--count", "40", "--quiet", "--out", str(out))  # fmt: skip
    assert code == 0
    summary = json.loads(stdout)
    assert summary["object_motion"]["kind"] == "resting"
    contacts = np.load(out / "contacts.npz")
    n = len(contacts["points"])
    assert contacts["object_pose"].shape == (n, 7)
    fit_json = json.loads((out / "fit.json").read_text())
    assert np.asarray(fit_json["poses"]).shape == (n, 7) and "solid" in fit_json
    metrics = json.loads((out / "metrics.json").read_text())
    assert set(metrics["pose_drift"]) == {"position_m", "angle_deg", "add_m", "adds_m"}
    assert metrics["object_motion"]["mass_kg"] == pytest.approx(0.4)
    assert metrics["force_limit"] == 0.3
    assert (out / "truth.json").exists() and (out / "truth_final.json").exists()


# ----------------------------------------------------------------------------- environments
def test_the_analytic_backend_refuses_a_free_object() -> None:
    from hapticsim.envs.haptic_explore_v0 import HapticExploreConfig

    for extra in ({"object_dynamics": "resting"}, {"force_limit": 0.3},
                  {"displacement_penalty": 1.0}):  # fmt: skip
        with pytest.raises(InvalidInputError, match="MuJoCo backend"):
            HapticExploreConfig(backend="analytic", **extra)
    with pytest.raises(InvalidInputError, match="displacement_penalty"):
        HapticExploreConfig(displacement_penalty=-1.0)


def test_a_touch_says_how_far_it_moved_the_object_and_the_penalty_takes_it_off() -> None:
    from hapticsim.envs.haptic_explore_v0 import HapticExploreEnv

    def episode(penalty: float) -> list[tuple[float, float]]:
        env = HapticExploreEnv(objects="paper", reward="eof", touch_budget=4,
                               object_dynamics=ObjectDynamics("resting", mass=0.2),
                               displacement_penalty=penalty)  # fmt: skip
        env.reset(seed=3)
        env.action_space.seed(3)
        out = []
        for _ in range(4):
            _, reward, _, _, info = env.step(env.action_space.sample())
            assert info["object_moved"] >= 0.0 and info["object_turned"] >= 0.0
            out.append((reward, info["object_moved"]))
        return out

    plain, penalised = episode(0.0), episode(100.0)
    # the same episode (one machine, one seed): the penalty is all that differs
    for (r0, moved0), (r1, moved1) in zip(plain, penalised, strict=True):
        assert moved0 == moved1
        assert r1 == pytest.approx(r0 - 100.0 * moved0, abs=1e-12)
