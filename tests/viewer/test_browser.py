"""The viewer in a real headless browser: Debian's Chromium driven by Playwright.

Skipped where viser, Playwright or Chromium is missing (``.ci/run`` installs all three: the
``viewer`` and ``browser`` extras and ``apt-get install chromium``).
"""

from __future__ import annotations

import io
import shutil
import socket
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from hapticsim.geometry import SuperquadricUnion
from hapticsim.viewer import export_html, load_run, replay_states, serve
from hapticsim.viewer.scene import FINGER_RGB

pytest.importorskip("viser")
sync_api = pytest.importorskip("playwright.sync_api")
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
# ~15 s each (software WebGL): behind the slow marker, which CI runs after the default tests
pytestmark = [
    pytest.mark.skipif(CHROMIUM is None, reason="no Chromium (apt-get install chromium)"),
    pytest.mark.slow,
]

#: Chromium's flags on a machine without a display, a GPU or a network.
FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
]  # fmt: skip
VIEWPORT = {"width": 1280, "height": 800}
#: Console messages a software-rendered WebGL page may print that are not the page's errors.
BENIGN = ("GPU stall due to ReadPixels", "Automatic fallback to software WebGL")


@pytest.fixture(scope="module")
def browser() -> Any:
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=FLAGS)
        yield b
        b.close()


@pytest.fixture(scope="module")
def replay(run_dir_150: Path) -> tuple[Any, list[Any]]:
    data = load_run(run_dir_150)
    return data, replay_states(data, estimate_every=10)


def _open(browser: Any, url: str) -> tuple[Any, list[str], list[str]]:
    """A page at `url`, with its console errors and the requests that left the machine."""
    page = browser.new_page(viewport=VIEWPORT)
    errors: list[str] = []
    outside: list[str] = []
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" and not any(
        b in m.text for b in BENIGN) else None)  # fmt: skip
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.on("request", lambda r: outside.append(r.url) if not r.url.startswith(
        ("file:", "data:", "blob:", "http://127.0.0.1", "http://localhost", "ws://")) else None)
    page.goto(url)
    return page, errors, outside


def _pixels(page: Any) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(page.screenshot())).convert("RGB"), dtype=int)


def _contact_pixels(img: np.ndarray, tolerance: int = 24) -> int:
    """Pixels within `tolerance` of a finger's colour (the contacts are drawn flat)."""
    return int(sum(
        (np.abs(img - np.array(rgb)).max(axis=2) <= tolerance).sum() for rgb in FINGER_RGB[:4]
    ))  # fmt: skip


def _settled(page: Any, check: Any, timeout: float = 15.0) -> np.ndarray:
    """A screenshot once `check(picture)` holds (software WebGL may draw a few frames late)."""
    deadline = time.monotonic() + timeout
    while True:
        img = _pixels(page)
        if check(img) or time.monotonic() > deadline:
            return img
        page.wait_for_timeout(300)


#: The label naming the state drawn, read through viser's scene-tree test hook: '' until the
#: page has set the hook up (a drawn canvas may come first; a predicate that throws would end
#: Playwright's wait at once instead of polling on).
STATUS_JS = (
    "(() => { const tree = window.__viserSceneTree;"
    " const n = tree && tree.getState()['/status'];"
    " return n ? n.message.props.text : ''; })()"
)


def _status(page: Any) -> str:
    return page.evaluate(f"() => {STATUS_JS}")


def _wait_status(page: Any, prefix: str, timeout: float = 10000) -> None:
    """Until the status label starts with `prefix`."""
    page.wait_for_function(f"t => {STATUS_JS}.startsWith(t)", arg=prefix, timeout=timeout)


def _nodes(page: Any) -> list[str]:
    return page.evaluate("() => Object.keys(window.__viserSceneTree.getState())")


def _drawn(img: np.ndarray) -> float:
    """Fraction of the picture that is not the blank page's white."""
    return float((np.abs(img - 255).max(axis=2) > 12).mean())


