"""Serve a run in viser (live, with a touch slider and layer toggles) or export it as one page.

:func:`serve` starts viser's server on `host` (localhost unless told otherwise) and blocks until
interrupted (or until `stop` is set); its panel has a slider over the touches, a play button,
a toggle per layer and the run's title. :func:`export_html` records the same scene, state after
state (``seconds_per_touch`` apart), into viser's recording format and writes it with viser's
client into one HTML file that opens offline: its timeline replays the exploration.
"""

from __future__ import annotations

import contextlib
import io
import signal
import socket
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from hapticsim._files import check_output_path, write_text_atomic
from hapticsim.errors import InvalidInputError
from hapticsim.viewer.run import RunData, State
from hapticsim.viewer.scene import RunScene

#: Default port of ``hapticsim view`` (viser's own default).
DEFAULT_PORT: int = 8080
#: Replay speed of an exported page [s of playback per touch].
SECONDS_PER_TOUCH: float = 0.2


def require_viser() -> Any:
    """The viser module, or a clear error naming the extra to install."""
    try:
        import viser
    except ImportError:
        raise InvalidInputError(
            "the viewer needs viser: pip install 'hapticsim[viewer]'"
        ) from None
    return viser


def _free_port(host: str) -> int:
    with socket.socket() as s:
        s.bind((host, 0))
        return int(s.getsockname()[1])


def _start(host: str, port: int) -> Any:
    viser = require_viser()
    try:  # viser prints a banner on stdout even when not verbose: stdout is ours (JSON)
        with contextlib.redirect_stdout(io.StringIO()):
            return viser.ViserServer(host=host, port=port, verbose=False)
    except OSError as exc:
        raise InvalidInputError(f"cannot serve on {host}:{port}: {exc.strerror or exc}") from None


def export_html(
    run: RunData, states: list[State], out: str | Path,
    seconds_per_touch: float = SECONDS_PER_TOUCH,
) -> Path:  # fmt: skip
    """Write run `run`'s replay as one self-contained HTML page (module docstring).

    Args:
        run: the run; states: its states (:func:`~hapticsim.viewer.run.replay_states`).
        out: the ``.html`` file to write (atomically).
        seconds_per_touch: playback time per state [s], > 0.

    Returns:
        The written path.
    """

    out = check_output_path(out, (".html", ".htm"))
    if not seconds_per_touch > 0:
        raise InvalidInputError(f"`seconds_per_touch` must be > 0, got {seconds_per_touch}")
    server = _start("127.0.0.1", _free_port("127.0.0.1"))
    try:
        view = RunScene(server.scene, run, states)
        view.aim(server.initial_camera)
        view.show(0)
        recording = server.get_scene_serializer()
        for k in range(1, len(states)):
            recording.insert_sleep(seconds_per_touch)
            view.show(k)
        recording.insert_sleep(seconds_per_touch)
        page = recording.as_html()
    finally:
        _stop(server)
    title = run.title.replace("&", "&amp;").replace("<", "&lt;")
    page = page.replace("<title>", f"<title>{title} - ", 1) if "<title>" in page else page
    return write_text_atomic(out, page)


def serve(
    run: RunData, states: list[State], host: str = "127.0.0.1", port: int = DEFAULT_PORT,
    stop: threading.Event | None = None, ready: Callable[[str], None] | None = None,
) -> None:  # fmt: skip
    """Serve run `run` until Ctrl-C or until `stop` is set (module docstring).

    Args:
        run, states: the run and its states.
        host: address to bind (default localhost only; ``0.0.0.0`` for every interface).
        port: port to bind.
        stop: an event that ends the server when set.
        ready: called with the viewer's URL once it serves (default: a line on stderr).
    """
    server = _start(host, int(port))
    try:
        view = RunScene(server.scene, run, states)
        view.aim(server.initial_camera)
        last = len(states) - 1
        gui = server.gui
        gui.add_markdown(f"**{run.title}**")
        slider = gui.add_slider("touch", min=0, max=max(last, 1), step=1, initial_value=last)
        play = gui.add_checkbox("play", initial_value=False)
        toggles = {name: gui.add_checkbox(name, initial_value=True) for name in view.layers()}
        lock = threading.Lock()

        def on_touch(_: Any) -> None:
            with lock:
                view.show(int(slider.value))

        slider.on_update(on_touch)
        for name, box in toggles.items():
            box.on_update(lambda _, n=name, b=box: _toggle(view, lock, n, b.value))
        view.show(last)
        url = f"http://{'localhost' if host in ('127.0.0.1', 'localhost') else host}:" \
              f"{server.get_port()}"  # fmt: skip
        (ready or (lambda u: print(f"hapticsim: viewing {run.path} at {u} (Ctrl-C ends)",
                                   file=sys.stderr, flush=True)))(url)  # fmt: skip
        event = stop or threading.Event()
        with _interruptible():
            try:
                while not event.wait(SECONDS_PER_TOUCH):
                    if play.value:
                        slider.value = 0 if int(slider.value) >= last else int(slider.value) + 1
                        on_touch(None)
            except KeyboardInterrupt:
                pass
    finally:
        _stop(server)


@contextlib.contextmanager
def _interruptible() -> Any:
    """Let SIGINT (Ctrl-C, ``kill -INT``) end the serving even when the process was started
    with it ignored, as a non-interactive shell starts a background job (Python then keeps it
    ignored); the previous handler is restored after. Only the main thread can set it."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.getsignal(signal.SIGINT)
    signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def _stop(server: Any) -> None:
    with contextlib.redirect_stdout(io.StringIO()):
        server.stop()
        time.sleep(0.05)  # let viser's threads see the stop before the interpreter goes on


def _toggle(view: RunScene, lock: threading.Lock, name: str, value: bool) -> None:
    with lock:
        view.set_layer(name, value)


__all__ = ["DEFAULT_PORT", "export_html", "require_viser", "serve"]
