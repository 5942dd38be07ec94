"""The run a viewer reads: hand.npz from explore, load_run's checks, the replay's states."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from hapticsim.errors import InvalidInputError
from hapticsim.viewer.run import MIN_FIT_CONTACTS, load_run, missing_files, replay_states
from tests.test_cli_core import assert_bad_input, run
from tests.viewer.conftest import COUNT


def test_explore_writes_the_hand_at_every_touch(run_dir: Path) -> None:
    with np.load(run_dir / "hand.npz") as h:
        contacts, position, wxyz = h["contacts"], h["position"], h["wxyz"]
        geoms = len(h["rgba"])
        assert geoms >= 10 and len(h["vertex_start"]) == geoms + 1  # palm, links, tips
        assert h["vertex_start"][-1] == len(h["vertices"])
        assert h["face_start"][-1] == len(h["faces"])
        assert list(h["finger_names"]) == ["thumb", "index", "middle", "ring"]
    # state 0 before the first contact, then one state per touch that recorded contacts
    assert contacts[0] == 0 and np.all(np.diff(contacts) > 0) and contacts[-1] == COUNT
    assert position.shape == (len(contacts), geoms, 3) and wxyz.shape == (len(contacts), geoms, 4)
    np.testing.assert_allclose(np.linalg.norm(wxyz, axis=2), 1.0, atol=1e-5)
    # the hand moves between touches (the palm's geom at least)
    assert np.ptp(position[:, 0], axis=0).max() > 0.01


def test_replay_has_one_state_per_touch_and_ends_on_the_runs_estimate(run_dir: Path) -> None:
    data = load_run(run_dir)
    states = replay_states(data, estimate_every=4)
    with np.load(run_dir / "hand.npz") as h:
        assert [s.contacts for s in states] == list(h["contacts"])
    assert all(s.estimate is None for s in states if s.contacts < MIN_FIT_CONTACTS)
    assert states[-1].estimate is data.estimate
    assert states[-1].epsilon == pytest.approx(data.metrics["epsilon"])
    later = [s.epsilon for s in states if s.epsilon is not None]
    assert later and all(0.0 <= e < 2.0 for e in later)
    # refits every 4th state that has 13 contacts: fewer distinct estimates than states
    assert 1 < len({id(s.estimate) for s in states if s.estimate is not None}) < len(states)


def test_a_run_without_hand_npz_replays_one_state_per_contact(run_dir: Path, tmp_path: Path) -> None:  # noqa: E501
    old = tmp_path / "old"
    shutil.copytree(run_dir, old)
    (old / "hand.npz").unlink()
    data = load_run(old)
    assert data.hand is None and data.finger_names[0] == "finger 0"
    states = replay_states(data, estimate_every=200)
    assert [s.contacts for s in states] == list(range(COUNT + 1))
    assert states[0].hand_position is None


def test_missing_files_are_all_named(run_dir: Path, tmp_path: Path) -> None:
    half = tmp_path / "half"
    half.mkdir()
    shutil.copy(run_dir / "fit.json", half / "fit.json")
    assert missing_files(half) == ["contacts.npz", "metrics.json", "truth.json or truth.stl"]
    with pytest.raises(InvalidInputError, match="missing contacts.npz, metrics.json, truth"):
        load_run(half)
    with pytest.raises(InvalidInputError, match="not a run directory"):
        load_run(tmp_path / "nowhere")
    with pytest.raises(InvalidInputError, match="estimate_every"):
        replay_states(load_run(run_dir), estimate_every=0)


def test_view_command_names_missing_files_with_exit_2(capsys, run_dir: Path, tmp_path: Path) -> None:  # noqa: ANN001, E501
    half = tmp_path / "half"
    half.mkdir()
    shutil.copy(run_dir / "contacts.npz", half / "contacts.npz")
    cases = [
        ([str(half)], "missing fit.json, metrics.json, truth.json or truth.stl"),
        ([str(tmp_path / "none")], "not a run directory"),
        ([str(run_dir), "--port", "0"], "--port"),
        ([str(run_dir), "--export", str(tmp_path / "x.txt")], ".html"),
        ([str(run_dir), "--export", str(tmp_path / "no" / "x.html")], "does not exist"),
    ]
    for argv, match in cases:
        assert_bad_input(*run(capsys, "view", *argv), "view", match)
    assert not (tmp_path / "x.txt").exists()


def test_view_without_viser_names_the_extra(capsys, run_dir: Path, monkeypatch) -> None:  # noqa: ANN001
    import sys

    monkeypatch.setitem(sys.modules, "viser", None)  # `import viser` raises ImportError
    code, out, err = run(capsys, "view", str(run_dir), "--export", str(run_dir / "x.html"))
    assert_bad_input(code, out, err, "view", "pip install 'hapticsim[viewer]'")


@pytest.fixture(scope="module")
def free_run(tmp_path_factory) -> Path:  # noqa: ANN001
    from hapticsim.exploration import explore
    from hapticsim.sim.dynamics import ObjectDynamics

    out = tmp_path_factory.mktemp("free") / "run"
    explore("cube", strategy="paper", seed=0, out_dir=out, progress=False, count=30,
            method="nH+track", object_dynamics=ObjectDynamics("resting", mass=0.2),
            force_limit=0.3)  # fmt: skip
    return out


class _Node:
    """A viser scene node as far as the viewer uses one."""

    def __init__(self) -> None:
        self.position, self.wxyz, self.visible, self.text = np.zeros(3), np.eye(4)[0], True, ""

    def remove(self) -> None:
        self.visible = None


class _Scene:
    """viser's SceneApi as far as the viewer uses it: every add_* makes a node."""

    def __init__(self) -> None:
        self.nodes: dict[str, _Node] = {}

    def set_up_direction(self, _: str) -> None:
        pass

    def __getattr__(self, name: str):  # noqa: ANN204
        def add(path: str, *args, **kwargs) -> _Node:  # noqa: ANN002, ANN003
            self.nodes[path] = _Node()
            return self.nodes[path]

        assert name.startswith("add_"), name
        return add


