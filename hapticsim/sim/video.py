"""Videos of an exploration: MuJoCo's offscreen renderer, recorded contacts drawn as they appear.

:class:`ExplorationVideo` hooks into a :class:`~hapticsim.sim.simulator.Simulator`
(:attr:`Simulator.tick_hooks`) and renders a frame every ``speed / fps`` seconds of simulated
time, looking from the scene's ``overview`` camera's direction at the object and the whole hand
(a free camera that follows the hand), with every contact recorded so far as a red dot, the
fingertips' current contacts in yellow, and the contact count and simulated time in a corner.
Between patterns the hand jumps to its next pose
(free-space transit is not simulated, :class:`~hapticsim.sim.explorer.ExplorerConfig`).

MP4 frames are streamed to ``ffmpeg`` (``imageio-ffmpeg``, the optional extra ``video``) so memory
stays flat; GIF frames are kept (smaller by default) and written with Pillow, which matplotlib
already needs. :meth:`ExplorationVideo.finish` gives the encoded file's bytes, so that the caller
writes it atomically beside its other outputs.
"""

from __future__ import annotations

import importlib.util
import io
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
from numpy.typing import NDArray

from hapticsim._validate import finite_float, positive_int
from hapticsim.errors import ChoiceError, InvalidInputError
from hapticsim.sim.recorder import Recorder
from hapticsim.sim.render import CONTACT_RGBA, add_markers, make_renderer
from hapticsim.sim.simulator import Simulator

#: Video formats.
VIDEO_FORMATS: tuple[str, ...] = ("mp4", "gif")
#: Colour (RGBA) of the fingertips' current contacts.
LIVE_RGBA: tuple[float, float, float, float] = (1.0, 0.85, 0.1, 1.0)


@dataclass(frozen=True)
class VideoConfig:
    """How an exploration video is made.

    Attributes:
        format: ``"mp4"`` (H.264 through imageio-ffmpeg) or ``"gif"``.
        fps: frames per second of the video.
        speed: simulated seconds per second of video (default 2: twice real time, so that the
            video costs at most about twice the run; 1: real time).
        width, height: frame size [px], multiples of 16 for MP4 (default 640 x 480; GIF 320 x
            240 when not given).
        camera: camera of the scene; with `follow`, the direction the video looks from.
        max_frames: frames kept at most (later ones are dropped; a 20 s exploration at 12.5
            frames per simulated second is 250 frames).
        follow: keep the object and the whole hand in frame (a free camera looking from the
            scene camera's direction at the box of both, smoothed); False: the fixed camera.
        caption: draw the contact count and the simulated time in the top left corner.
    """

    format: str = "mp4"
    fps: int = 25
    speed: float = 2.0
    width: int | None = None
    height: int | None = None
    camera: str = "overview"
    max_frames: int = 3000
    follow: bool = True
    caption: bool = True

    def __post_init__(self) -> None:
        if self.format not in VIDEO_FORMATS:
            raise ChoiceError("format", self.format, VIDEO_FORMATS)
        positive_int(self.fps, "fps")
        positive_int(self.max_frames, "max_frames")
        if not 0.01 <= finite_float(self.speed, "speed") <= 100.0:
            raise InvalidInputError(f"`speed` must be in [0.01, 100], got {self.speed!r}")
        small = self.format == "gif"
        width = self.width if self.width is not None else (320 if small else 640)
        height = self.height if self.height is not None else (240 if small else 480)
        for name, value in (("width", width), ("height", height)):
            positive_int(value, name, minimum=16)
            if self.format == "mp4" and value % 16:
                raise InvalidInputError(f"`{name}` must be a multiple of 16 for MP4, got {value}")
        object.__setattr__(self, "width", int(width))
        object.__setattr__(self, "height", int(height))


def check_video_support(config: VideoConfig) -> None:
    """Raise InvalidInputError when the format's encoder is not installed (before a run)."""
    if config.format == "mp4" and importlib.util.find_spec("imageio_ffmpeg") is None:
        raise InvalidInputError(
            "MP4 videos need imageio-ffmpeg: pip install 'hapticsim[video]' (or ask for a GIF)"
        )


