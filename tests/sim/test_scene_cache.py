"""Compiled scenes are reused: a repeated object is not compiled again, a moved one is a copy
whose object, stand, table and camera stand where a fresh compile puts them."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from hapticsim.errors import InvalidInputError, SimulationError
from hapticsim.geometry import Superquadric, rotvec_to_matrix
from hapticsim.sim.scene import SceneCache, SceneConfig, build_scene

BOX = Superquadric(a=(0.025, 0.03, 0.02), eps=(0.2, 0.3))
CONFIG = SceneConfig(mesh_resolution=24)  # a small hull: the test is about placement


def _forward(model: mujoco.MjModel) -> mujoco.MjData:
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return data


def test_the_same_object_comes_back_from_the_cache() -> None:
    cache = SceneCache(capacity=2)
    first = cache.scene(BOX, CONFIG)
    assert cache.scene(BOX, CONFIG) is first
    assert (cache.hits, cache.misses) == (1, 1)
    # another configuration is another scene
    assert cache.scene(BOX, SceneConfig(mesh_resolution=16)) is not first
    assert len(cache) == 2


def test_a_moved_object_is_placed_as_a_fresh_compile_places_it() -> None:
    cache = SceneCache()
    cache.scene(BOX, CONFIG)
    moved = BOX.transformed(rotvec_to_matrix(np.array([0.2, -0.1, 0.7])), np.array([0.02, 0, 0]))
    reused = cache.scene(moved, CONFIG)
    fresh = build_scene(moved, CONFIG)
    assert cache.misses == 1 and reused.truth == moved
    assert reused.table_top_z == pytest.approx(fresh.table_top_z, abs=1e-12)
    a, b = _forward(reused.model), _forward(fresh.model)
    # exactly the same world placement of every geom (object mesh, stand, table) and camera
    np.testing.assert_allclose(a.geom_xpos, b.geom_xpos, atol=1e-12)
    np.testing.assert_allclose(a.geom_xmat, b.geom_xmat, atol=1e-12)
    np.testing.assert_allclose(a.cam_xpos, b.cam_xpos, atol=1e-12)
    np.testing.assert_allclose(a.cam_xmat, b.cam_xmat, atol=1e-9)
    # the first scene's model was copied, not changed
    first = cache.scene(BOX, CONFIG)
    assert first.model is not reused.model and first.truth == BOX


def test_the_least_recently_used_object_is_dropped() -> None:
    cache = SceneCache(capacity=1)
    first = cache.scene(BOX, CONFIG)
    cache.scene(BOX.replace(a=(0.02, 0.02, 0.02)), CONFIG)
    assert len(cache) == 1 and cache.scene(BOX, CONFIG) is not first


def test_a_moved_object_is_still_checked_against_the_workspace() -> None:
    cache = SceneCache()
    cache.scene(BOX, CONFIG)
    with pytest.raises(SimulationError, match="too far"):
        cache.scene(BOX.replace(center=(1.0, 0.0, 0.0)), CONFIG)


def test_capacity_must_be_positive() -> None:
    with pytest.raises(InvalidInputError, match="capacity"):
        SceneCache(capacity=0)


# ---------------------------------------------------------------------------- planning scenes
def _collisions(scene, poses) -> list[int]:
    from hapticsim.sim.planning import PalmPlanner

    planner = PalmPlanner(scene)
    return [planner.collision_count(p, r, {1: scene.hand.posture(1, "probe")}) for p, r in poses]


@pytest.mark.parametrize("eps", [(0.1, 0.1), (1.0, 1.0)])
def test_a_resized_primitive_plans_as_a_fresh_one(eps) -> None:
    from hapticsim.sim.explorer import planning_config
    from hapticsim.sim.scene import PlanningSceneCache, build_planning_scene

    config = planning_config(SceneConfig())
    cache = PlanningSceneCache()
    first = Superquadric(a=(0.03, 0.03, 0.03), eps=eps)
    cache.scene(first, config)
    rough = Superquadric(a=(0.024, 0.041, 0.033), eps=eps, center=(0.01, -0.02, 0.03),
                         rotation=rotvec_to_matrix(np.array([0.1, -0.2, 0.5])))  # fmt: skip
    reused, fresh = cache.scene(rough, config), build_planning_scene(rough, config)
    assert reused.model is cache.scene(rough, config).model and reused.truth == rough
    assert reused.table_top_z == pytest.approx(fresh.table_top_z, abs=1e-12)
    a, b = _forward(reused.model), _forward(fresh.model)
    np.testing.assert_allclose(a.geom_xpos, b.geom_xpos, atol=1e-12)
    np.testing.assert_allclose(reused.model.geom_size, fresh.model.geom_size, atol=1e-12)
    np.testing.assert_allclose(reused.model.geom_rbound, fresh.model.geom_rbound, rtol=1e-9)
    # the palm planner's collision checks agree pose by pose, near and far
    rng = np.random.default_rng(0)
    poses = [(rough.center + rng.normal(0.0, 0.04, 3) + (0, 0, 0.06),
              rotvec_to_matrix(rng.normal(0.0, 1.0, 3))) for _ in range(40)]  # fmt: skip
    counts = _collisions(reused, poses)
    assert counts == _collisions(fresh, poses) and sum(counts) > 0


def test_other_rough_shapes_are_planned_on_their_mesh() -> None:
    from hapticsim.sim.scene import planning_primitive

    assert planning_primitive(BOX) is None  # eps 0.2, 0.3: neither a box nor an ellipsoid
    assert planning_primitive(Superquadric(a=(0.03,) * 3, eps=(0.1, 0.1), taper=(0.2, 0))) is None
