"""Hand descriptions: validation names the bad element; any described hand explores.

The Shadow and Adroit tests use the models that gymnasium-robotics installs (the ``hands``
extra); they skip when it is missing.
"""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.geometry import Superquadric
from hapticsim.metrics.accuracy import contact_accuracy
from hapticsim.perception.vision import RoughObject
from hapticsim.sim.controllers import Probe
from hapticsim.sim.explorer import Explorer
from hapticsim.sim.hand_description import (
    HAND_NAMES,
    HandDescriptionError,
    load_hand,
)
from hapticsim.sim.recorder import Recorder
from hapticsim.sim.scene import SceneConfig, build_scene

SPHERE = Superquadric(a=(0.03, 0.03, 0.03), eps=(1.0, 1.0), center=(0.0, 0.0, 0.05))

#: A description of hapticsim's own hand (models/hand.xml) with two fingers, written the way a
#: user describes a hand of their own: fingertip spheres added, position actuators added.
TWO_FINGERS = """
name = "pinch"
model = "hapticsim:hand.xml"
root = "palm"

[actuation]
mode = "add"
kp = 3.0
kv = 0.05
joint_margin = 0.01

[[fingers]]
name = "thumb"
thumb = true
body = "thumb_distal"
tip_pos = [0.040, 0.0, 0.0]
tip_radius = 0.0085
joints = ["thumb_abd", "thumb_flex1", "thumb_flex2"]
tucked = [0.0, 1.5, 1.7]
probe = [0.0, 0.3, 1.35]
sweep = [0.0, 0.35, 1.7]

[[fingers]]
name = "index"
body = "index_distal"
tip_pos = [0.038, 0.0, 0.0]
tip_radius = 0.0085
joints = ["index_abd", "index_flex1", "index_flex2"]
tucked = [0.0, 1.5, 1.9]
probe = [0.0, 0.3, 1.35]
sweep = [0.0, 0.35, 1.75]
"""