def test_the_exported_page_opens_offline_and_replays_every_touch(browser, replay, tmp_path) -> None:  # noqa: ANN001, E501
    data, states = replay
    page_file = export_html(data, states, tmp_path / "run.html")
    assert page_file.stat().st_size < 5_000_000
    start = time.perf_counter()
    page, errors, outside = _open(browser, page_file.as_uri())
    page.wait_for_selector("canvas", timeout=5000)
    page.wait_for_function("document.querySelector('.mantine-Slider-root') !== null",
                           timeout=5000)  # fmt: skip
    opened = time.perf_counter() - start
    assert opened < 5.0, f"the page took {opened:.1f} s to draw"  # measured 0.9-1.0 s
    page.wait_for_timeout(1500)
    # pause the replay, then look at the first touches and at the last
    page.locator("button").filter(has=page.locator("svg")).nth(1).click()
    bar = page.locator(".mantine-Slider-root").bounding_box()
    y = bar["y"] + bar["height"] / 2
    page.mouse.click(bar["x"] + 0.03 * bar["width"], y)
    page.wait_for_timeout(1500)
    early = _pixels(page)
    page.mouse.click(bar["x"] + 0.995 * bar["width"], y)
    late = _settled(page, lambda img: _contact_pixels(img) > 2000)
    blank = np.full_like(late, 255)
    assert _drawn(late) > 0.03 and _drawn(blank) == 0.0  # the object, the hand, the contacts
    assert _contact_pixels(late) > 2 * max(_contact_pixels(early), 10), "contacts accumulate"
    assert np.abs(late - early).max(axis=2).mean() > 1.0, "the slider changes what is drawn"
    last = len(states) - 1
    assert _status(page).startswith(f"touch {last} of {last}: {len(data.points)} contacts")
    # one state per touch, SECONDS_PER_TOUCH apart: the timeline's length says how many
    thumb = page.locator("[role=slider]").first
    assert float(thumb.get_attribute("aria-valuemax")) == pytest.approx(0.2 * len(states))
    nodes = _nodes(page)
    assert {"/truth/part0", "/estimate/part0", "/hand/geom000", "/status"} <= set(nodes)
    assert not errors, errors
    assert not outside, f"the page fetched {outside}"
    page.close()


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def test_the_live_viewer_serves_moves_with_its_slider_and_stops(browser, replay) -> None:  # noqa: ANN001
    data, states = replay
    port, stop, urls = _free_port(), threading.Event(), []
    thread = threading.Thread(target=serve, args=(data, states), daemon=True,
                              kwargs={"port": port, "stop": stop, "ready": urls.append})
    thread.start()
    deadline = time.monotonic() + 20
    while not urls and time.monotonic() < deadline:
        time.sleep(0.05)
    assert urls == [f"http://localhost:{port}"]
    try:
        page, errors, outside = _open(browser, urls[0])
        page.wait_for_selector("canvas", timeout=10000)
        last = len(states) - 1
        _wait_status(page, f"touch {last} of {last}:")
        last = _settled(page, lambda img: _contact_pixels(img) > 2000)
        thumb = page.locator("[role=slider]").first
        thumb.focus()
        page.keyboard.press("Home")  # the touch slider to 0: no contacts yet
        _wait_status(page, "touch 0 of")
        first = _settled(page, lambda img: _contact_pixels(img) < 500)
        assert _contact_pixels(last) > 2 * max(_contact_pixels(first), 10)
        for layer in ("truth", "contacts", "normals", "estimate", "hand"):  # a toggle each
            assert page.get_by_text(layer, exact=True).count() >= 1, layer
        assert not errors, errors
        assert not outside, f"the page fetched {outside}"
        page.close()
    finally:
        stop.set()
        thread.join(timeout=10)
    assert not thread.is_alive(), "the server did not stop"
    with socket.socket() as s:  # no one listens on the port any more (TIME_WAIT may linger)
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        s.bind(("127.0.0.1", port))


def test_the_suite_report_page_loads_its_pictures(browser, tmp_path: Path) -> None:  # noqa: ANN001
    from hapticsim.suites.html_report import write_report
    from tests.suites.test_html_report import _two_groups

    index = write_report(_two_groups(), tmp_path / "rep", baseline=_two_groups())
    page, errors, outside = _open(browser, index.as_uri())
    page.wait_for_load_state("load")
    widths = page.evaluate("() => Array.from(document.images).map(i => i.naturalWidth)")
    assert len(widths) == 2 and min(widths) > 300
    assert page.get_by_text("no regression").count() == 1
    assert not errors and not outside
    page.close()


def test_a_mesh_truth_union_estimate_and_taxels_show(browser, tmp_path: Path) -> None:  # noqa: ANN001
    from hapticsim.data.example_meshes import l_block
    from hapticsim.data.objects import write_stl
    from hapticsim.exploration import explore

    write_stl(tmp_path / "l_block.stl", l_block())
    out = tmp_path / "run"
    explore(str(tmp_path / "l_block.stl"), strategy="paper", seed=0, out_dir=out, progress=False,
            count=60, method="multi", sensing="tactile")  # fmt: skip
    data = load_run(out)
    assert isinstance(data.estimate, SuperquadricUnion) and data.taxels is not None
    assert data.taxel_state is not None and data.taxel_state.shape == data.taxels.shape
    page_file = export_html(data, replay_states(data, estimate_every=20), tmp_path / "l.html")
    page, errors, outside = _open(browser, page_file.as_uri())
    _wait_status(page, "touch ")
    bar = page.locator(".mantine-Slider-root").bounding_box()
    page.locator("button").filter(has=page.locator("svg")).nth(1).click()
    page.mouse.click(bar["x"] + 0.995 * bar["width"], bar["y"] + bar["height"] / 2)
    page.wait_for_timeout(1500)
    nodes = set(_nodes(page))
    parts = {f"/estimate/part{j}" for j in range(len(data.estimate.parts))}
    assert {"/truth/part0", "/taxels/pad", "/taxels/state"} | parts <= nodes
    assert _drawn(_pixels(page)) > 0.03
    assert not errors and not outside
    page.close()


@pytest.mark.parametrize("inherited", ["default", "ignored"])
def test_the_view_command_serves_until_interrupted(run_dir: Path, inherited: str) -> None:
    """SIGINT ends it, also when it was started with SIGINT ignored (a non-interactive
    shell's background job: Python keeps an inherited SIG_IGN, and the viewer then never
    stopped)."""
    import signal
    import subprocess
    import sys
    import urllib.request

    port = _free_port()
    ignore = None if inherited == "default" else (
        lambda: signal.signal(signal.SIGINT, signal.SIG_IGN))  # fmt: skip
    proc = subprocess.Popen(
        [sys.executable, "-m", "hapticsim.cli", "view", str(run_dir), "--port", str(port),
         "--estimate-every", "50", "--quiet"],
        stderr=subprocess.PIPE, stdout=subprocess.PIPE, text=True, preexec_fn=ignore,
    )  # fmt: skip
    try:
        lines = [proc.stderr.readline()]
        while "at http://" not in lines[-1] and lines[-1] and len(lines) < 50:
            lines.append(proc.stderr.readline())  # a cold cache's compile lines come first
        assert f"at http://localhost:{port}" in lines[-1], lines
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=10) as reply:
            assert reply.status == 200 and b"<html" in reply.read(2000).lower()
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=15)
    finally:
        proc.kill()
    assert proc.returncode == 0, err
    assert "Traceback" not in err and out == ""
