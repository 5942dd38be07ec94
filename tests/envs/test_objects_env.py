"""The environment on objects of any kind, planning on the vision estimate."""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from hapticsim.data.bodies import get_body
from hapticsim.data.distributions import ObjectDistribution, ObjectSet, coerce_objects
from hapticsim.data.example_meshes import l_block, truncated_pyramid
from hapticsim.data.objects import write_stl
from hapticsim.envs.estimator import FitSchedule
from hapticsim.envs.haptic_explore_v0 import HapticExploreEnv
from hapticsim.errors import InvalidInputError
from hapticsim.geometry import MeshSolid, Superquadric
from hapticsim.perception.vision import BOX_EPS

FAST_FIT = FitSchedule(full_budget=1500, refine_budget=200, full_every=10)


def test_objects_accepts_kinds_single_objects_and_lists(tmp_path) -> None:
    path = write_stl(tmp_path / "l.stl", l_block())
    assert isinstance(coerce_objects("paper"), ObjectDistribution)
    assert isinstance(coerce_objects("random_tapered"), ObjectDistribution)
    single = coerce_objects(str(path))
    assert isinstance(single, ObjectSet) and isinstance(single.sample(np.random.default_rng(0)),
                                                        MeshSolid)  # fmt: skip
    mixed = coerce_objects(["cube", str(path), "random", get_body("ellipsoid")])
    gen = np.random.default_rng(1)
    drawn = [mixed.sample(gen) for _ in range(40)]
    kinds = {type(d).__name__ for d in drawn}
    assert kinds == {"Superquadric", "MeshSolid"}
    randoms = [d for d in drawn if isinstance(d, Superquadric) and d != get_body("cube")
               and d != get_body("ellipsoid")]  # fmt: skip
    assert len({tuple(r.a) for r in randoms}) == len(randoms) > 1  # a new shape each time
    for bad, message in (([], "at least one"), ([3.5], r"objects\[0\]"), (7, "objects")):
        with pytest.raises(InvalidInputError, match=message):
            coerce_objects(bad)
    with pytest.raises(InvalidInputError, match="not found"):
        coerce_objects(["missing.stl"])


def test_random_distribution_draws_as_before() -> None:
    # the random kinds draw a, eps, taper in this order from the episode's generator
    shape = ObjectDistribution("random_tapered").sample(np.random.default_rng(3))
    gen = np.random.default_rng(3)
    a, eps, taper = gen.uniform(0.02, 0.05, 3), gen.uniform(0.1, 1.0, 2), gen.uniform(-0.4, 0.4, 2)
    assert np.array_equal(shape.a, a) and np.array_equal(shape.eps, eps)
    assert np.array_equal(shape.taper, taper)


def test_the_environment_plans_on_the_vision_estimate() -> None:
    env = HapticExploreEnv(backend="analytic", objects="paper", fit=FAST_FIT, position_noise=0.0)
    for seed in range(4):
        env.reset(seed=seed)
        rough = env.rough
        assert np.array_equal(env.origin, rough.center)
        assert np.all(rough.shape.taper == 0.0)
        assert np.allclose(rough.shape.eps, BOX_EPS) or np.allclose(rough.shape.eps, 1.0)
        assert np.linalg.norm(rough.center - env.truth.center) < 0.01  # measured <= 6 mm
        assert rough.vision is not None and rough.vision["points"] > 500


def test_analytic_backend_touches_meshes_on_their_surface() -> None:
    env = HapticExploreEnv(
        backend="analytic", objects=[l_block(), truncated_pyramid()], fit=FAST_FIT, noise=0.0,
        touch_budget=12,
    )  # fmt: skip
    check_env(env, skip_render_check=True)
    for seed in (0, 1):
        env.reset(seed=seed)
        for _ in range(12):
            *_, info = env.step(env.action_space.sample())
        truth = env.truth
        assert isinstance(truth, MeshSolid) and isinstance(info["truth"], MeshSolid)
        contacts = env.contacts
        dist, angle = truth.contact_errors(
            contacts.extra["points_clean"], contacts.extra["normals_clean"]
        )
        # ray casts refined to ~1.4e-6 m; measured max 1.5e-6 m and 0.0 degrees
        assert len(dist) > 20 and np.max(dist) < 1e-5 and np.max(angle) < 1.0
        assert 0.0 <= info["epsilon"] <= 2.0 and 0.0 <= info["iou"] <= 1.0
        assert np.isfinite(info["chamfer"])


def test_mujoco_backend_explores_a_mesh() -> None:
    env = HapticExploreEnv(
        backend="mujoco", objects=[truncated_pyramid()], fit=FAST_FIT, noise=0.0, touch_budget=4
    )
    env.reset(seed=0)
    for k in range(4):
        *_, info = env.step(np.array([np.cos(k), 0.3, 0.5, -0.2 + 0.3 * k, 0.1], np.float32))
    contacts = env.contacts
    assert len(contacts) >= 3
    dist, _ = env.truth.contact_errors(
        contacts.extra["points_clean"], contacts.extra["normals_clean"]
    )
    assert np.max(dist) < 1e-4  # MuJoCo collides with the convex mesh itself: measured ~1e-9 m
    env.close()