class ExplorationVideo:
    """Frames of a running simulation (see the module docstring).

    Args:
        config: video settings.

    Raises:
        InvalidInputError: the MP4 encoder (imageio-ffmpeg) is not installed.
    """

    def __init__(self, config: VideoConfig | None = None) -> None:
        self.config = VideoConfig() if config is None else config
        check_video_support(self.config)
        self.frames = 0
        self._renderer: mujoco.Renderer | None = None
        self._recorder: Recorder | None = None
        self._next_time = 0.0
        self._gif: list[NDArray[np.uint8]] = []
        self._writer = None
        self._path: Path | None = None
        self._camera: mujoco.MjvCamera | None = None
        self._view: tuple[NDArray[np.float64], float] | None = None  # smoothed centre, radius

    def attach(self, sim: Simulator, recorder: Recorder) -> None:
        """Start taking frames of `sim`, drawing the contacts of `recorder`."""
        cfg = self.config
        self._renderer = make_renderer(sim.model, cfg.width, cfg.height)
        self._recorder = recorder
        self._next_time = sim.time
        self._view = None
        self._camera = _follow_camera(sim.model, cfg.camera) if cfg.follow else None
        if cfg.format == "mp4":
            import imageio.v2 as imageio

            fd, name = tempfile.mkstemp(prefix="hapticsim-video-", suffix=".mp4")
            os.close(fd)
            self._path = Path(name)
            self._writer = imageio.get_writer(
                name, fps=cfg.fps, codec="libx264", quality=7, macro_block_size=16,
                ffmpeg_log_level="error",
            )  # fmt: skip
        sim.tick_hooks.append(self.capture)
        self.capture(sim)

    def capture(self, sim: Simulator) -> None:
        """Take a frame when its time has come (a tick hook)."""
        if self._renderer is None or self.frames >= self.config.max_frames:
            return
        if sim.time < self._next_time - 1e-9 and self.frames > 0:
            return
        self._next_time = sim.time + self.config.speed / self.config.fps
        renderer = self._renderer
        if self._camera is not None:
            self._aim(sim)
        renderer.update_scene(
            sim.data, camera=self._camera if self._camera is not None else self.config.camera
        )
        # shadow maps are 90 % of a frame on a CPU renderer (~0.45 s against 0.05 s at 640 x 480)
        renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = False
        if self._recorder is not None and len(self._recorder):
            add_markers(renderer.scene, self._recorder.points(), CONTACT_RGBA)
        live = [t.point_world for t in sim.contacts.tips if t is not None and t.force > 0]
        if live:
            add_markers(renderer.scene, np.array(live), LIVE_RGBA, radius=0.002)
        frame = renderer.render()
        if sim.tactile is not None:  # the pads' pressure images along the bottom edge
            frame = pad_strip(frame, sim.tactile.read(sim.data).pressure)
        if self.config.caption:
            count = 0 if self._recorder is None else len(self._recorder)
            frame = caption(frame, f"{count} contacts   t = {sim.time:5.1f} s")
        if self._writer is not None:
            self._writer.append_data(frame)
        else:
            self._gif.append(frame.copy())
        self.frames += 1

    def _aim(self, sim: Simulator) -> None:
        """Point the free camera at the box of the object and the hand (palm and fingertips),
        from far enough to hold its bounding sphere; centre and radius follow the hand with a
        time constant of a few frames, so the picture does not shake."""
        assert self._camera is not None
        truth = sim.scene.truth
        points = [np.asarray(truth.bounds), sim.palm_pose()[0][None, :]]
        points += [sim.tip_world(k)[None, :] for k in range(len(sim.hand.fingers))]
        cloud = np.concatenate(points)
        low, high = cloud.min(axis=0), cloud.max(axis=0)
        center, radius = 0.5 * (low + high), 0.5 * float(np.linalg.norm(high - low))
        if self._view is not None:
            old_center, old_radius = self._view
            center = 0.75 * old_center + 0.25 * center
            radius = max(0.9 * old_radius + 0.1 * radius, radius)  # never cut the hand off
        self._view = (center, radius)
        fovy = float(sim.model.vis.global_.fovy)
        self._camera.lookat[:] = center
        self._camera.distance = 1.1 * radius / np.sin(np.radians(fovy) / 2.0)

    def finish(self) -> bytes:
        """Stop, encode and return the video file's bytes."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
        if self._writer is not None:
            self._writer.close()
            self._writer = None
            assert self._path is not None
            try:
                return self._path.read_bytes()
            finally:
                self._path.unlink(missing_ok=True)
        from PIL import Image

        if not self._gif:
            return b""
        # octree palettes keep the few red pixels of small contact markers (median cut drops
        # them into the nearest orange of the fingertips)
        octree = Image.Quantize.FASTOCTREE
        images = [Image.fromarray(f).quantize(colors=255, method=octree) for f in self._gif]
        buffer = io.BytesIO()
        images[0].save(
            buffer, format="GIF", save_all=True, append_images=images[1:],
            duration=int(round(1000 / self.config.fps)), loop=0,
        )  # fmt: skip
        self._gif.clear()
        return buffer.getvalue()

    def close(self) -> None:
        """Drop everything (after a failed run)."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
        if self._writer is not None:
            self._writer.close()
            self._writer = None
        if self._path is not None:
            self._path.unlink(missing_ok=True)
        self._gif.clear()


