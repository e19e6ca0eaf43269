"""The explorer in a real browser (headless Chromium driven by Playwright).

The page of ``prp3 explore`` is served by the command itself (a subprocess);
the tests set its widgets as a user's drag does (the model's ``value``, which
BokehJS sends to the server), then read the drawn data sources back from the
page and hold them against the library's values for the same pose.  The HTML
file of a run is opened from ``file://`` with the network off, and played.

Skipped, with one line, when Playwright or Chromium is missing (``.ci/run``
installs Debian's chromium; the ``test`` extra the ``playwright`` package).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from browsertools import explore_server, require_browser, run_prp3
from prp3 import Robot
from prp3.errors import Prp3Error
from prp3.explorer.run_folder import read_run
from prp3.explorer.scene import State, pose_table
from prp3.model.motion import Motion
from prp3.plotting.animation import frame_indices

pytest.importorskip("bokeh", reason="the explorer needs Bokeh (pip install 'prp3[explore]')")
require_browser()

#: e_i and n_i of the legs, written out here (α = π/3, π, −π/3, eq. 1).
E = np.array([[0.5, math.sqrt(3) / 2], [-1.0, 0.0], [0.5, -math.sqrt(3) / 2]])
N = np.array([[-math.sqrt(3) / 2, 0.5], [0.0, -1.0], [math.sqrt(3) / 2, 0.5]])

_READ = """
(name) => {
  const source = Bokeh.documents[0].get_model_by_name(name);
  const data = source.data instanceof Map ? Object.fromEntries(source.data) : source.data;
  return Object.fromEntries(Object.entries(data).map(([k, v]) => [k, Array.from(v)]));
}
"""

_SET = """
([name, value]) => { Bokeh.documents[0].get_model_by_name(name).value = value; }
"""


@pytest.fixture(scope="module")
def server() -> Iterator[str]:
    with explore_server() as (url, _):
        yield url


@pytest.fixture(scope="module")
def run_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("browser") / "rot"
    run_prp3("simulate", "--motion", "rotation", "--samples", "61", "--output", str(folder))
    return folder


@pytest.fixture(scope="module")
def run_server(run_folder: Path) -> Iterator[str]:
    with explore_server("--results", str(run_folder)) as (url, _):
        yield url


def _open(browser: Any, url: str) -> Any:
    page = browser.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda error: errors.append(str(error)))
    page.goto(url)
    page.wait_for_function(
        "() => window.Bokeh && Bokeh.documents.length > 0 && "
        "Bokeh.documents[0].get_model_by_name('arrows') !== null",
        timeout=30_000,
    )
    page.errors = errors
    return page


def _until(check: Callable[[], bool], timeout: float = 15.0) -> None:
    deadline = time.monotonic() + timeout
    while not check():
        if time.monotonic() > deadline:
            raise AssertionError("the page did not update in time")
        time.sleep(0.05)


def _forces(arrows: dict[str, list[Any]], quantity: str) -> np.ndarray:
    rows = [k for k, q in enumerate(arrows["quantity"]) if q == quantity]
    return np.array([[arrows["fx"][k], arrows["fy"][k]] for k in rows], dtype=float)


def _expected(table: dict[str, Any], k: int) -> dict[str, np.ndarray]:
    """The arrows of sample ``k`` of a results table, placed along e_i, n_i here."""

    def leg(name: str) -> np.ndarray:
        return np.array([float(table[f"{name}_{x}"][k]) for x in "ABC"])[:, None]

    return {
        "f10": leg("f10") * E,
        "f21": leg("f21y") * N + leg("f21z") * E,
        "n10": leg("n10") * N,
    }


def _matches(page: Any, expected: dict[str, np.ndarray]) -> bool:
    arrows = page.evaluate(_READ, "arrows")
    if not arrows["quantity"]:
        return False
    return all(
        np.allclose(_forces(arrows, name), value, rtol=1e-12, atol=1e-12)
        for name, value in expected.items()
    )


def test_the_page_loads_with_the_robot_and_its_forces(browser: Any, server: str) -> None:
    page = _open(browser, server)
    try:
        arrows = page.evaluate(_READ, "arrows")
        assert sorted(set(arrows["quantity"])) == ["f10", "f21", "n10", "n32"]
        assert len(arrows["quantity"]) == 12
        assert _matches(page, _expected(pose_table(Robot(), State()), 0))
        platform = page.evaluate(_READ, "platform")
        assert np.allclose(
            platform["xs"][0], [0.0, -0.3 * math.sqrt(3) / 2, 0.3 * math.sqrt(3) / 2]
        )
        assert page.evaluate("() => Bokeh.documents[0].get_model_by_name('message').text") == ""
        # the check box of f10 hides its arrows (shafts and heads), the others stay
        drawn = """() => {
          const found = [];
          for (const m of Bokeh.documents[0]._all_models.values()) {
            if (m.type === "GlyphRenderer" && m.data_source.name === "arrows") {
              const data = m.data_source.data;
              const quantity = data instanceof Map ? data.get("quantity") : data.quantity;
              found.push([...m.view.indices].map((k) => quantity[k]).sort());
            }
          }
          return found;
        }"""
        every = sorted(arrows["quantity"])
        assert page.evaluate(drawn) == [every, every]  # the shafts and the heads
        page.evaluate(
            "() => { Bokeh.documents[0].get_model_by_name('arrow_toggles').active = [1, 2, 3, 4, 5] }"
        )
        rest = sorted(q for q in arrows["quantity"] if q != "f10")
        _until(lambda: page.evaluate(drawn) == [rest, rest])
        page.evaluate("() => { Bokeh.documents[0].get_model_by_name('arrow_toggles').active = [] }")
        _until(lambda: page.evaluate(drawn) == [[], []])
        assert page.errors == []
    finally:
        page.close()


def test_moving_the_sliders_draws_the_library_s_forces(browser: Any, server: str) -> None:
    page = _open(browser, server)
    try:
        settings = {"x": 0.031, "y": -0.022, "phi": 0.25, "dx": 0.3, "dphi": -1.2, "ddy": 4.0}
        for name, value in settings.items():
            page.evaluate(_SET, [name, value])
        state = State.from_controls(settings)
        expected = _expected(pose_table(Robot(), state), 0)
        _until(lambda: _matches(page, expected))
        table = page.evaluate(_READ, "values")
        row = table["quantity"].index("f10")
        library = pose_table(Robot(), state)
        assert [table[leg][row] for leg in "ABC"] == [float(library[f"f10_{x}"][0]) for x in "ABC"]

        # and the table on the screen shows them (BokehJS redraws a table only when told)
        def shown() -> list[str]:
            cells = page.locator(".slick-cell").all_inner_texts()
            start = cells.index("f10")
            return cells[start + 2 : start + 5]

        _until(lambda: shown() == [f"{float(library[f'f10_{x}'][0]):.4f}" for x in "ABC"])
        # the field beside the slider shows the same value (linked in the browser)
        assert page.evaluate("() => Bokeh.documents[0].get_model_by_name('x_field').value") == 0.031
    finally:
        page.close()


def test_a_singular_pose_shows_the_message_and_no_stale_picture(browser: Any, server: str) -> None:
    page = _open(browser, server)
    try:
        page.evaluate(_SET, ["phi", math.pi / 3.0])
        with pytest.raises(Prp3Error) as caught:
            pose_table(Robot(), State((0.0, 0.0, math.pi / 3.0)))
        message = "() => Bokeh.documents[0].get_model_by_name('message').text"
        _until(lambda: page.evaluate(message) != "")
        shown = page.locator("text=singular pose").first.inner_text()
        assert shown == str(caught.value)
        assert page.evaluate(_READ, "arrows")["quantity"] == []
        assert page.evaluate(_READ, "platform")["xs"] == []
        assert page.evaluate(_READ, "overlay")["image"] == []  # no map of another φ
        assert len(page.evaluate(_READ, "base")["xs"]) == 1  # the fixed base stays
        page.evaluate(_SET, ["phi", 0.1])  # a regular pose again: drawn, the message gone
        _until(lambda: page.evaluate(message) == "")
        assert _matches(page, _expected(pose_table(Robot(), State((0.0, 0.0, 0.1))), 0))
    finally:
        page.close()


def test_a_design_parameter_updates_the_forces_live(browser: Any, server: str) -> None:
    page = _open(browser, server)
    try:
        page.evaluate(_SET, ["design:payload.mass", 2.5])
        robot = Robot.from_mapping({"payload": {"mass": 2.5}})
        _until(lambda: _matches(page, _expected(pose_table(robot, State()), 0)))
        assert len(page.evaluate(_READ, "payload")["x"]) == 1
    finally:
        page.close()


def test_the_scrubber_shows_the_run_s_forces(
    browser: Any, run_server: str, run_folder: Path
) -> None:
    table = read_run(run_folder).table
    page = _open(browser, run_server)
    try:
        for k in (17, 45):
            page.evaluate(_SET, ["time", k])
            expected = _expected(table, k)
            _until(
                lambda expected=expected: all(  # type: ignore[misc]
                    np.allclose(
                        _forces(page.evaluate(_READ, "arrows"), name), value, rtol=1e-9, atol=1e-9
                    )
                    for name, value in expected.items()
                )
            )
        assert page.evaluate("() => Bokeh.documents[0].get_model_by_name('phi').value") == (
            pytest.approx(float(table["phi"][45]), abs=1e-15)
        )
    finally:
        page.close()


def test_the_exported_html_opens_offline_and_plays(
    browser: Any, run_folder: Path, tmp_path: Path
) -> None:
    page_file = tmp_path / "rot.html"
    run_prp3("explore", "--results", str(run_folder), "--export", str(page_file))
    table = read_run(run_folder).table
    frames = frame_indices(int(table["t"].size), 200)
    context = browser.new_context(offline=True)
    requested: list[str] = []

    def refuse(route: Any) -> None:
        if not route.request.url.startswith("file://"):
            requested.append(route.request.url)
            route.abort()
        else:
            route.continue_()

    context.route("**/*", refuse)
    page = context.new_page()
    try:
        page.goto(page_file.as_uri())
        page.wait_for_function("() => window.Bokeh && Bokeh.documents.length > 0", timeout=30_000)
        assert _matches(page, _expected(table, int(frames[0])))
        page.locator("button", has_text="play").click()
        read = """() => {
          const doc = Bokeh.documents[0];
          const k = doc.get_model_by_name('time').value;
          const data = doc.get_model_by_name('arrows').data;
          const d = data instanceof Map ? Object.fromEntries(data) : data;
          return [k, Object.fromEntries(Object.entries(d).map(([c, v]) => [c, Array.from(v)]))];
        }"""
        page.wait_for_function(
            "() => Bokeh.documents[0].get_model_by_name('time').value >= 5", timeout=20_000
        )
        page.locator("button", has_text="pause").click()
        k, arrows = page.evaluate(read)
        assert k >= 5
        for name, value in _expected(table, int(frames[k])).items():
            np.testing.assert_allclose(_forces(arrows, name), value, rtol=1e-12, atol=1e-12)
        cells = page.locator(".slick-cell").all_inner_texts()
        start = cells.index("f21z")
        assert cells[start + 2 : start + 5] == [
            f"{float(table[f'f21z_{x}'][frames[k]]):.4f}" for x in "ABC"
        ]
        assert requested == []
    finally:
        context.close()


# ---------------------------------------------------------------- a family robot (3-RRR)
@pytest.fixture(scope="module")
def rrr_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    from prp3.family import FamilyRobot

    path = tmp_path_factory.mktemp("family") / "rrr.toml"
    path.write_text(FamilyRobot.default("3-RRR").to_toml(), encoding="utf-8")
    with explore_server("--robot", str(path)) as (url, _):
        yield url


def test_a_3rrr_page_draws_the_library_s_joint_forces_after_a_slider_move(
    browser: Any, rrr_server: str
) -> None:
    from prp3.family import FamilyRobot, family_inverse_dynamics, family_kinematics

    robot = FamilyRobot.default("3-RRR")

    def library(state: State) -> tuple[np.ndarray, Any]:
        motion = Motion(t=np.zeros(()), pose=np.array(state.pose),
                        velocity=np.array(state.velocity),
                        acceleration=np.array(state.acceleration))  # fmt: skip
        # the Newton-Euler route: not the one the page solves with
        return family_inverse_dynamics(robot, motion, method="newton-euler").force, (
            family_kinematics(robot, motion)
        )

    def drawn(page: Any) -> np.ndarray | None:
        arrows = page.evaluate(_READ, "arrows")
        if not arrows["quantity"]:
            return None
        return np.stack([_forces(arrows, f"F{k}") for k in (1, 2, 3)], axis=1)  # (legs, k, 2)

    page = _open(browser, rrr_server)
    try:
        force, _ = library(State())
        first = drawn(page)
        assert first is not None and np.allclose(first, force, rtol=1e-9, atol=1e-9)
        revolute = page.evaluate(_READ, "revolute")
        assert len(revolute["x"]) == 9 and page.evaluate(_READ, "sliders")["xs"] == []
        settings = {"x": 0.02, "y": -0.015, "phi": 0.1, "dphi": 0.5, "ddx": 2.0}
        for name, value in settings.items():
            page.evaluate(_SET, [name, value])
        state = State.from_controls(settings)
        force, kin = library(state)

        def moved() -> bool:
            now = drawn(page)
            return now is not None and bool(np.allclose(now, force, rtol=1e-9, atol=1e-9))

        _until(moved)
        measures = page.evaluate(_READ, "measures")
        np.testing.assert_allclose(measures["value"], [*kin.mu_leg, kin.mu_par], atol=1e-12)
        # an unreachable pose: the library's line, and nothing drawn but the base
        page.evaluate(_SET, ["x", 0.18])
        message = "() => Bokeh.documents[0].get_model_by_name('message').text"
        _until(lambda: page.evaluate(message) != "")
        assert "cannot reach the pose" in page.evaluate(message)
        assert page.evaluate(_READ, "arrows")["quantity"] == []
        assert page.evaluate(_READ, "revolute")["x"] == []
        assert page.errors == []
    finally:
        page.close()


@pytest.fixture(scope="module")
def rrr_run_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, Path]]:
    from prp3.family import FamilyRobot

    folder = tmp_path_factory.mktemp("family_run")
    path = folder / "rrr.toml"
    path.write_text(FamilyRobot.default("3-RRR").to_toml(), encoding="utf-8")
    run_prp3("simulate", "--robot", str(path), "--motion", "rotation", "--samples", "41",
             "--output", str(folder / "run"))  # fmt: skip
    with explore_server("--robot", str(path), "--results", str(folder / "run")) as (url, _):
        yield url, folder / "run"


def test_the_scrubber_of_a_3rrr_run_draws_the_run_s_forces_and_plays(
    browser: Any, rrr_run_server: tuple[str, Path]
) -> None:
    from prp3.explorer.run_folder import read_family_run

    url, folder = rrr_run_server
    table = read_family_run(folder).table

    def run_forces(k: int) -> np.ndarray:  # (legs, joints k, 2), the run's own columns
        return np.array(
            [
                [[float(table[f"f{c}{j}_{leg}"][k]) for c in "xy"] for j in (1, 2, 3)]
                for leg in "ABC"
            ]
        )

    def drawn(page: Any) -> np.ndarray | None:
        arrows = page.evaluate(_READ, "arrows")
        if not arrows["quantity"]:
            return None
        return np.stack([_forces(arrows, f"F{j}") for j in (1, 2, 3)], axis=1)

    def shows(page: Any, k: int) -> bool:
        now = drawn(page)
        return now is not None and bool(np.allclose(now, run_forces(k), rtol=1e-9, atol=1e-9))

    page = _open(browser, url)
    try:
        _until(lambda: shows(page, 0))
        for k in (13, 32):
            page.evaluate(_SET, ["time", k])
            _until(lambda k=k: shows(page, k))  # type: ignore[misc]
            assert page.evaluate(
                "() => Bokeh.documents[0].get_model_by_name('phi').value"
            ) == pytest.approx(float(table["phi"][k]), abs=1e-15)
        # the linked plots' time lines follow the scrubber
        spans = """() => [...Bokeh.documents[0]._all_models.values()]
          .filter((m) => m.type === "Span").map((m) => m.location)"""
        assert page.evaluate(spans) == [pytest.approx(float(table["t"][32]), abs=1e-15)] * 4
        page.locator("button", has_text="play").click()
        page.wait_for_function(
            "() => Bokeh.documents[0].get_model_by_name('time').value != 32", timeout=20_000
        )
        page.evaluate("() => { Bokeh.documents[0].get_model_by_name('play').active = false }")
        page.wait_for_function(
            "() => Bokeh.documents[0].get_model_by_name('play').label.includes('play')"
        )
        time.sleep(0.5)  # a step the server had begun is drawn
        k = int(page.evaluate("() => Bokeh.documents[0].get_model_by_name('time').value"))
        _until(lambda: shows(page, k))
        assert page.errors == []
    finally:
        page.close()
