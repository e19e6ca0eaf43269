"""The workspace statics map (``prp3.analysis.workspace.workspace_statics``, ``prp3 workspace``).

Expected values are not taken from the code under test:

* at the central pose the statics is derived by hand below (free bodies of
  link 2, the piston and the platform with its payload);
* at random poses the Newton–Euler solver (21 balances of the 7 bodies,
  independent of the kernel) at zero velocity and acceleration;
* the CLI's files against the library and the hand rules of ``held``.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from prp3 import Limits, Robot, inverse_dynamics
from prp3.analysis.workspace import workspace_slice, workspace_statics
from prp3.cli import main
from prp3.cli.workspace import wants_statics
from prp3.errors import SingularPoseError
from prp3.model.motion import Motion
from prp3.model.parameters import Friction, JointFriction, Load, Payload
from strategies import poses, robots

STATICS_COLUMNS = "x,y,reachable,f10_A,f10_B,f10_C,f10_peak,held".split(",")


def hand_statics_at_the_centre(
    l0: float,
    gravity: tuple[float, float],
    masses: tuple[float, float, float],
    payload: tuple[float, tuple[float, float]],
    load: tuple[tuple[float, float], float],
) -> np.ndarray:
    """``f10`` holding the central pose ``x = y = φ = 0`` at rest, by hand.

    Geometry (docs/model.md): ``α = (π/3, π, −π/3)``, ``e_i = (cos α_i, sin α_i)``,
    ``d_i`` at angle ``α_i − π/3`` (``φ = 0``), ``d⊥_i = J·d_i``.  At the centre
    ``λ10 = λ32 = 0`` and the closure ``G = P_i + λ32_i·d_i + Rot(α_i)·c`` gives
    ``P_i − G = −Rot(α_i)·c``, ``c = (l0/2)·(1/√3, 1)``.

    Free bodies at rest, the legs' mass centres at ``P_i`` (``c1 = c2 = 0``):

    * link 2 of leg i: the pin force ``F21_i`` of the piston at ``P_i``, its
      weight ``m2·g`` at ``P_i`` and the sleeve's reaction.  The first two
      have no moment about ``P_i``, so neither has the reaction: without
      friction it is a force normal to ``d_i`` through ``P_i``.  Call
      ``t_i·d⊥_i`` the force link 2 exerts on the platform; then
      ``F21_i = t_i·d⊥_i − m2·g``.
    * piston i: along ``e_i`` (the guide's reaction is normal to it)
      ``f10_i + m1·g·e_i − F21_i·e_i = 0``, so
      ``f10_i = t_i·(d⊥_i·e_i) − (m1 + m2)·g·e_i``.
    * platform with its payload (mass ``mp`` at ``c_p`` from ``G``; the
      platform frame is the fixed one at ``φ = 0``): forces
      ``Σ t_i·d⊥_i + (m3 + mp)·g + F = 0``, moments about ``G``
      ``Σ t_i·(P_i − G) × d⊥_i + mp·c_p × g + M = 0``: three linear equations
      for ``t_A, t_B, t_C``.
    """
    m1, m2, m3 = masses
    mp, (cpx, cpy) = payload
    (fx, fy), moment = load
    g = np.array(gravity)
    alpha = np.array([math.pi / 3.0, math.pi, -math.pi / 3.0])
    e = np.stack([np.cos(alpha), np.sin(alpha)], axis=-1)
    d = np.stack([np.cos(alpha - math.pi / 3.0), np.sin(alpha - math.pi / 3.0)], axis=-1)
    d_perp = np.stack([-d[:, 1], d[:, 0]], axis=-1)
    c = 0.5 * l0 * np.array([1.0 / math.sqrt(3.0), 1.0])
    lever = -np.stack([np.cos(alpha) * c[0] - np.sin(alpha) * c[1],
                       np.sin(alpha) * c[0] + np.cos(alpha) * c[1]], axis=-1)  # P_i − G  # fmt: skip
    cross = lever[:, 0] * d_perp[:, 1] - lever[:, 1] * d_perp[:, 0]
    system = np.array([d_perp[:, 0], d_perp[:, 1], cross])
    weight = (m3 + mp) * g
    rhs = -np.array([weight[0] + fx, weight[1] + fy, mp * (cpx * g[1] - cpy * g[0]) + moment])
    t = np.linalg.solve(system, rhs)
    return np.asarray(t * (d_perp * e).sum(axis=-1) - (m1 + m2) * (e @ g))


def test_the_hand_statics_reproduces_the_papers_central_forces() -> None:
    # the derivation itself, on the paper's robot: f10 = (31.8589, −8.4957, −23.3632) N
    # (t = (2/3)·m3·9.81·(1, −1/2, −1/2), d⊥·e = √3/2, g·e = −9.81·(√3/2, 0, −√3/2))
    f10 = hand_statics_at_the_centre(0.3, (0.0, -9.81), (1.0, 0.75, 3.0), (0.0, (0.0, 0.0)),
                                     ((0.0, 0.0), 0.0))  # fmt: skip
    h = math.sqrt(3.0) / 2.0
    expected = [h * 19.62 + 1.75 * 9.81 * h, -h * 9.81, -h * 9.81 - 1.75 * 9.81 * h]
    np.testing.assert_allclose(f10, expected, rtol=1e-14)


@pytest.mark.parametrize(
    ("gravity", "payload", "load"),
    [
        ((0.0, -9.81), (0.5, (0.0, 0.0)), ((0.0, 0.0), 0.0)),
        ((0.0, -9.81), (0.5, (0.02, -0.01)), ((3.0, -5.0), 0.4)),
        ((2.0, -7.0), (1.5, (-0.03, 0.05)), ((-1.0, 2.0), -0.25)),
        ((0.0, 0.0), (0.0, (0.0, 0.0)), ((0.0, -20.0), 1.0)),  # a horizontal table, a pure load
    ],
)
def test_statics_at_the_centre_by_hand(
    gravity: tuple[float, float],
    payload: tuple[float, tuple[float, float]],
    load: tuple[tuple[float, float], float],
) -> None:
    robot = Robot(
        gravity=gravity,
        payload=Payload(mass=payload[0], com=payload[1], inertia=1e-3),
        load=Load(force=load[0], moment=load[1]),
        limits=Limits(stroke=(-0.05, 0.05)),
    )
    grid = np.linspace(-0.04, 0.04, 9)  # the centre is grid point (4, 4)
    statics = workspace_statics(robot, 0.0, grid, grid)
    expected = hand_statics_at_the_centre(0.3, gravity, (1.0, 0.75, 3.0), payload, load)
    scale = np.abs(expected).max()
    np.testing.assert_allclose(statics.f10[4, 4], expected, rtol=0, atol=1e-13 * scale)
    assert statics.peak[4, 4] == pytest.approx(np.abs(expected).max(), rel=1e-13)


@st.composite
def loaded_robots(draw: st.DrawFn) -> Robot:
    base = draw(robots())
    floats = st.floats(-5.0, 5.0, allow_nan=False)
    coefficient = st.floats(0.0, 2.0, allow_nan=False)
    return Robot(
        l0=base.l0,
        gravity=base.gravity,
        piston=base.piston,
        link=base.link,
        platform=base.platform,
        payload=Payload(
            mass=draw(st.floats(0.0, 3.0)),
            com=(draw(floats) * 0.05 * base.l0, draw(floats) * 0.05 * base.l0),
            inertia=draw(st.floats(0.0, 0.1)),
        ),
        load=Load(force=(draw(floats) * 4.0, draw(floats) * 4.0), moment=draw(floats)),
        # friction vanishes at rest (s(0) = 0): it must change nothing
        friction=Friction(
            actuator=JointFriction(viscous=draw(coefficient), coulomb=draw(coefficient)),
            sleeve=JointFriction(coulomb=draw(coefficient), mu=draw(st.floats(0.0, 0.2))),
        ),
    )


@settings(max_examples=25, deadline=None)
@given(robot=loaded_robots(), data=st.data())
def test_statics_agrees_with_newton_euler_at_rest(robot: Robot, data: st.DataObject) -> None:
    pose = data.draw(poses(robot.l0))
    h = 1e-3 * robot.l0
    x = np.array([pose[0], pose[0] + h])
    y = np.array([pose[1] - h, pose[1]])
    statics = workspace_statics(robot, float(pose[2]), x, y)
    _, reference = inverse_dynamics(robot, Motion.at_rest(pose), method="newton-euler")
    scale = max(float(np.abs(reference.f10).max()), 1.0)
    np.testing.assert_allclose(statics.f10[1, 0], reference.f10, rtol=0, atol=1e-11 * scale)
    assert statics.peak[1, 0] == float(np.abs(statics.f10[1, 0]).max())


def test_held_and_the_unheld_fraction_follow_max_force() -> None:
    grid = np.linspace(-0.06, 0.06, 25)
    robot = Robot(payload=Payload(mass=0.5), limits=Limits(stroke=(-0.05, 0.05), max_force=35.0))
    statics = workspace_statics(robot, 0.1, grid, grid)
    ws = workspace_slice(robot, 0.1, grid, grid)
    np.testing.assert_array_equal(statics.reachable, ws.reachable)
    over = ws.reachable & (statics.peak > 35.0)
    assert over.any() and (ws.reachable & ~over).any()  # the limit splits the region
    np.testing.assert_array_equal(statics.held, ws.reachable & ~over)
    assert statics.unheld_fraction == over.sum() / ws.reachable.sum()
    unlimited = workspace_statics(Robot(payload=Payload(mass=0.5)), 0.1, grid, grid)
    assert unlimited.unheld_fraction is None and unlimited.held.all()
    np.testing.assert_array_equal(unlimited.f10, statics.f10)  # also outside the stroke


def test_statics_refuses_a_singular_orientation() -> None:
    with pytest.raises(SingularPoseError, match=r"phi = 1\.047"):
        workspace_statics(Robot(), math.pi / 3.0, [0.0, 0.1], [0.0, 0.1])


# ------------------------------------------------------------------ the command line
def run_cli(capsys: pytest.CaptureFixture[str], *argv: object) -> tuple[int, str, str]:
    try:
        status = main([str(a) for a in argv])
    except SystemExit as exit_:
        status = int(exit_.code or 0)
    out, err = capsys.readouterr()
    return status, out, err


def read_csv(path: Path) -> tuple[list[str], dict[str, np.ndarray]]:
    with path.open(newline="") as stream:
        rows = list(csv.reader(stream))
    values = np.array([[float(v) for v in row] for row in rows[1:]])
    return rows[0], {name: values[:, j] for j, name in enumerate(rows[0])}


ROBOT_TOML = """\
[payload]
mass = 0.5
com = [0.02, 0.0]

[load]
force = [0.0, -2.0]

[limits]
stroke = [-0.05, 0.05]
max_force = 36.0
"""


def test_workspace_writes_the_statics_map(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "robot.toml").write_text(ROBOT_TOML)
    out = tmp_path / "ws"
    status, stdout, stderr = run_cli(
        capsys, "workspace", "--robot", tmp_path / "robot.toml", "--points", 21,
        "--orientations", 5, "--phi", 0.2, "--output", out,
    )  # fmt: skip
    assert status == 0, stderr
    assert {"statics.csv", "statics.png"} <= {p.name for p in out.iterdir()}
    assert (out / "statics.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    header, table = read_csv(out / "statics.csv")
    assert header == STATICS_COLUMNS
    _, grid = read_csv(out / "workspace.csv")
    np.testing.assert_array_equal(table["x"], grid["x"])
    np.testing.assert_array_equal(table["reachable"], grid["reachable"])
    # the file's robot without its limits: f10 is written also outside the stroke
    free = Robot(payload=Payload(mass=0.5, com=(0.02, 0.0)), load=Load(force=(0.0, -2.0)))
    for k in range(0, table["x"].size, 37):  # every 37th grid point, by Newton–Euler
        pose = [table["x"][k], table["y"][k], 0.2]
        _, reference = inverse_dynamics(free, Motion.at_rest(pose), method="newton-euler")
        f10 = [table[f"f10_{leg}"][k] for leg in "ABC"]
        np.testing.assert_allclose(f10, reference.f10, rtol=0, atol=1e-12)
    peak = np.abs(np.stack([table[f"f10_{leg}"] for leg in "ABC"])).max(axis=0)
    np.testing.assert_array_equal(table["f10_peak"], peak)
    held = (table["reachable"] == 1.0) & (peak <= 36.0)
    np.testing.assert_array_equal(table["held"], held.astype(float))
    reachable = table["reachable"] == 1.0
    fraction = 1.0 - held.sum() / reachable.sum()
    assert 0.0 < fraction < 1.0
    assert f"above limits.max_force = 36 N (cannot hold its load): {100 * fraction:.4g} %" in stdout


def test_statics_is_optional(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # by default only for a robot with a payload, a load or max_force
    assert not wants_statics(Robot(), None)
    assert wants_statics(Robot(payload=Payload(mass=0.1)), None)
    assert wants_statics(Robot(load=Load(moment=1.0)), None)
    assert wants_statics(Robot(limits=Limits(max_force=10.0)), None)
    assert not wants_statics(Robot(limits=Limits(max_force=10.0)), False)
    (tmp_path / "robot.toml").write_text(ROBOT_TOML)
    common = ("--points", 5, "--orientations", 3)
    status, stdout, err = run_cli(
        capsys, "workspace", *common, "--statics", "--output", tmp_path / "asked"
    )
    assert status == 0, err  # the paper's robot, asked for: its own weight
    assert (tmp_path / "asked" / "statics.csv").is_file()
    assert "statics (at rest): largest |f10|" in stdout and "max_force" not in stdout
    status, _, err = run_cli(
        capsys, "workspace", "--robot", tmp_path / "robot.toml", *common, "--no-statics",
        "--output", tmp_path / "declined",
    )  # fmt: skip
    assert status == 0, err
    assert not (tmp_path / "declined" / "statics.png").exists()


@pytest.mark.parametrize(
    ("toml", "argv", "message"),
    [
        ("[payload]\nmass = -1.0\n", (), "payload.mass"),
        ("[load]\nforce = [1.0]\n", (), "load.force"),
        ("[payload]\nmass = 0.5\n", ("--phi", str(math.pi / 3.0)), "is singular"),
        ("[limits]\nmax_force = 0.0\n", ("--statics",), "max_force"),
    ],
)
def test_bad_statics_input_is_one_line_and_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], toml: str, argv: tuple[str, ...],
    message: str,
) -> None:  # fmt: skip
    (tmp_path / "robot.toml").write_text(toml)
    out = tmp_path / "ws"
    status, stdout, stderr = run_cli(
        capsys, "workspace", "--robot", tmp_path / "robot.toml", "--points", 5,
        "--orientations", 3, *argv, "--output", out,
    )  # fmt: skip
    assert status == 2 and stdout == ""
    assert len(stderr.strip().splitlines()) == 1 and message in stderr, stderr
    assert not out.exists() or not any(out.iterdir())


def test_the_statics_map_covers_nothing_and_says_what_it_plots() -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from prp3.plotting.workspace import statics_figure

    robot = Robot(payload=Payload(mass=0.5), limits=Limits(stroke=(-0.05, 0.05), max_force=35.0))
    grid = np.linspace(-0.06, 0.06, 31)
    statics = workspace_statics(robot, 0.0, grid, grid)
    figure = statics_figure(robot, statics)
    canvas = FigureCanvasAgg(figure)
    canvas.draw()
    renderer = canvas.get_renderer()
    ax, bar = figure.axes
    legend = ax.get_legend()
    assert not legend.get_window_extent(renderer).overlaps(ax.get_window_extent(renderer))
    labels = [text.get_text() for text in legend.get_texts()]
    assert "unreachable grid points" in labels
    assert any("cannot hold" in label for label in labels)
    assert any("max_force = 35 N" in label for label in labels)  # the contour
    assert "(N)" in bar.get_ylabel()
    fraction = statics.unheld_fraction
    assert fraction is not None and f"{100 * fraction:.3g} %" in ax.get_title()
    assert "payload 0.5 kg" in ax.get_title()


def test_the_spring_holds_its_share_at_rest() -> None:
    # at rest the spring pushes piston i with −k·(λ10_i − rest) along e_i: the statics map's
    # f10 is the robot's without the spring plus k·(λ10_i − rest), λ10 by the closed-form
    # inverse geometry; and prp3 workspace writes the map by default for it
    from prp3.cli.workspace import wants_statics
    from prp3.mechanics.geometry import inverse_geometry
    from prp3.model.parameters import Spring, SpringParameters

    robot = Robot(spring=Spring(SpringParameters(stiffness=600.0, rest=0.015, damping=9.0)))
    grid = np.linspace(-0.04, 0.04, 9)
    sprung, free = (
        workspace_statics(robot, 0.2, grid, grid),
        workspace_statics(Robot(), 0.2, grid, grid),
    )
    X, Y = np.meshgrid(grid, grid)
    pose = np.stack([X, Y, np.full_like(X, 0.2)], axis=-1)
    lambda10 = inverse_geometry(robot, pose.reshape(-1, 3)).lambda10.reshape(9, 9, 3)
    expected = 600.0 * (lambda10 - 0.015)
    np.testing.assert_allclose(sprung.f10 - free.f10, expected, rtol=0, atol=1e-12)
    assert wants_statics(robot, None) and not wants_statics(Robot(), None)
    damper_only = Robot(spring=Spring(SpringParameters(damping=9.0)))  # nothing at rest
    assert not wants_statics(damper_only, None)
