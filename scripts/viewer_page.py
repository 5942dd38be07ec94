"""Measure the exported viewer page of a 150-contact run in headless Chromium; its screenshot.

    python scripts/viewer_page.py                       # JSON on stdout
    python scripts/viewer_page.py --screenshot docs/figures/viewer.png

Explores the cube (paper strategy, seed 0, 150 contacts), exports the replay
(``hapticsim view RUN --export``), opens it offline in Debian's Chromium (Playwright) REPEAT
times and prints the median time until the scene is drawn, with the load average. Needs the
extras ``viewer`` and ``browser`` and ``apt-get install chromium``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
]  # fmt: skip


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--screenshot", default=None, help="also write a PNG of the last touch")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()

    from playwright.sync_api import sync_playwright

    from hapticsim.exploration import explore
    from hapticsim.viewer import export_html, load_run, replay_states

    with tempfile.TemporaryDirectory() as tmp:
        run_dir = Path(tmp) / "run"
        explore("cube", strategy="paper", seed=0, out_dir=run_dir, progress=False, count=150)
        start = time.perf_counter()
        run = load_run(run_dir)
        states = replay_states(run)
        fits = time.perf_counter() - start
        start = time.perf_counter()
        page_file = export_html(run, states, Path(tmp) / "run.html")
        export = time.perf_counter() - start
        opened = []
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path="/usr/bin/chromium", args=FLAGS)
            for k in range(args.repeat):
                page = browser.new_page(viewport={"width": 1280, "height": 800})
                start = time.perf_counter()
                page.goto(page_file.as_uri())
                page.wait_for_selector("canvas")
                page.wait_for_function(
                    "() => { const t = window.__viserSceneTree; return t &&"
                    " t.getState()['/status'] !== undefined; }"
                )  # fmt: skip
                opened.append(time.perf_counter() - start)
                if k == 0 and args.screenshot:
                    page.wait_for_timeout(1000)
                    page.locator("button").filter(has=page.locator("svg")).nth(1).click()
                    for close in page.locator("button.mantine-Notification-closeButton").all():
                        close.click()
                    bar = page.locator(".mantine-Slider-root").bounding_box()
                    page.mouse.click(bar["x"] + 0.995 * bar["width"], bar["y"] + bar["height"] / 2)
                    page.wait_for_timeout(2500)
                    page.screenshot(path=args.screenshot)
                page.close()
            browser.close()
        json.dump({
            "contacts": len(run.points), "states": len(states),
            "replay_fits_seconds": round(fits, 2), "export_seconds": round(export, 2),
            "page_bytes": page_file.stat().st_size,
            "open_seconds_median": round(statistics.median(opened), 2),
            "open_seconds": [round(t, 2) for t in opened],
            "load_average": list(os.getloadavg()),
        }, sys.stdout, indent=1)  # fmt: skip
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
