"""The live view in a real headless browser: Playwright driving Debian's chromium.

Skipped (with the reason) where playwright, aiohttp or /usr/bin/chromium is missing;
`.ci/run` installs chromium. `BTNAV_UPDATE_SCREENSHOT=1` saves the README's picture
(docs/images/live_view.png) from the tour.
"""

from __future__ import annotations

import os
import threading
import time
from pathlib import Path

import pytest

pytest.importorskip("aiohttp", reason="the live view needs aiohttp (the view extra)")
sync_api = pytest.importorskip(
    "playwright.sync_api", reason="browser tests need playwright (the test extra)"
)

from btnav.mission import Mission, run_mission  # noqa: E402
from btnav.viz.live.live_view import LiveView  # noqa: E402
from btnav.viz.live.replay import Replay  # noqa: E402

from ..mission.missions import REPO, TOUR, write_mission  # noqa: E402

CHROMIUM = Path("/usr/bin/chromium")
ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
SCREENSHOT = REPO / "docs" / "images" / "live_view.png"


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    if not CHROMIUM.exists():
        pytest.skip(f"no chromium at {CHROMIUM} (apt-get install chromium)")
    with sync_api.sync_playwright() as p:
        context = p.chromium.launch_persistent_context(
            str(tmp_path_factory.mktemp("chromium-profile")),  # an empty user-data-dir
            executable_path=str(CHROMIUM),
            args=ARGS,
            headless=True,
            viewport={"width": 1200, "height": 720},
        )
        yield context
        context.close()


class LiveRun:
    """A mission run with the view attached, in a thread, then idling until closed."""

    def __init__(self, mission: Mission, out: Path, speed: float) -> None:
        self.view = LiveView(speed).start()
        self.mission = mission
        self.error: BaseException | None = None
        self.report = None
        self.thread = threading.Thread(target=self._run, args=(out,), daemon=True)
        self.thread.start()

    def _run(self, out: Path) -> None:
        try:
            m = self.mission
            self.report = run_mission(m, out, attach=lambda nav: self.view.attach(nav, m))
            self.view.result = self.report.status
            self.view.idle()
        except BaseException as err:  # re-raised in the test's thread
            self.error = err

    def close(self) -> None:
        self.view.close()
        self.thread.join(30)
        if self.error is not None:
            raise self.error


def open_page(browser, url: str):
    page = browser.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(url)
    page.wait_for_function("window.btnav.frames > 0 && window.btnav.static !== null")
    return page, errors


def state(page, expression: str):
    return page.evaluate(f"window.btnav.{expression}")


def wait_for(page, expression: str, timeout_s: float = 20.0) -> None:
    page.wait_for_function(f"() => {expression}", timeout=timeout_s * 1000)


def test_the_page_shows_the_tour_moving_and_pause_holds_sim_time(tmp_path, browser):
    mission = Mission.load(TOUR, overrides={"mission.time_limit": 60})
    run = LiveRun(mission, tmp_path / "out", speed=2.0)
    try:
        page, errors = open_page(browser, run.view.url)
        page.select_option("#costmap", "global")
        wait_for(page, "window.btnav.frame.t > 3 && window.btnav.tree.length > 10")
        first, pose0 = page.screenshot(), state(page, "frame.robot")
        time.sleep(1.5)
        second, pose1 = page.screenshot(), state(page, "frame.robot")
        assert first != second
        assert abs(pose1[0] - pose0[0]) + abs(pose1[1] - pose0[1]) > 0.2  # it drove
        assert "RUNNING" in page.inner_text("#legend")
        assert page.locator("#tree .st-R").count() > 0  # Groot's running nodes, orange
        assert "t = " in page.inner_text("#simtime") and "RTF" in page.inner_text("#rtf")
        if os.environ.get("BTNAV_UPDATE_SCREENSHOT") == "1":
            wait_for(page, "Object.keys(window.btnav.costmapImages).length > 0")
            time.sleep(0.5)
            SCREENSHOT.parent.mkdir(parents=True, exist_ok=True)
            page.screenshot(path=str(SCREENSHOT))

        page.click("#pause")
        wait_for(page, "window.btnav.frame.paused === true")
        held = state(page, "frame.t")
        time.sleep(1.0)
        assert state(page, "frame.t") == held  # paused: sim time stands still
        page.click("#step")
        wait_for(page, f"window.btnav.frame.t > {held}")
        stepped = state(page, "frame.t")
        assert stepped == pytest.approx(held + 0.05, abs=1e-6)  # one update of the view
        time.sleep(0.5)
        assert state(page, "frame.t") == stepped
        page.click("#pause")  # resume
        wait_for(page, f"window.btnav.frame.t > {stepped + 0.5}")
        assert not errors
    finally:
        run.close()


def test_a_drag_on_the_map_sends_a_goal_the_robot_reaches(tmp_path, browser):
    path = write_mission(
        tmp_path, "short", task={"navigate_to_pose": [1.5, 1.0, 0.0]}, time_limit=10
    )
    run = LiveRun(Mission.load(path), tmp_path / "out", speed=0)
    try:
        page, errors = open_page(browser, run.view.url)
        wait_for(page, "window.btnav.frame.result !== null")  # the mission ended: idling
        goal = (3.0, 2.0)
        u, v = page.evaluate(f"window.btnav.toCanvas({goal[0]}, {goal[1]})")
        box = page.locator("#map").bounding_box()
        page.click("#goal-tool")
        page.mouse.move(box["x"] + u, box["y"] + v)
        page.mouse.down()
        page.mouse.move(box["x"] + u, box["y"] + v - 40, steps=4)  # drag: facing +y
        page.mouse.up()
        wait_for(
            page, "window.btnav.frame.goals.length === 1 && window.btnav.frame.goals[0][0] > 2.9"
        )
        goal_sent = state(page, "frame.goals[0]")
        assert goal_sent[0] == pytest.approx(goal[0], abs=0.05)
        assert goal_sent[2] == pytest.approx(1.57, abs=0.1)  # the drag's direction
        wait_for(
            page,
            "Math.hypot(window.btnav.frame.robot[0] - 3, window.btnav.frame.robot[1] - 2) < 0.3"
            " && window.btnav.frame.actions.length === 0",
            timeout_s=60,
        )
        assert not errors
    finally:
        run.close()


def test_the_replay_slider_moves_through_the_run(tmp_path, browser):
    path = write_mission(
        tmp_path,
        "rec",
        task={"navigate_to_pose": [3.0, 2.0, 1.57]},
        time_limit=4,
        outputs=["report", "recording"],
    )
    run_mission(Mission.load(path), tmp_path / "out")
    replay = Replay(tmp_path / "out").start()
    try:
        page, errors = open_page(browser, replay.url)
        assert page.locator("#slider").is_visible() and not page.locator("#pause").is_visible()
        assert state(page, "frame.t") == 0.0
        last = len(replay.frames) - 1
        page.eval_on_selector(
            "#slider", f"s => {{ s.value = '{last}'; s.dispatchEvent(new Event('input')); }}"
        )
        wait_for(page, f"window.btnav.frame.index === {last}")
        assert state(page, "frame.t") == replay.frames[-1]["t"]
        assert state(page, "frame.robot")[0] > 1.5  # where it had driven to
        assert "result" in page.inner_text("#result")
        assert not errors
    finally:
        replay.close()
