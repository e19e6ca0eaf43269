"""The explorer without a browser: its data functions, the HTML file of a run, the command line.

The arrows the page draws are checked against physics rebuilt outside the
explorer: the forces on each piston and on the platform, read back from the
arrows, must balance the bodies' inertia and weight (Newton's second law,
with the joint rates of ``tests/strategies.py``), and the tails must sit at
the joints of the reference geometry.  The browser tests are
``tests/test_explore_browser.py``.
"""

from __future__ import annotations

import math
import os
import re
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from browsertools import free_port, prp3_env
from clitools import cli, one_line
from prp3 import Robot
from prp3.analysis.inverse_dynamics import inverse_dynamics
from prp3.errors import InputFileError, ParameterError, Prp3Error, SingularPoseError
from prp3.explorer.run_folder import read_run, run_motion
from prp3.explorer.scene import (
    DESIGN_PARAMETERS,
    State,
    arrow_scale,
    design_robot,
    design_values,
    empty_view,
    pose_table,
    scene_view,
    singularity_curve,
    stroke_bands,
    workspace_overlay,
)
from prp3.model.motion import Motion, paper_motion
from prp3.model.parameters import Limits, Payload
from strategies import REF_E, REF_N, ref_geometry, ref_joint, ref_rates, ref_slide, robots

pytest.importorskip("bokeh", reason="the explorer needs Bokeh (pip install 'prp3[explore]')")


finite = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)


def _arrows(view_arrows: dict[str, list[object]], quantity: str) -> np.ndarray:
    rows = [k for k, q in enumerate(view_arrows["quantity"]) if q == quantity]
    assert [view_arrows["leg"][k] for k in rows] == ["A", "B", "C"]
    return np.array([[view_arrows["fx"][k], view_arrows["fy"][k]] for k in rows], dtype=float)


@settings(max_examples=40, deadline=None)
@given(
    robot=robots(offsets=False),
    q=st.tuples(st.floats(-0.3, 0.3), st.floats(-0.3, 0.3), st.floats(-1.7, 0.7)),
    rates=st.lists(finite, min_size=6, max_size=6),
)
def test_the_arrows_balance_every_piston_and_the_platform(
    robot: Robot, q: tuple[float, float, float], rates: list[float]
) -> None:
    pose = np.array([q[0] * robot.l0, q[1] * robot.l0, q[2]])
    velocity = np.array(rates[:3]) * np.array([robot.l0, robot.l0, 1.0])
    acceleration = 5.0 * np.array(rates[3:]) * np.array([robot.l0, robot.l0, 1.0])
    state = State(tuple(pose), tuple(velocity), tuple(acceleration))  # type: ignore[arg-type]
    scale = 1e-3
    view = scene_view(robot, pose_table(robot, state), 0, scale)
    arrows = view.arrows
    f10, f21, n10, n32 = (_arrows(arrows, name) for name in ("f10", "f21", "n10", "n32"))
    ref = ref_geometry(robot.l0, pose)
    rate = ref_rates(robot.l0, pose, velocity, acceleration)
    g = np.array(robot.gravity)
    size = 1.0 + np.abs(np.concatenate([f10, f21, n10, n32])).max()
    # piston i translates along e_i: f10 + n10 − f21 + m1·g = m1·λ̈10·e_i (the force of link 2
    # on the piston is −f21; f10 along e, n10 along n, as the arrows must be drawn)
    m1 = robot.piston.mass
    inertia = m1 * (rate.ddlambda10[:, None] * REF_E - g)
    np.testing.assert_allclose(f10 + n10 - f21, inertia, rtol=0, atol=1e-9 * size)
    np.testing.assert_allclose(np.einsum("ij,ij->i", f10, REF_N), 0.0, atol=1e-9 * size)
    np.testing.assert_allclose(np.einsum("ij,ij->i", n10, REF_E), 0.0, atol=1e-9 * size)
    # the platform (mass centre at G): Σ n32_i·d⊥_i + m3·g = m3·a_G; n32 normal to d_i
    m3 = robot.platform.mass
    np.testing.assert_allclose(
        n32.sum(axis=0), m3 * (acceleration[:2] - g), rtol=0, atol=1e-9 * size
    )
    np.testing.assert_allclose(
        np.einsum("ij,ij->i", n32, ref_slide(pose[2])), 0.0, atol=1e-9 * size
    )
    # every tail at its joint P_i of the reference geometry, every head scale·F further
    for k, leg in enumerate(arrows["leg"]):
        j = "ABC".index(str(leg))
        tail = np.array([arrows["x0"][k], arrows["y0"][k]], dtype=float)
        head = np.array([arrows["x1"][k], arrows["y1"][k]], dtype=float)
        force = np.array([arrows["fx"][k], arrows["fy"][k]], dtype=float)
        np.testing.assert_allclose(tail, ref.joint[j], rtol=0, atol=1e-12 * robot.l0)
        np.testing.assert_allclose(head - tail, scale * force, rtol=1e-12, atol=1e-15)
        assert math.isclose(arrows["value"][k], float(np.hypot(*force)), rel_tol=1e-12)  # type: ignore[arg-type]
    # the drawn joints and bars
    np.testing.assert_allclose(view.shapes["joints"]["x"], ref.joint[:, 0], atol=1e-12)
    np.testing.assert_allclose(view.shapes["joints"]["y"], ref.joint[:, 1], atol=1e-12)