def _write(tmp_path: Path, text: str, name: str = "hand.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def _gymnasium_robotics() -> None:
    pytest.importorskip("gymnasium_robotics", reason="the `hands` extra is not installed")


# ---------------------------------------------------------------------------- validation
def test_the_default_hand_is_hapticsims_own() -> None:
    hand = load_hand()
    assert hand.name == "hapticsim" and hand.finger_names == ("thumb", "index", "middle", "ring")
    assert hand.sweep_fingers == (1, 2, 3) and load_hand("hapticsim") is hand  # cached


def test_unknown_hand_lists_the_shipped_ones() -> None:
    with pytest.raises(HandDescriptionError, match="hapticsim, shadow, adroit"):
        load_hand("allegro")
    assert issubclass(HandDescriptionError, InvalidInputError)


def test_missing_body_is_named(tmp_path) -> None:
    path = _write(tmp_path, TWO_FINGERS.replace('"index_distal"', '"index_tip_link"'))
    with pytest.raises(HandDescriptionError, match="finger 'index': no body 'index_tip_link' in "
                       "hand.xml"):  # fmt: skip
        load_hand(path)


def test_missing_joint_is_named(tmp_path) -> None:
    path = _write(tmp_path, TWO_FINGERS.replace('"index_flex2"]', '"index_flex3"]'))
    with pytest.raises(HandDescriptionError, match="finger 'index': no joint 'index_flex3'"):
        load_hand(path)


def test_a_finger_list_without_a_thumb_is_refused(tmp_path) -> None:
    path = _write(tmp_path, TWO_FINGERS.replace("thumb = true\n", ""))
    with pytest.raises(HandDescriptionError, match="no finger is the thumb.*thumb = true"):
        load_hand(path)


def test_the_thumb_must_come_first(tmp_path) -> None:
    text = TWO_FINGERS.replace("thumb = true\n", "").replace(
        'name = "index"\n', 'name = "index"\nthumb = true\n'
    )
    with pytest.raises(HandDescriptionError, match="thumb must be the first"):
        load_hand(_write(tmp_path, text))


@pytest.mark.parametrize(
    ("old", "new", "match"),
    [
        ("tucked = [0.0, 1.5, 1.9]", "tucked = [0.0, 1.5]", "posture `tucked` must list 3"),
        ("probe = [0.0, 0.3, 1.35]\nsweep = [0.0, 0.35, 1.75]", "probe = [0.0, 0.3, 2.9]\n"
         "sweep = [0.0, 0.35, 1.75]", "probe.*2.9 rad for joint 'index_flex2' is outside"),
        ('root = "palm"', 'root = "wrist"', "no root body 'wrist'"),
        ('joints = ["index_abd"', 'joints = ["thumb_abd"', "joint 'thumb_abd'.*does not move"),
        ('mode = "add"', 'mode = "pneumatic"', "mode.*model.*add"),
        ('mode = "add"', 'mode = "model"', "actuation 'model' needs one actuator per joint"),
        ('tip_radius = 0.0085\njoints = ["index', 'tip_radius = -1.0\njoints = ["index',
         "tip_radius.*>= 0.0001"),
        ('name = "pinch"', 'name = "pinch"\ncolour = "red"', "unknown keys \\['colour'\\]"),
        ('model = "hapticsim:hand.xml"', 'model = "no_such_package_x:hand.xml"',
         "package 'no_such_package_x', which is not installed"),
        ('model = "hapticsim:hand.xml"', 'model = "missing.xml"', "model file .*missing.xml"),
    ],
)  # fmt: skip
def test_bad_descriptions_name_the_problem(tmp_path, old: str, new: str, match: str) -> None:
    assert old in TWO_FINGERS
    with pytest.raises(HandDescriptionError, match=match):
        load_hand(_write(tmp_path, TWO_FINGERS.replace(old, new)))


def test_bad_toml_is_one_clear_error(tmp_path) -> None:
    with pytest.raises(HandDescriptionError, match="not valid TOML"):
        load_hand(_write(tmp_path, "name = [unclosed"))


# ---------------------------------------------------------------------------- composition
def test_a_user_hand_with_added_spheres_and_actuators_probes(tmp_path) -> None:
    hand = load_hand(_write(tmp_path, TWO_FINGERS))
    scene = build_scene(SPHERE, SceneConfig(hand=hand))
    assert [f.name for f in scene.hand.fingers] == ["thumb", "index"]
    assert all(f.tip_radius == 0.0085 for f in scene.hand.fingers)
    explorer = Explorer(scene, RoughObject(SPHERE, has_edges=False), Recorder())
    top = SPHERE.center + np.array([0.0, 0.0, SPHERE.a[2]])
    for finger in (0, 1):
        explorer.probe_patch(finger, [Probe(top, (0.0, 0.0, -1.0))])
    arrays = explorer.recorder.arrays()
    assert arrays["finger"].tolist() == [0, 1]
    acc = contact_accuracy(SPHERE, arrays["points_clean"], arrays["normals_clean"])
    # measured: distance ~1e-5 m, angle ~1 deg (hull facets of the sphere)
    assert acc["distance_max"] < 2e-4 and acc["angle_max_deg"] < 3.0


def test_a_finger_the_hand_does_not_have_is_refused() -> None:
    explorer = Explorer(build_scene(SPHERE), RoughObject(SPHERE, has_edges=False), Recorder())
    with pytest.raises(InvalidInputError, match="finger.*0..3"):
        explorer.probe_patch(4, [Probe(SPHERE.center, (0.0, 0.0, -1.0))])


@pytest.mark.parametrize("name", [n for n in HAND_NAMES if n != "hapticsim"])
def test_shipped_third_party_hands_compose(name: str) -> None:
    _gymnasium_robotics()
    scene = build_scene(SPHERE, SceneConfig(hand=name))
    hand = scene.hand
    assert hand.finger_names == ("th", "ff", "mf", "rf", "lf") and hand.sweep_fingers == (1, 2, 3)
    assert [f.n_joints for f in hand.fingers] == [5, 3, 3, 3, 4]
    # the distal joints follow J1 (tendon coupling), the palm's wrist joint is held
    assert all(len(f.coupled) == 1 for f in hand.fingers[1:]) and scene.model.neq == 2
    for f in hand.fingers:
        assert f.tip_geom_id in hand.tip_finger_of_geom and hand.geom_is_hand[f.tip_geom_id]
        for name_ in ("tucked", "probe", "sweep"):
            q = f.posture(name_)
            assert np.all(q >= f.ctrl_low) and np.all(q <= f.ctrl_high)


@pytest.mark.parametrize("name", [n for n in HAND_NAMES if n != "hapticsim"])
def test_third_party_hands_record_accurate_contacts(name: str) -> None:
    _gymnasium_robotics()
    explorer = Explorer(
        build_scene(SPHERE, SceneConfig(hand=name)), RoughObject(SPHERE, has_edges=False),
        Recorder(),
    )  # fmt: skip
    top = SPHERE.center + np.array([0.0, 0.0, SPHERE.a[2]])
    side = SPHERE.center + np.array([SPHERE.a[0], 0.0, 0.0])
    for finger in range(5):
        explorer.probe_patch(finger, [Probe(top, (0.0, 0.0, -1.0)), Probe(side, (-1.0, 0, 0))])
    arrays = explorer.recorder.arrays()
    # measured: 10 contacts (two per finger), distances ~1e-5 m, angles < 1.5 deg
    assert len(arrays["finger"]) >= 8 and set(arrays["finger"].tolist()) == {0, 1, 2, 3, 4}
    acc = contact_accuracy(SPHERE, arrays["points_clean"], arrays["normals_clean"])
    assert acc["distance_max"] < 2e-4 and acc["angle_max_deg"] < 3.0


def test_cli_unknown_hand_is_one_line_exit_2() -> None:
    import subprocess
    import sys

    proc = subprocess.run(
        [sys.executable, "-m", "hapticsim.cli", "explore", "--hand", "allegro", "--quiet"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert proc.returncode == 2 and proc.stdout == ""
    assert len(proc.stderr.strip().splitlines()) == 1 and "shadow" in proc.stderr


@pytest.mark.slow
@pytest.mark.parametrize(("hand", "body"), [("shadow", "cube"), ("shadow", "cylinder"),
                                            ("adroit", "cube")])  # fmt: skip
def test_third_party_hands_meet_the_issue_targets(hand: str, body: str, tmp_path) -> None:
    """Issue 12: paper strategy, sigma_N = 0: >= 100 contacts, median distance <= 0.5 mm, median
    normal angle <= 2 deg (p95 <= 10), nH epsilon <= 0.10. Measured (seed 0): 150 contacts,
    distances < 1e-5 m, angle medians <= 0.8 deg and p95 <= 1.4 deg, epsilon < 0.001."""
    _gymnasium_robotics()
    from hapticsim.exploration import explore

    summary = explore(body, "paper", noise=0.0, method="nH", seed=0, out_dir=tmp_path,
                      progress=False, hand=hand)  # fmt: skip
    acc = summary["contact_accuracy"]
    assert summary["hand"] == hand and summary["contacts"] >= 100
    assert acc["distance_median"] <= 5e-4
    assert acc["angle_median_deg"] <= 2.0 and acc["angle_p95_deg"] <= 10.0
    assert summary["metrics"]["epsilon"] <= 0.10


def test_same_seed_same_contacts_with_the_shadow_hand() -> None:
    _gymnasium_robotics()
    from hapticsim.sim.session import run_exploration

    box = Superquadric(a=(0.025, 0.03, 0.03), eps=(0.2, 0.2))
    runs = [
        run_exploration(box, "patch", count=20, rng=3, scene_config=SceneConfig(hand="shadow"))
        for _ in range(2)
    ]
    for key, value in runs[0].arrays.items():
        np.testing.assert_array_equal(value, runs[1].arrays[key], err_msg=key)


def test_joint_margins_shrink_the_control_ranges(tmp_path) -> None:
    plain = load_hand(_write(tmp_path, TWO_FINGERS, "plain.toml"))
    kept = load_hand(
        _write(
            tmp_path, TWO_FINGERS.replace("joint_margin = 0.01", "joint_margin = 0.05"), "kept.toml"
        )
    )
    for hand, margin in ((plain, 0.01), (kept, 0.05)):
        finger = build_scene(SPHERE, SceneConfig(hand=hand)).hand.fingers[1]
        # index_flex1 spans -25..100 deg; its added actuator keeps `margin` from both ends
        np.testing.assert_allclose(finger.ctrl_range[1], np.radians([-25, 100]) + [margin, -margin])
