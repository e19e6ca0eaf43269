"""Workspace slices of the spatial robots (docs/spatial.md §17) against independent routes.

Reachability against the inverse geometry's own refusals point by point (and the
hexapod's leg lengths by hand), the parallel measure against the hexapod's closed
form ``(r_i × u_i, u_i)`` and, for the Delta and the 3-RPS, its sign against the
determinant of the actuated coordinates' finite differences over the robot's free
coordinates, the efforts at rest against the Newton–Euler route and against virtual
work (``τ·dq_act = dU`` along every free direction, the potential rebuilt from the
bodies' mass centres); ``prp3 workspace`` for each architecture and its refusals.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import fsolve

from clitools import cli, one_line
from prp3.errors import ParameterError, Prp3Error, UnreachablePoseError
from prp3.spatial.geometry import chain_frames, inverse_geometry, leg_coordinates, plane_offsets
from prp3.spatial.kinematics import complete_motion
from prp3.spatial.model import delta, hexapod, three_rps
from prp3.spatial.motion import PlatformMotion
from prp3.spatial.newton_euler import newton_euler_dynamics
from prp3.spatial.rotations import exp_rotation, rpy_matrix
from prp3.spatial.workspace import (
    SpatialWorkspace,
    spatial_statics_table,
    spatial_workspace,
    spatial_workspace_table,
)

ROBOTS = {"6-UPS": hexapod, "3-RPS": three_rps, "3-RUU": delta}


def _poses(ws: SpatialWorkspace) -> tuple[np.ndarray, np.ndarray]:
    return ws.position.reshape(-1, 3), ws.rotation.reshape(-1, 3, 3)


def _reachable_directly(robot, p: np.ndarray, r: np.ndarray) -> bool:
    try:
        inverse_geometry(robot, PlatformMotion.at_rest(p[None], r[None]))
    except UnreachablePoseError:
        return False
    return True


@pytest.mark.parametrize(
    "name, options",
    [
        ("6-UPS", {}),
        ("6-UPS", {"plane": "xz", "rpy": [0.05, -0.1, 0.2], "extent": [-0.04, 0.04, 0.06, 0.11]}),
        ("6-UPS", {"plane": "rp", "rpy": [0.0, 0.0, 0.1]}),
        ("3-RPS", {}),
        ("3-RPS", {"offset": 0.12}),
        ("3-RUU", {}),
        ("3-RUU", {"plane": "yz", "offset": 0.02}),
    ],
)
def test_reachability_agrees_with_the_inverse_geometry_point_by_point(name, options):
    robot = ROBOTS[name]()
    ws = spatial_workspace(robot, points=13, **options)
    positions, rotations = _poses(ws)
    direct = np.array(
        [_reachable_directly(robot, p, r) for p, r in zip(positions, rotations, strict=True)]
    )
    assert np.array_equal(ws.reachable.reshape(-1), direct)
    assert 0 < direct.sum() < direct.size  # the slice crosses the workspace's border
    # the grid's coordinates are the poses' own (the parasitic components only are solved)
    table = spatial_workspace_table(ws)
    first, second = ws.axes
    u, v = np.meshgrid(ws.u, ws.v)
    np.testing.assert_allclose(table[first], u.reshape(-1), atol=1e-12)
    np.testing.assert_allclose(table[second], v.reshape(-1), atol=1e-12)
    if robot.parasitic:  # the completed poses are complete_motion's
        reach = ws.reachable.reshape(-1)
        grid = PlatformMotion.at_rest(positions[reach], rotations[reach])
        done = complete_motion(robot, grid)
        np.testing.assert_allclose(done.position, positions[reach], atol=1e-9 * robot.scale)
        np.testing.assert_allclose(done.rotation, rotations[reach], atol=1e-9)
    else:
        assert np.allclose(rotations, rpy_matrix(np.array(options.get("rpy", [0.0] * 3)))) or (
            ws.plane == "rp"
        )


def test_the_hexapods_reasons_are_its_leg_lengths_by_hand():
    robot = hexapod()
    ws = spatial_workspace(robot, plane="xz", extent=[-0.06, 0.06, 0.0, 0.2], points=25)
    positions, rotations = _poses(ws)
    base = np.array([leg.joints[0].position for leg in robot.legs])
    attach = np.array([leg.attachment_position for leg in robot.legs])
    ends = positions[:, None, :] + np.einsum("nij,lj->nli", rotations, attach)
    length = np.linalg.norm(ends - base[None], axis=-1)  # U centre to S centre
    offsets = [leg.joints[1].position[0] + leg.joints[2].position[0] for leg in robot.legs]
    q_p = length - np.array(offsets)[None]
    low, high = robot.legs[0].joints[1].limits[0]
    out = (q_p < low) | (q_p > high)
    reason = ws.reason.reshape(-1)
    assert np.array_equal(reason == 2, out.any(axis=1))
    first = np.argmax(out, axis=1) + 1
    assert np.array_equal(ws.reason_leg.reshape(-1)[reason == 2], first[reason == 2])
    assert (reason == 0).any() and (reason == 2).any()


def test_the_hexapods_parallel_measure_is_its_closed_form():
    robot = hexapod()
    ws = spatial_workspace(robot, plane="xy", rpy=[0.1, 0.0, -0.2],
                           extent=[-0.05, 0.05, -0.05, 0.05], points=9)  # fmt: skip
    positions, rotations = _poses(ws)
    base = np.array([leg.joints[0].position for leg in robot.legs])
    attach = np.array([leg.attachment_position for leg in robot.legs])
    ends = positions[:, None, :] + np.einsum("nij,lj->nli", rotations, attach)
    unit = ends - base[None]
    unit /= np.linalg.norm(unit, axis=-1, keepdims=True)
    r = ends - positions[:, None, :]
    rows = np.concatenate([np.cross(r, unit) / robot.scale, unit], axis=-1)
    np.testing.assert_allclose(ws.mu_par.reshape(-1), np.linalg.det(rows), rtol=1e-9)
    # the serial measure of a UPS leg: (q_P/l)^2 cos b, b the U's second angle
    q = leg_coordinates(robot, positions, rotations).q
    expected = (q[..., 2] / robot.scale) ** 2 * np.cos(q[..., 1])
    np.testing.assert_allclose(ws.mu_leg.reshape(-1, 6), expected, rtol=1e-9)


def _actuated(robot, p: np.ndarray, r: np.ndarray) -> np.ndarray:
    q = leg_coordinates(robot, p[None], r[None]).q[0]
    return q[:, robot.legs[0].actuated_coordinate]


def test_the_deltas_parallel_measure_changes_sign_with_its_jacobian_by_differences():
    robot = delta()
    ws = spatial_workspace(robot, plane="xz", points=15)
    positions, _ = _poses(ws)
    h = 1e-6
    det = np.full(positions.shape[0], np.nan)
    for k, p in enumerate(positions):
        if not np.isfinite(ws.mu_par.reshape(-1)[k]):
            continue
        columns = [
            (_actuated(robot, p + h * e, np.eye(3)) - _actuated(robot, p - h * e, np.eye(3)))
            / (2 * h)
            for e in np.eye(3)
        ]
        det[k] = np.linalg.det(np.stack(columns, axis=-1))
    mu = ws.mu_par.reshape(-1)
    home = np.array(robot.home_position)
    home_det = np.linalg.det(np.stack([
        (_actuated(robot, home + h * e, np.eye(3)) - _actuated(robot, home - h * e, np.eye(3)))
        / (2 * h) for e in np.eye(3)
    ], axis=-1))  # fmt: skip
    clear = np.isfinite(det) & (np.abs(mu) > 1e-3 * abs(ws.home_par))
    clear &= np.abs(det) > 1e-3 * abs(home_det)
    assert clear.sum() > 20
    same = np.sign(mu[clear]) * np.sign(ws.home_par) == np.sign(det[clear]) * np.sign(home_det)
    assert same.all()


def _rps_completed(
    robot, z: float, roll: float, pitch: float, guess: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The 3-RPS pose of ``(z, roll, pitch)``: its ``x, y`` and yaw by scipy's fsolve from
    ``guess`` (the solution is checked by its own residual)."""

    def pose(unknown):
        p = np.array([unknown[0], unknown[1], z])
        return p, rpy_matrix(np.array([roll, pitch, unknown[2]]))

    def residual(unknown):
        p, r = pose(unknown)
        return plane_offsets(robot, p[None], r[None])[0]

    solution = fsolve(residual, guess, xtol=1e-13, full_output=True)[0]
    assert np.abs(residual(solution)).max() < 1e-12
    return pose(solution)