def test_the_table_holds_the_independent_newton_euler_values() -> None:
    robot = Robot(payload=Payload(mass=1.5, com=(0.02, -0.01), inertia=1e-3))
    state = State((0.02, -0.03, 0.2), (0.1, -0.2, 0.5), (1.0, 2.0, -3.0))
    view = scene_view(robot, pose_table(robot, state), 0, 1e-3)
    motion = Motion(
        t=np.zeros(1),
        pose=np.array([state.pose]),
        velocity=np.array([state.velocity]),
        acceleration=np.array([state.acceleration]),
    )
    _, reference = inverse_dynamics(robot, motion, method="newton-euler")
    table = view.table
    for name in ("f10", "f21y", "f21z", "n10", "m10", "n32", "m32", "p10"):
        row = table["quantity"].index(name)
        values = [table[leg][row] for leg in "ABC"]
        expected = getattr(reference, name)[0]
        np.testing.assert_allclose(values, expected, rtol=1e-9, atol=1e-9)
    # the payload is drawn at G + Rot(φ)·com
    c, s = math.cos(0.2), math.sin(0.2)
    centre = (0.02 + c * 0.02 + s * 0.01, -0.03 + s * 0.02 - c * 0.01)
    assert view.shapes["payload"]["x"] == pytest.approx([centre[0]], abs=1e-15)
    assert view.shapes["payload"]["y"] == pytest.approx([centre[1]], abs=1e-15)


def test_friction_adds_its_arrows_along_the_joints() -> None:
    robot = design_robot(
        Robot(), {"friction.actuator.viscous": 5.0, "friction.sleeve.viscous": 3.0}
    )
    state = State((0.01, 0.02, 0.1), (0.2, -0.1, 0.4), (0.0, 0.0, 0.0))
    table = pose_table(robot, state)
    arrows = scene_view(robot, table, 0, 1e-3).arrows
    fric10, fric32 = _arrows(arrows, "fric10"), _arrows(arrows, "fric32")
    ref = ref_geometry(robot.l0, state.pose)
    rate = ref_rates(robot.l0, state.pose, state.velocity, state.acceleration)
    # viscous only: −b·v along the joint (docs/loads_and_friction.md)
    np.testing.assert_allclose(fric10, -5.0 * rate.dlambda10[:, None] * REF_E, atol=1e-12)
    np.testing.assert_allclose(fric32, -3.0 * rate.dlambda32[:, None] * ref.slide, atol=1e-12)
    assert set(arrows["quantity"]) == {"f10", "f21", "n10", "n32", "fric10", "fric32"}


def test_a_singular_pose_is_the_library_s_error_and_draws_nothing() -> None:
    with pytest.raises(SingularPoseError) as caught:
        pose_table(Robot(), State((0.0, 0.0, math.pi / 3.0)))
    assert "singular pose" in str(caught.value)
    view = scene_view(Robot(), pose_table(Robot(), State()), 0, 1e-3)
    blank = empty_view(view)
    assert all(not column for source in blank.sources().values() for column in source.values())
    assert {k: set(v) for k, v in blank.sources().items()} == {
        k: set(v) for k, v in view.sources().items()
    }