def _follow_camera(model: mujoco.MjModel, name: str) -> mujoco.MjvCamera:
    """A free camera looking the way the scene camera `name` looks (its azimuth and elevation);
    :meth:`ExplorationVideo._aim` sets where and from how far."""
    camera = mujoco.MjvCamera()
    camera.type = mujoco.mjtCamera.mjCAMERA_FREE
    index = int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_CAMERA, name))
    if index < 0:
        raise InvalidInputError(f"the scene has no camera {name!r} for the video")
    quat = model.cam_quat[index]
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, quat)
    forward = -rot.reshape(3, 3)[:, 2]  # a camera looks along its -z
    camera.azimuth = float(np.degrees(np.arctan2(forward[1], forward[0])))
    camera.elevation = float(np.degrees(np.arcsin(np.clip(forward[2], -1.0, 1.0))))
    return camera


def caption(frame: NDArray[np.uint8], text: str) -> NDArray[np.uint8]:
    """`frame` with `text` in white on a dark band in its top left corner (Pillow)."""
    from PIL import Image, ImageDraw

    image = Image.fromarray(frame)
    draw = ImageDraw.Draw(image)
    size = max(12, frame.shape[0] // 28)
    try:
        from PIL import ImageFont

        font = ImageFont.load_default(size=size)
    except (TypeError, OSError):  # pragma: no cover - an old Pillow
        font = None
    box = draw.textbbox((8, 6), text, font=font)
    draw.rectangle((box[0] - 4, box[1] - 3, box[2] + 4, box[3] + 3), fill=(20, 20, 20))
    draw.text((8, 6), text, fill=(255, 255, 255), font=font)
    return np.asarray(image)


def pad_strip(frame: NDArray[np.uint8], images: NDArray[np.float64],
              full_scale: float = 1.0e5) -> NDArray[np.uint8]:  # fmt: skip
    """`frame` (h, w, 3) with the pads' pressure images (pads, rows, cols) [Pa] drawn side by
    side along its bottom edge (a quarter of its height; dark: 0, yellow: `full_scale`)."""
    out = np.array(frame, copy=True)
    h, w = out.shape[:2]
    pads, rows, cols = images.shape
    size = max(8, h // 4)
    scale = max(1, size // max(rows, cols))
    gap = 4
    x = gap
    for k in range(pads):
        value = np.clip(images[k] / full_scale, 0.0, 1.0)
        tile = np.kron(value, np.ones((scale, scale)))
        th, tw = tile.shape
        if x + tw > w or th + gap > h:
            break
        rgb = np.stack([255 * np.sqrt(tile), 255 * tile, 40 + 0 * tile], axis=-1)
        out[h - th - gap : h - gap, x : x + tw] = rgb.astype(np.uint8)
        x += tw + gap
    return out


__all__ = [
    "ExplorationVideo",
    "LIVE_RGBA",
    "VIDEO_FORMATS",
    "VideoConfig",
    "check_video_support",
    "pad_strip",
]
