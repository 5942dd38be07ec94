"""The MJCF files ship with the package and describe the hand of the issue."""

from __future__ import annotations

import mujoco
import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.sim.models import MODEL_FILES, model_path, models_dir

FINGER_NAMES = ("thumb", "index", "middle", "ring")
JOINT_SUFFIXES = ("abd", "flex1", "flex2")


def test_models_are_found() -> None:
    for name in MODEL_FILES:
        assert model_path(name).is_file()
    assert (models_dir() / "hand.xml").read_text().lstrip().startswith("<!--")


def test_unknown_model_lists_choices() -> None:
    with pytest.raises(InvalidInputError, match="hand.xml"):
        model_path("robot.xml")


def test_hand_has_four_fingers_three_hinges_actuators_and_sensors() -> None:
    # a plain hand: the scene adds the mocap palm, the free joint and the weld
    model = mujoco.MjModel.from_xml_path(str(model_path("hand.xml")))
    assert model.nmocap == 0 and model.neq == 0 and model.njnt == 12
    assert model.nu == len(FINGER_NAMES) * len(JOINT_SUFFIXES)
    for finger in FINGER_NAMES:
        for suffix in JOINT_SUFFIXES:
            j = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, f"{finger}_{suffix}")
            assert model.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE
        g = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, f"{finger}_tip_geom")
        assert model.geom_type[g] == mujoco.mjtGeom.mjGEOM_SPHERE
        s = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SENSOR, f"{finger}_touch")
        assert model.sensor_type[s] == mujoco.mjtSensor.mjSENS_TOUCH