def test_an_unreachable_pose_names_the_stroke() -> None:
    robot = Robot(limits=Limits(stroke=(-0.05, 0.05)))
    with pytest.raises(Prp3Error, match=r"outside the stroke \[-0.05, 0.05\] m"):
        pose_table(robot, State((0.15, 0.0, 0.0)))


def test_the_stroke_bands_run_between_the_joints_at_both_ends() -> None:
    robot = Robot(l0=0.4, limits=Limits(stroke=(-0.03, 0.07)))
    bands = stroke_bands(robot)
    for j in range(3):
        low = ref_joint(0.4, np.full(3, -0.03))[j]
        high = ref_joint(0.4, np.full(3, 0.07))[j]
        np.testing.assert_allclose(bands["xs"][j], [low[0], high[0]], atol=1e-15)
        np.testing.assert_allclose(bands["ys"][j], [low[1], high[1]], atol=1e-15)
    assert stroke_bands(Robot())["xs"] == []


def test_the_overlay_is_the_statics_map_within_the_strokes() -> None:
    robot = Robot(limits=Limits(stroke=(-0.04, 0.06)), payload=Payload(mass=1.0))
    overlay = workspace_overlay(robot, 0.3, 21)
    image = np.asarray(overlay["image"]["image"][0])
    grid = np.linspace(-0.18, 0.18, 21)
    X, Y = np.meshgrid(grid, grid)
    pose = np.stack([X, Y, np.full_like(X, 0.3)], axis=-1)
    lam = ref_geometry(0.3, pose).lambda10
    inside = ((lam >= -0.04) & (lam <= 0.06)).all(axis=-1)
    assert np.array_equal(np.isfinite(image), inside)
    # at a reachable grid pose, the largest actuator force of the statics (independent method)
    k = tuple(np.argwhere(inside)[len(np.argwhere(inside)) // 2])
    rest = np.zeros((1, 3))
    _, held = inverse_dynamics(
        robot, Motion(t=np.zeros(1), pose=pose[k][None], velocity=rest, acceleration=rest),
        method="newton-euler",
    )  # fmt: skip
    assert image[k] == pytest.approx(float(np.abs(held.f10).max()), rel=1e-9)
    assert overlay["image"]["dw"][0] == pytest.approx(0.36 + 0.018)


def test_the_singularity_curve_is_sin_phi_minus_pi_over_3() -> None:
    curve = singularity_curve((-1.0, 2.0), 31)
    np.testing.assert_allclose(curve["measure"], np.sin(np.linspace(-1, 2, 31) - math.pi / 3))


def test_the_arrow_scale_draws_the_largest_statics_force_at_a_third_of_l0() -> None:
    robot = Robot(l0=0.5)
    table = pose_table(robot, State())
    peak = max(
        abs(float(table[f"{q}_{leg}"][0]))
        for q in ("f10", "f21y", "f21z", "n10", "n32")
        for leg in "ABC"
    )
    assert arrow_scale(robot) * peak == pytest.approx(0.35 * 0.5)
    assert arrow_scale(Robot(gravity=(0.0, 0.0))) == pytest.approx(0.35 * 0.3)


@pytest.mark.parametrize("key", list(DESIGN_PARAMETERS))
def test_each_design_parameter_changes_only_itself(key: str) -> None:
    robot = Robot()
    before = design_values(robot)
    changed = design_robot(robot, {key: before[key] + 0.25})
    after = design_values(changed)
    assert after[key] == before[key] + 0.25
    assert {k: v for k, v in after.items() if k != key} == {
        k: v for k, v in before.items() if k != key
    }
    assert design_robot(robot, {key: before[key]}) == robot  # no [friction] made for zeros


def test_a_bad_design_value_is_refused_naming_its_key() -> None:
    with pytest.raises(ParameterError, match=r"payload\.mass"):
        design_robot(Robot(), {"payload.mass": -1.0})
    with pytest.raises(ParameterError, match=r"friction\.sleeve\.mu"):
        design_robot(Robot(), {"friction.sleeve.mu": math.nan})
    with pytest.raises(Prp3Error, match=r"unknown design parameter 'platform\.colour'"):
        design_robot(Robot(), {"platform.colour": 1.0})


# ---------------------------------------------------------------- runs
@pytest.fixture(scope="module")
def rotation_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("runs") / "rot"
    from prp3.cli import main

    assert (
        main(["simulate", "--motion", "rotation", "--samples", "41", "--output", str(folder)]) == 0
    )
    return folder


@pytest.mark.parametrize("form", ["csv", "parquet"])
def test_a_run_is_read_and_its_motion_recovered(tmp_path: Path, form: str) -> None:
    pytest.importorskip("pyarrow")
    from prp3.cli import main

    folder = tmp_path / form
    with open(os.devnull, "w") as sink:
        import contextlib

        with contextlib.redirect_stdout(sink):
            status = main(["simulate", "--motion", "rotation", "--samples", "41",
                           "--format", form, "--output", str(folder)])  # fmt: skip
    assert status == 0
    run = read_run(folder)
    assert run.path.name == f"results.{form}" and run.samples == 41
    motion = run_motion(Robot(), run)
    paper = paper_motion("rotation", 41)
    np.testing.assert_allclose(motion.pose, paper.pose, atol=1e-15)
    np.testing.assert_allclose(motion.velocity, paper.velocity, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(motion.acceleration, paper.acceleration, rtol=1e-9, atol=1e-10)
    # drawn from its own columns, sample 20 shows the run's forces
    view = scene_view(Robot(), run.table, 20, 1e-3)
    row = view.table["quantity"].index("f21z")
    assert [view.table[leg][row] for leg in "ABC"] == [
        run.table[f"f21z_{leg}"][20] for leg in "ABC"
    ]


def test_a_run_of_another_robot_is_refused(rotation_run: Path) -> None:
    with pytest.raises(InputFileError, match=r"give the --robot of the run") as caught:
        run_motion(Robot(l0=0.31), read_run(rotation_run))
    assert caught.value.sample == 1 and "results.csv" in str(caught.value)


def test_folders_without_results_are_refused(tmp_path: Path) -> None:
    with pytest.raises(InputFileError, match="not a folder"):
        read_run(tmp_path / "missing")
    with pytest.raises(InputFileError, match=r"no results\.csv or results\.parquet"):
        read_run(tmp_path)
    (tmp_path / "results.csv").write_text("t,x\n0,1\n")
    with pytest.raises(InputFileError, match=r"results\.csv.*missing column"):
        read_run(tmp_path)


def test_a_truncated_parquet_run_is_named_truncated(tmp_path: Path) -> None:
    pytest.importorskip("pyarrow")
    from prp3.cli import main

    folder = tmp_path / "run"
    argv = ["simulate", "--motion", "rotation", "--samples", "41", "--format", "parquet"]
    assert main([*argv, "--output", str(folder)]) == 0
    whole = (folder / "results.parquet").read_bytes()
    (folder / "results.parquet").write_bytes(whole[: len(whole) // 2])
    with pytest.raises(InputFileError, match=r"results\.parquet.*truncated: a Parquet file cut"):
        read_run(folder)
    (folder / "results.parquet").write_bytes(b"not parquet at all")
    with pytest.raises(InputFileError, match="not a Parquet file"):
        read_run(folder)


# ---------------------------------------------------------------- HTML file of a run
def test_simulate_html_writes_one_self_contained_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    page = tmp_path / "run.html"
    status, out, err = cli(capsys, "simulate", "--motion", "vertical", "--samples", "31",
                           "--output", tmp_path / "out", "--html", page)  # fmt: skip
    assert status == 0, err
    assert f"html file written: {page}" in out
    text = page.read_text(encoding="utf-8")
    assert "<script" in text and "Bokeh" in text
    # Bokeh inline (INLINE resources): no script or style sheet loaded from elsewhere (the
    # browser test opens it with the network off)
    assert not re.search(r"<script[^>]*\bsrc=", text) and not re.search(r"<link[^>]*\bhref=", text)
    assert [p.name for p in tmp_path.iterdir() if p.is_file()] == ["run.html"]


def test_explore_export_writes_only_its_file(
    tmp_path: Path, rotation_run: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    page = tmp_path / "rot.html"
    before = sorted(p.name for p in rotation_run.iterdir())
    status, out, err = cli(capsys, "explore", "--results", rotation_run, "--export", page)
    assert (status, err) == (0, "")
    assert out.strip() == f"prp3 explore: wrote {page}"
    assert (
        page.stat().st_size > 100_000 and sorted(p.name for p in rotation_run.iterdir()) == before
    )


def test_a_failed_html_leaves_no_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    page = tmp_path / "missing" / "run.html"
    status, _, err = cli(capsys, "explore", "--export", page)
    assert status == 2 and "run.html" in one_line(err)
    assert not page.exists() and list(tmp_path.iterdir()) == []


# ---------------------------------------------------------------- command line errors
def test_a_robot_file_that_does_not_parse_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    robot = tmp_path / "robot.toml"
    robot.write_text("l0 = -1\n")
    status, out, err = cli(capsys, "explore", "--robot", robot, "--no-browser", "--port", 1)
    assert status == 2 and out == ""
    assert one_line(err).startswith("prp3 explore: error: ") and "l0" in err


def test_a_results_folder_that_does_not_parse_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "results.csv").write_text("t,x\n0,1\n")
    status, out, err = cli(capsys, "explore", "--results", tmp_path, "--no-browser")
    assert status == 2 and out == ""
    line = one_line(err)
    assert line.startswith("prp3 explore: error: ") and "results.csv" in line


def test_a_run_of_another_robot_is_one_line(
    tmp_path: Path, rotation_run: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    robot = tmp_path / "robot.toml"
    robot.write_text("l0 = 0.35\n")
    status, _, err = cli(capsys, "explore", "--robot", robot, "--results", rotation_run)
    assert status == 2 and "give the --robot of the run" in one_line(err)


def test_a_busy_port_is_one_line_naming_it(capsys: pytest.CaptureFixture[str]) -> None:
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        status, out, err = cli(capsys, "explore", "--no-browser", "--port", port)
    assert status == 2 and out == ""
    assert one_line(err) == (
        f"prp3 explore: error: --port {port}: port {port} on 127.0.0.1 is busy (another program "
        "listens there): choose another with --port"
    )


def test_a_bad_port_is_a_usage_error(capsys: pytest.CaptureFixture[str]) -> None:
    status, _, err = cli(capsys, "explore", "--port", "70000")
    assert status == 2 and one_line(err).startswith("prp3 explore: error: argument --port")


@pytest.mark.slow  # a server in a subprocess
def test_ctrl_c_stops_the_server_with_130_and_writes_nothing(tmp_path: Path) -> None:
    port = free_port()
    server = subprocess.Popen(
        [sys.executable, "-m", "prp3", "explore", "--no-browser", "--port", str(port)],
        cwd=tmp_path, env=prp3_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert server.stdout is not None
        line = server.stdout.readline()
        assert line.strip() == f"prp3 explore: serving http://127.0.0.1:{port}/ (Ctrl-C stops)"
        with socket.create_connection(("127.0.0.1", port), timeout=60) as client:
            client.sendall(b"GET / HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n")
            reply = client.recv(64)
        assert reply.startswith(b"HTTP/1.1 200")
        time.sleep(0.2)
        server.send_signal(signal.SIGINT)
        out, err = server.communicate(timeout=30)
    finally:
        if server.poll() is None:
            server.kill()
            server.communicate()
    assert server.returncode == 130
    assert (out, err) == ("", "prp3 explore: interrupted\n")
    assert list(tmp_path.iterdir()) == []


def test_a_design_edit_is_the_robot_file_with_that_value() -> None:
    """Every design field but friction's (tested above) gives the robot its ROBOT.toml gives
    with that value, read by the TOML reader: the independent route to the edit."""
    import tomllib

    robot = Robot()
    before = design_values(robot)
    component = {"x": 0, "y": 1}
    for key in (k for k in DESIGN_PARAMETERS if not k.startswith("friction.")):
        defaults = {"payload": {"mass": 0.0, "com": [0.0, 0.0], "inertia": 0.0},
                    "load": {"force": [0.0, 0.0], "moment": 0.0}}  # fmt: skip
        value = before[key] + 0.01
        data = tomllib.loads(robot.to_toml())
        *path, last = key.split(".")
        where: Any = data
        for part in path:
            where = where.setdefault(part, defaults.get(part, {}))
        if isinstance(where, list):
            where[component[last]] = value
        else:
            where[last] = value
        assert design_robot(robot, {key: value}) == Robot.from_mapping(data), key
