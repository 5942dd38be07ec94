"""Videos of an exploration: MuJoCo's offscreen renderer, recorded contacts drawn as they appear.

:class:`ExplorationVideo` hooks into a :class:`~hapticsim.sim.simulator.Simulator`
(:attr:`Simulator.tick_hooks`) and renders a frame every ``speed / fps`` seconds of simulated
time from the scene's ``overview`` camera, with every contact recorded so far as a red dot and
the fingertips' current contacts in yellow. Between patterns the hand jumps to its next pose
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
from hapticsim.errors import InvalidInputError
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
        speed: simulated seconds per second of video (1: real time).
        width, height: frame size [px], multiples of 16 for MP4 (default 640 x 480; GIF 320 x
            240 when not given).
        camera: camera of the scene.
        max_frames: frames kept at most (later ones are dropped; a 20 s exploration at 25 fps
            is 500 frames).
    """

    format: str = "mp4"
    fps: int = 25
    speed: float = 1.0
    width: int | None = None
    height: int | None = None
    camera: str = "overview"
    max_frames: int = 3000

    def __post_init__(self) -> None:
        if self.format not in VIDEO_FORMATS:
            raise InvalidInputError(
                f"`format` must be one of {', '.join(VIDEO_FORMATS)}, got {self.format!r}"
            )
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

    def attach(self, sim: Simulator, recorder: Recorder) -> None:
        """Start taking frames of `sim`, drawing the contacts of `recorder`."""
        cfg = self.config
        self._renderer = make_renderer(sim.model, cfg.width, cfg.height)
        self._recorder = recorder
        self._next_time = sim.time
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
        renderer.update_scene(sim.data, camera=self.config.camera)
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
        if self._writer is not None:
            self._writer.append_data(frame)
        else:
            self._gif.append(frame.copy())
        self.frames += 1

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