def test_a_free_object_moves_in_the_replay_as_it_moved_in_the_run(free_run: Path) -> None:
    from hapticsim.fitting.track import true_poses
    from hapticsim.geometry.rotations import quaternion_to_matrix
    from hapticsim.viewer.run import object_motion
    from hapticsim.viewer.scene import RunScene

    data = load_run(free_run)
    n = len(data.points)
    assert data.object_pose.shape == (n, 7) and data.tracked.shape == (n, 7)
    rest = data.metrics["object_motion"]["rest_pose"]
    motion = object_motion(data)
    np.testing.assert_allclose(motion, true_poses(data.object_pose, np.array(rest)))
    states = replay_states(data, estimate_every=100)
    assert states[0].object_pose is None  # no contact yet: the object at rest
    np.testing.assert_allclose(states[-1].object_pose, motion[-1])
    # the last state draws the tracking fit where its last tracked pose puts it
    last = data.tracked[-1]
    np.testing.assert_allclose(states[-1].estimate.center,
                               quaternion_to_matrix(last[3:]) @ data.estimate.center + last[:3],
                               atol=1e-9)  # fmt: skip
    scene = _Scene()
    view = RunScene(scene, data, states)
    view.show(len(states) - 1)
    truth = scene.nodes["/truth/part0"]
    np.testing.assert_allclose(truth.position, motion[-1][:3])
    np.testing.assert_allclose(truth.wxyz, motion[-1][3:])
    assert "the object moved" in scene.nodes["/status"].text
    view.show(0)  # back before the first contact: the object at rest again
    np.testing.assert_allclose(truth.position, 0.0)
    np.testing.assert_allclose(truth.wxyz, [1.0, 0.0, 0.0, 0.0])


def test_a_fixed_run_draws_its_truth_where_it_stands(run_dir: Path) -> None:
    from hapticsim.viewer.scene import RunScene

    data = load_run(run_dir)
    assert data.object_pose is None and data.tracked is None
    states = replay_states(data, estimate_every=100)
    assert all(s.object_pose is None for s in states)
    scene = _Scene()
    RunScene(scene, data, states).show(len(states) - 1)
    assert np.all(scene.nodes["/truth/part0"].position == 0)
    assert "moved" not in scene.nodes["/status"].text


def test_bad_object_poses_are_one_line(free_run: Path, tmp_path: Path) -> None:
    bad = tmp_path / "bad"
    shutil.copytree(free_run, bad)
    with np.load(bad / "contacts.npz") as z:
        arrays = dict(z)
    arrays["object_pose"] = arrays["object_pose"][:, :6]
    np.savez(bad / "contacts.npz", **arrays)
    with pytest.raises(InvalidInputError, match=r"object_pose must be \(\d+, 7\)") as exc:
        load_run(bad)
    assert "\n" not in str(exc.value)