def test_the_3rps_parallel_measure_changes_sign_with_its_jacobian_by_differences():
    robot = three_rps()
    ws = spatial_workspace(robot, points=11)  # the plane rp crosses mu_par = 0 (§17)
    mu = ws.mu_par.reshape(-1)
    assert (np.sign(mu[np.isfinite(mu)]) != np.sign(ws.home_par)).any()
    u, v = (g.reshape(-1) for g in np.meshgrid(ws.u, ws.v))
    h = 1e-6

    positions, rotations = _poses(ws)
    yaw = np.arctan2(rotations[:, 1, 0], rotations[:, 0, 0])
    guesses = np.concatenate([positions[:, :2], yaw[:, None]], axis=1)

    def jacobian_det(roll, pitch, guess):
        z = ws.offset
        columns = []
        for step in np.eye(3) * h:
            plus = _actuated(robot, *_rps_completed(robot, z + step[0], roll + step[1],
                                                    pitch + step[2], guess))  # fmt: skip
            minus = _actuated(robot, *_rps_completed(robot, z - step[0], roll - step[1],
                                                     pitch - step[2], guess))  # fmt: skip
            columns.append((plus - minus) / (2 * h))
        return np.linalg.det(np.stack(columns, axis=-1))

    home_det = jacobian_det(0.0, 0.0, np.zeros(3))
    agree = 0
    for k in range(u.size):
        if not np.isfinite(mu[k]) or abs(mu[k]) < 1e-2 * abs(ws.home_par):
            continue
        det = jacobian_det(u[k], v[k], guesses[k])
        if abs(det) < 1e-2 * abs(home_det):
            continue
        assert np.sign(mu[k] * ws.home_par) == np.sign(det * home_det), (u[k], v[k])
        agree += 1
    assert agree > 50


