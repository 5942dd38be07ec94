"""Exploration videos: frames at the configured rate, contacts drawn as they are recorded."""

from __future__ import annotations

import io

import numpy as np
import pytest
from PIL import Image

from hapticsim.errors import InvalidInputError
from hapticsim.exploration import explore
from hapticsim.geometry import Superquadric
from hapticsim.sim.session import run_exploration
from hapticsim.sim.video import ExplorationVideo, VideoConfig

BOX = Superquadric(a=(0.025, 0.03, 0.03), eps=(0.2, 0.2))


def _red_pixels(frame: np.ndarray) -> int:
    """Pixels of the contact markers' red (the lit orange fingertips have r < 3 g)."""
    r, g = frame[..., 0].astype(int), frame[..., 1].astype(int)
    return int(np.sum((r > 120) & (r > 3.5 * g)))


@pytest.fixture(scope="module")
def gif() -> tuple[bytes, int, float]:
    video = ExplorationVideo(VideoConfig(format="gif", fps=10, speed=1.0))  # 320 x 240
    run = run_exploration(BOX, "patch", count=20, rng=0, video=video)
    return video.finish(), video.frames, run.sim_time


def test_one_frame_per_tenth_of_a_simulated_second(gif) -> None:
    data, frames, sim_time = gif
    assert data[:6] == b"GIF89a"
    # a frame every 0.1 s of simulated time (the hand's jumps between patches add a few)
    assert sim_time * 10 <= frames <= sim_time * 10 + 40


def test_recorded_contacts_appear_in_red(gif) -> None:
    data, _, _ = gif
    image = Image.open(io.BytesIO(data))
    first = np.asarray(image.convert("RGB"))
    image.seek(image.n_frames - 1)
    last = np.asarray(image.convert("RGB"))
    # measured: no red pixel before the first contact, 18 once 20 contacts are drawn
    assert _red_pixels(first) == 0 and _red_pixels(last) > 8


def test_the_caption_holds_the_count_and_the_time(gif) -> None:
    data, _, _ = gif
    image = Image.open(io.BytesIO(data))
    image.seek(image.n_frames - 1)
    corner = np.asarray(image.convert("RGB"))[2:24, 2:150].astype(int)
    dark = np.all(corner < 40, axis=-1).mean()
    white = np.all(corner > 200, axis=-1).mean()
    assert dark > 0.3 and white > 0.03  # the band and its letters (measured: 0.87 and 0.051)


def test_by_default_the_video_runs_at_twice_real_time_and_follows_the_hand() -> None:
    config = VideoConfig(format="gif", fps=10, width=160, height=128)
    assert config.speed == 2.0 and config.follow and config.caption
    video = ExplorationVideo(config)
    run = run_exploration(BOX, "patch", count=20, rng=0, video=video)
    assert run.sim_time * 5 <= video.frames <= run.sim_time * 5 + 40
    assert video._camera is not None and video._view is not None
    center, radius = video._view
    # the view holds the object's box and the hand (a 0.06 m box, a hand of ~0.2 m; measured:
    # radius 0.102 m, centre 0.035 m from the box's)
    assert 0.05 < radius < 0.5 and np.linalg.norm(center - BOX.center) < radius
    video.finish()


def test_mp4_is_streamed_through_ffmpeg(tmp_path) -> None:
    pytest.importorskip("imageio_ffmpeg", reason="the `video` extra is not installed")
    video = ExplorationVideo(VideoConfig(format="mp4", fps=5, width=160, height=128))
    run_exploration(BOX, "patch", count=20, rng=0, video=video)
    data = video.finish()
    assert data[4:8] == b"ftyp" and video.frames > 5


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [({"format": "avi"}, "mp4, gif"), ({"width": 100}, "multiple of 16"),
     ({"speed": 0.0}, "speed"), ({"fps": 0}, "fps")],
)  # fmt: skip
def test_bad_video_settings_are_named(kwargs, match) -> None:
    with pytest.raises(InvalidInputError, match=match):
        VideoConfig(**kwargs)


def test_explore_writes_the_video_beside_its_files(tmp_path) -> None:
    summary = explore("cube", "patch", seed=0, out_dir=tmp_path / "run", progress=False,
                      count=20, video="gif")  # fmt: skip
    path = summary["files"]["video"]
    assert path.endswith("exploration.gif") and open(path, "rb").read(6) == b"GIF89a"