@pytest.mark.parametrize("name", list(ROBOTS))
def test_the_efforts_at_rest_are_the_newton_euler_routes(name):
    robot = ROBOTS[name]()
    ws = spatial_workspace(robot, points=9, statics=True)
    regular = ws.regular.reshape(-1)
    assert regular.sum() > 10
    positions, rotations = _poses(ws)
    rest = PlatformMotion.at_rest(positions[regular], rotations[regular])
    tau = newton_euler_dynamics(robot, rest).tau
    got = ws.tau.reshape(-1, len(robot.legs))
    np.testing.assert_allclose(got[regular], tau, rtol=0, atol=1e-10 * np.abs(tau).max())
    assert np.isnan(got[~regular]).all()
    table = spatial_statics_table(ws)
    np.testing.assert_allclose(table["tau_peak"][regular], np.abs(tau).max(axis=1), rtol=1e-12)


def _potential(robot, p: np.ndarray, r: np.ndarray) -> float:
    """``U = −Σ m g·c`` over every body, the mass centres from the chain of frames."""
    q = leg_coordinates(robot, p[None], r[None]).q
    frames = chain_frames(robot, q)
    g = np.array(robot.gravity)
    u = -robot.platform.mass * g @ (p + r @ np.array(robot.platform.centre))
    for i, leg in enumerate(robot.legs):
        for k, body in enumerate(leg.bodies):
            centre = frames.origin[0, i, k] + frames.rotation[0, i, k] @ np.array(body.centre)
            u -= body.mass * g @ centre
    return float(u)


def _free_moves(robot, p: np.ndarray, r: np.ndarray, s: float):
    """The poses moved by ``s`` along each free direction (parasitic components solved)."""
    moves = []
    for c in range(6):
        name = ("wx", "wy", "wz", "vx", "vy", "vz")[c]
        if name in robot.parasitic:
            continue
        if c < 3:
            moved = (p, exp_rotation(s * np.eye(3)[c]) @ r)
        else:
            moved = (p + s * robot.scale * np.eye(3)[c - 3], r)
        if robot.parasitic:
            done = complete_motion(robot, PlatformMotion.at_rest(moved[0][None], moved[1][None]))
            moved = (done.position[0], done.rotation[0])
        moves.append(moved)
    return moves


@pytest.mark.parametrize("name", list(ROBOTS))
def test_the_efforts_at_rest_balance_the_weight_by_virtual_work(name):
    robot = ROBOTS[name]()
    ws = spatial_workspace(robot, points=7, statics=True)
    regular = np.flatnonzero(ws.regular.reshape(-1))
    positions, rotations = _poses(ws)
    tau = ws.tau.reshape(-1, len(robot.legs))
    h = 1e-6
    for k in regular[:: max(1, regular.size // 6)]:
        p, r = positions[k], rotations[k]
        for (pp, rp), (pm, rm) in zip(
            _free_moves(robot, p, r, h), _free_moves(robot, p, r, -h), strict=True
        ):
            dq = _actuated(robot, pp, rp) - _actuated(robot, pm, rm)
            du = _potential(robot, pp, rp) - _potential(robot, pm, rm)
            weight = robot.platform.mass + sum(b.mass for leg in robot.legs for b in leg.bodies)
            scale = weight * 9.81 * h * robot.scale
            assert abs(tau[k] @ dq - du) < 1e-6 * scale, (name, k)


def test_the_library_refuses_bad_slices():
    robot = hexapod()
    cases = [
        ({"plane": "zz"}, "plane must be one of"),
        ({"offset": float("nan")}, "offset"),
        ({"offset": 1e9}, "offset = 1000000000.0 m is beyond"),
        ({"rpy": [0.0, 0.0]}, "rpy must be 3 numbers"),
        ({"points": 1001}, "points"),
        ({"extent": [0.1, -0.1, 0.0, 0.1]}, "min < max"),
        ({"offset": 1.0}, "no pose of the 6-UPS in the plane xy at z = 1"),
        ({"statics": 1}, "statics must be True or False"),
    ]
    for options, words in cases:
        with pytest.raises(ParameterError) as caught:
            spatial_workspace(robot, **{"points": 5, **options})
        assert words in str(caught.value) and "\n" not in str(caught.value)
    with pytest.raises(ParameterError, match="plane 'xy' moves x, y, which the 3-RPS"):
        spatial_workspace(three_rps(), plane="xy")
    with pytest.raises(ParameterError, match="gives roll, yaw, which the 3-RUU determines"):
        spatial_workspace(delta(), rpy=[0.1, 0.0, 0.2])
    with pytest.raises(ParameterError, match="give only the yaw"):
        spatial_workspace(robot, plane="rp", rpy=[0.1, 0.0, 0.0])
    with pytest.raises(Prp3Error, match="ws has no efforts"):
        spatial_statics_table(spatial_workspace(robot, points=3))


def _read(path: Path) -> dict[str, np.ndarray]:
    with path.open(newline="") as handle:
        rows = list(csv.reader(handle))
    values = np.array([[float(v) if v else np.nan for v in row] for row in rows[1:]])
    return {name: values[:, j] for j, name in enumerate(rows[0])}


@pytest.mark.parametrize("name", list(ROBOTS))
def test_prp3_workspace_of_a_spatial_robot_file(capsys, tmp_path, name):
    robot_file = tmp_path / f"{name}.toml"
    robot_file.write_text(f'architecture = "{name}"\n', encoding="utf-8")
    out = tmp_path / "out"
    status, stdout, err = cli(capsys, "workspace", "--robot", robot_file, "--points", "9",
                              "--statics", "--output", out)  # fmt: skip
    assert status == 0, err
    assert f"prp3 workspace: {name}" in stdout and "files written:" in stdout
    for figure in ("workspace.png", "statics.png"):
        assert (out / figure).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    table = _read(out / "workspace.csv")
    robot = ROBOTS[name]()
    legs = len(robot.legs)
    assert list(table) == [
        "x", "y", "z", "roll", "pitch", "yaw", "reachable", "regular", "reason", "reason_leg",
        *(f"mu_leg_{i + 1}" for i in range(legs)), "mu_par",
    ]  # fmt: skip
    assert table["x"].size == 81
    assert np.array_equal(table["reachable"] == 1, table["reason"] == 0)
    for k in range(81):  # every row's pose: reachable as the inverse geometry says
        p = np.array([table["x"][k], table["y"][k], table["z"][k]])
        r = rpy_matrix(np.array([table["roll"][k], table["pitch"][k], table["yaw"][k]]))
        assert _reachable_directly(robot, p, r) == (table["reachable"][k] == 1)
    statics = _read(out / "statics.csv")
    regular = statics["regular"] == 1
    assert regular.any() and np.isnan(statics["tau_1"][~regular]).all()
    rows = np.flatnonzero(regular)
    p = np.stack([statics[c][rows] for c in "xyz"], axis=-1)
    r = rpy_matrix(np.stack([statics[c][rows] for c in ("roll", "pitch", "yaw")], axis=-1))
    tau = newton_euler_dynamics(robot, PlatformMotion.at_rest(p, r)).tau
    got = np.stack([statics[f"tau_{i + 1}"][rows] for i in range(legs)], axis=-1)
    np.testing.assert_allclose(got, tau, atol=1e-9 * np.abs(tau).max())


@pytest.mark.parametrize(
    "robot, options, words",
    [
        ("6-UPS", ["--plane", "zz"], "--plane zz is not a plane of a slice"),
        ("3-RPS", ["--plane", "xy"], "plane 'xy' moves x, y, which the 3-RPS"),
        ("6-UPS", ["--offset", "nan"], "argument --offset: expected a finite number"),
        ("6-UPS", ["--offset", "5.0"], "no pose of the 6-UPS in the plane xy at z = 5"),
        ("6-UPS", ["--points", "5000"], "--points 5000 is more than the 1000"),
        ("6-UPS", ["--phi", "0.1"], "--phi applies to the planar robots"),
        ("3-RUU", ["--rpy", "0.1", "0", "0"], "gives roll, which the 3-RUU determines"),
        ("6-UPS", ["--extent", "0.1", "-0.1", "0", "1"], "min < max"),
        (None, ["--plane", "xy"], "--plane applies to a spatial robot file"),
    ],
)
def test_prp3_workspace_refuses_a_bad_slice_in_one_line(capsys, tmp_path, robot, options, words):
    out = tmp_path / "out"
    given = []
    if robot is not None:
        path = tmp_path / "robot.toml"
        path.write_text(f'architecture = "{robot}"\n', encoding="utf-8")
        given = ["--robot", path]
    points = [] if "--points" in options else ["--points", "5"]
    status, _, err = cli(capsys, "workspace", *given, *options, *points, "--output", out)
    assert status == 2
    assert words in one_line(err)
    assert not out.exists()
