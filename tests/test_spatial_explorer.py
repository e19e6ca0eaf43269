"""The 3-D explorer of a spatial run (``prp3 simulate --robot SPATIAL.toml --html``, ``prp3 explore
--robot SPATIAL.toml``; docs/spatial.md §22), in Python.

The figure's data is held against what it must draw, rebuilt here: the joint points from the
reported ``q`` columns by the joints' own rotations (tests/spatial_pages.py), the arrows from
the reported ``F`` columns times the scale the legend states, the platform origin's path from
the built-in motion's formula, to 1e-12 m.  The page file the command line writes is read back
(its script's JSON, what the browser receives) and held against the ``results.csv`` the same
run wrote.  Refusals are one line and exit status 2, and leave nothing behind.
"""

from __future__ import annotations

import math
import socket
import sys
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from clitools import cli, listing, one_line
from prp3.errors import Prp3Error
from prp3.io.tables import read_table_csv
from prp3.spatial.kinematics import complete_motion
from prp3.spatial.model import SpatialRobot, delta, hexapod, three_rps
from prp3.spatial.motion import spatial_motion
from prp3.spatial.outputs import spatial_inverse_dynamics, spatial_results_table
from spatial_pages import expected_points, page_figure, reported_forces, xyz

pytest.importorskip("plotly", reason="the 3-D explorer needs plotly (pip install 'prp3[explore]')")

from prp3.explorer.spatial_page import spatial_page_figure
from prp3.explorer.spatial_run import read_spatial_run

RUNS = {"6-UPS": (hexapod, "heave"), "3-RPS": (three_rps, "tilt"), "3-RUU": (delta, "circle")}
SAMPLES = 17


@cache
def _run(architecture: str) -> tuple[SpatialRobot, dict[str, np.ndarray]]:
    constructor, motion = RUNS[architecture]
    robot = constructor()
    done = complete_motion(robot, spatial_motion(robot, motion, SAMPLES))
    return robot, spatial_results_table(spatial_inverse_dynamics(robot, done, "newton-euler"))


@cache
def _figure(architecture: str) -> dict[str, Any]:
    robot, table = _run(architecture)
    return spatial_page_figure(robot, table, architecture)


def _by_meta(figure: dict[str, Any], traces: list[dict[str, Any]]) -> dict[str, dict[str, Any]]:
    names = [trace["meta"] for trace in figure["data"]]
    return dict(zip(names, traces, strict=False))  # a frame holds the moving traces, in order


def _check_frame(
    robot: SpatialRobot,
    table: dict[str, Any],
    k: int,
    traces: dict[str, dict[str, Any]],
    scale: float,
) -> None:
    """The traces of sample ``k`` draw its joint points and its reported forces / ``scale``."""
    points = expected_points(robot, table, k)
    force = reported_forces(robot, table, k)
    legs = len(robot.legs)
    for j, label in enumerate(robot.legs[0].labels):
        np.testing.assert_allclose(xyz(traces[f"joint {label}"]), points[:, j], rtol=0, atol=1e-12)
        shafts = xyz(traces[f"force {label}"]).reshape(legs, 3, 3)
        np.testing.assert_allclose(shafts[:, 0], points[:, j], rtol=0, atol=1e-12)
        np.testing.assert_allclose(
            (shafts[:, 1] - shafts[:, 0]) * scale, force[:, j], rtol=0, atol=1e-12 * scale
        )
        assert np.isnan(shafts[:, 2]).all()  # a gap between the legs' arrows
        cones = traces[f"head {label}"]
        np.testing.assert_allclose(xyz(cones), shafts[:, 1], rtol=0, atol=1e-12)
        head = np.stack([cones["u"], cones["v"], cones["w"]], axis=-1)
        # along the force, pointing at the tip
        cross = np.cross(head, force[:, j])
        assert np.abs(cross).max() <= 1e-12 * max(np.abs(force[:, j]).max(), 1.0)
        assert (np.einsum("ij,ij->i", head, force[:, j]) >= 0).all()
        for i in range(legs):
            text = traces[f"joint {label}"]["text"][i]
            assert text.startswith(f"leg {i + 1}, joint {label} (")
            fx, fy, fz = force[i, j]
            assert f"F = ({fx:.6g}, {fy:.6g}, {fz:.6g}) N" in text
            assert traces[f"force {label}"]["text"][3 * i + 1] == text  # the arrow's tip too
    # the base polygon through the first joints, the platform's through the last ones
    outline = xyz(traces["platform outline"])
    assert np.allclose(outline[0], outline[-1], atol=0)  # closed
    for corner in points[:, -1]:
        assert np.linalg.norm(outline[:-1] - corner, axis=1).min() <= 1e-12
    for corner in points[:, 0]:
        assert np.linalg.norm(xyz(traces["base outline"])[:-1] - corner, axis=1).min() <= 1e-12
    for i in range(legs):  # each leg's chain runs from its base joint to its platform joint
        chain = xyz(traces[f"leg {i + 1}"])
        np.testing.assert_allclose(chain[0], points[i, 0], atol=1e-12)
        np.testing.assert_allclose(chain[-1], points[i, -1], atol=1e-12)


@given(architecture=st.sampled_from(sorted(RUNS)), sample=st.integers(0, SAMPLES - 1))
@settings(max_examples=15, deadline=None)
def test_every_frame_draws_the_reported_joint_points_and_forces(
    architecture: str, sample: int
) -> None:
    robot, table = _run(architecture)
    figure = _figure(architecture)
    meta = figure["layout"]["meta"]
    assert meta["samples"] == list(range(SAMPLES))  # 17 samples: every one a frame
    frame = figure["frames"][sample]
    assert frame["name"] == str(sample)
    _check_frame(robot, table, sample, _by_meta(figure, frame["data"]), meta["scale"])
    if sample == 0:  # the figure's own traces show the first sample
        _check_frame(robot, table, 0, _by_meta(figure, figure["data"]), meta["scale"])
    step = figure["layout"]["sliders"][0]["steps"][sample]
    assert step["args"][0] == [str(sample)]
    assert step["label"] == f"{float(table['t'][sample]):.3f} s"


@pytest.mark.parametrize("architecture", sorted(RUNS))
def test_the_scale_the_legend_states_draws_the_largest_force_within_its_fraction(
    architecture: str,
) -> None:
    """The scale is the smallest of 1, 2, 5 × 10ⁿ N per m that draws the run's largest force at
    most 0.3 of the robot's size (the largest side of the legs' box over the run)."""
    robot, table = _run(architecture)
    figure = _figure(architecture)
    scale = figure["layout"]["meta"]["scale"]
    largest = max(
        float(np.linalg.norm(reported_forces(robot, table, k), axis=-1).max())
        for k in range(SAMPLES)
    )
    chains = np.concatenate(
        [
            xyz(trace)
            for frame in figure["frames"]
            for trace in frame["data"][4 : 4 + len(robot.legs)]
        ]
    )
    size = float((chains.max(axis=0) - chains.min(axis=0)).max())
    assert largest / scale <= 0.3 * size * (1 + 1e-12)
    power = 10.0 ** math.floor(math.log10(scale * (1 + 1e-12)))
    mantissa = round(scale / power, 9)
    assert mantissa in (1.0, 2.0, 5.0)
    smaller = {1.0: 0.5, 2.0: 1.0, 5.0: 2.0}[mantissa] * power
    assert largest / smaller > 0.3 * size  # the next smaller step would draw it too long
    stated = f"{scale:.0f} N per m" if scale >= 1 else f"{scale:.3g} N per m"
    assert stated in figure["layout"]["legend"]["title"]["text"]
    # the cube of the scene holds every arrow's tip, the three axes alike
    ranges = [figure["layout"]["scene"][f"{a}axis"]["range"] for a in "xyz"]
    assert len({round(high - low, 15) for low, high in ranges}) == 1
    for frame in figure["frames"]:
        for trace in frame["data"]:
            if trace["type"] == "scatter3d":
                drawn = xyz(trace)
                drawn = drawn[~np.isnan(drawn).any(axis=1)]
                for c, (low, high) in enumerate(ranges):
                    assert (drawn[:, c] >= low).all() and (drawn[:, c] <= high).all()


def test_the_platform_path_is_the_motion_s() -> None:
    robot, table = _run("6-UPS")
    figure = _figure("6-UPS")
    path = xyz(next(trace for trace in figure["data"] if trace["meta"] == "path"))
    theta = 2.0 * np.pi * table["t"] / 3.0
    expected = np.array(robot.home_position) + np.stack(
        [0 * theta, 0 * theta, 0.1 * robot.scale * np.sin(theta)], axis=-1
    )  # docs/spatial.md §15's heave
    np.testing.assert_allclose(path, expected, rtol=0, atol=1e-12)


def test_a_long_run_shows_at_most_200_frames_first_and_last_kept() -> None:
    robot = hexapod()
    motion = spatial_motion(robot, "tilt", 401)
    table = spatial_results_table(spatial_inverse_dynamics(robot, motion, "newton-euler"))
    figure = spatial_page_figure(robot, table)
    samples = figure["layout"]["meta"]["samples"]
    assert len(samples) == len(figure["frames"]) == 200
    assert samples[0] == 0 and samples[-1] == 400 and samples == sorted(set(samples))
    k = samples[117]
    _check_frame(robot, table, k, _by_meta(figure, figure["frames"][117]["data"]),
                 figure["layout"]["meta"]["scale"])  # fmt: skip


# ---------------------------------------------------------------- the command line
def _robot_file(folder: Path, architecture: str) -> Path:
    path = folder / f"{architecture}.toml"
    path.write_text(f'architecture = "{architecture}"\n', encoding="utf-8")
    return path


@pytest.mark.parametrize("architecture", sorted(RUNS))
def test_simulate_html_writes_the_page_of_the_run_it_wrote(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, architecture: str
) -> None:
    _, motion = RUNS[architecture]
    robot_file = _robot_file(tmp_path, architecture)
    page = tmp_path / "run.html"
    status, out, err = cli(capsys, "simulate", "--robot", robot_file, "--motion", motion,
                           "--samples", 9, "--output", tmp_path / "out", "--html", page)  # fmt: skip
    assert status == 0, err
    assert f"html file written: {page}" in out
    text = page.read_text(encoding="utf-8")
    assert text.startswith("<!DOCTYPE html>") and "plotly.js" in text[:3_000_000]
    assert '<script src="http' not in text  # plotly.js is inline: the page opens offline
    figure = page_figure(page)
    table = read_table_csv(tmp_path / "out" / "results.csv", [], list(_run(architecture)[1]))
    robot = RUNS[architecture][0]()
    scale = figure["layout"]["meta"]["scale"]
    assert figure["layout"]["meta"]["samples"] == list(range(9))
    for k in (0, 4, 8):
        _check_frame(robot, table, k, _by_meta(figure, figure["frames"][k]["data"]), scale)
    # and prp3 explore of that folder writes the same figure
    export = tmp_path / "export.html"
    status, out, err = cli(capsys, "explore", "--robot", robot_file, "--results",
                           tmp_path / "out", "--export", export)  # fmt: skip
    assert status == 0, err and out.strip() == f"prp3 explore: wrote {export}"
    again = page_figure(export)
    assert again["frames"] == figure["frames"] and again["data"] == figure["data"]


def test_explore_without_results_shows_the_heave_motion(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    export = tmp_path / "heave.html"
    status, _, err = cli(capsys, "explore", "--robot", _robot_file(tmp_path, "3-RPS"),
                         "--export", export)  # fmt: skip
    assert status == 0, err
    figure = page_figure(export)
    robot = three_rps()
    table = spatial_results_table(
        spatial_inverse_dynamics(
            robot, complete_motion(robot, spatial_motion(robot, "heave", 301)), "newton-euler"
        )
    )
    k = figure["layout"]["meta"]["samples"][50]
    _check_frame(robot, table, k, _by_meta(figure, figure["frames"][50]["data"]),
                 figure["layout"]["meta"]["scale"])  # fmt: skip


@pytest.fixture
def spatial_run(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> tuple[Path, Path]:
    robot_file = _robot_file(tmp_path, "6-UPS")
    status, _, err = cli(capsys, "simulate", "--robot", robot_file, "--motion", "tilt",
                         "--samples", 7, "--output", tmp_path / "run")  # fmt: skip
    assert status == 0, err
    return robot_file, tmp_path / "run"


def _planar_run(capsys: pytest.CaptureFixture[str], folder: Path) -> Path:
    status, _, err = cli(capsys, "simulate", "--motion", "vertical", "--samples", 5,
                         "--output", folder)  # fmt: skip
    assert status == 0, err
    return folder


def test_explore_refuses_what_is_not_a_run_of_the_spatial_robot(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, spatial_run: tuple[Path, Path]
) -> None:
    robot_file, run = spatial_run
    export = tmp_path / "x.html"

    def refused(*options: object) -> str:
        status, out, err = cli(capsys, "explore", *options, "--export", export)
        assert status == 2 and out == ""
        assert not export.exists()
        return one_line(err)

    # a spatial run without its robot file, or with a planar one
    line = refused("--results", run)
    assert "holds a spatial robot's run: give its spatial robot file" in line
    assert f"--robot SPATIAL.toml --results {run}" in line
    # a planar run with a spatial robot
    planar = _planar_run(capsys, tmp_path / "planar")
    line = refused("--robot", robot_file, "--results", planar)
    assert line.startswith(f"prp3 explore: error: {planar / 'results.csv'}: not a spatial robot")
    # the run of another spatial robot
    line = refused("--robot", _robot_file(tmp_path, "3-RPS"), "--results", run)
    assert "not a run of this 3-RPS (3 legs of joints R1, P2, S3): it has 'q_1_U1_a'" in line
    # missing results
    (tmp_path / "empty").mkdir()
    line = refused("--robot", robot_file, "--results", tmp_path / "empty")
    assert "no results.csv or results.parquet in it" in line
    line = refused("--robot", robot_file, "--results", tmp_path / "nowhere")
    assert "nowhere: not a folder of `prp3 simulate` results" in line
    # legs that do not close: one joint value moved (another robot's geometry)
    bad = tmp_path / "bad"
    bad.mkdir()
    rows = (run / "results.csv").read_text(encoding="utf-8").splitlines()
    column = rows[0].split(",").index("q_4_P2")
    cells = rows[5].split(",")
    cells[column] = repr(float(cells[column]) + 1e-6)
    rows[5] = ",".join(cells)
    (bad / "results.csv").write_text("\n".join(rows) + "\n", encoding="utf-8")
    line = refused("--robot", robot_file, "--results", bad)
    assert f"{bad / 'results.csv'}:6:" in line and "legs 1 and 4 place the platform" in line
    assert "not a run of this 6-UPS; give the --robot of the run" in line
    # a time that does not increase
    rows = (run / "results.csv").read_text(encoding="utf-8").splitlines()
    rows[3], rows[4] = rows[4], rows[3]
    (bad / "results.csv").write_text("\n".join(rows) + "\n", encoding="utf-8")
    line = refused("--robot", robot_file, "--results", bad)
    assert ":5:" in line and "t must be strictly increasing: t = 1.0 follows 1.5" in line


def test_the_library_reads_a_parquet_run_as_its_csv(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, spatial_run: tuple[Path, Path]
) -> None:
    pytest.importorskip("pyarrow")
    robot_file, run = spatial_run
    status, _, err = cli(capsys, "simulate", "--robot", robot_file, "--motion", "tilt",
                         "--samples", 7, "--output", tmp_path / "pq", "--format", "parquet")  # fmt: skip
    assert status == 0, err
    ours, theirs = read_spatial_run(tmp_path / "pq", hexapod()), read_spatial_run(run, hexapod())
    assert list(ours.table) == list(theirs.table)
    for name in ours.table:
        np.testing.assert_allclose(ours.table[name], theirs.table[name], rtol=1e-15, atol=0)


def test_without_plotly_the_spatial_html_is_refused_in_one_line_and_nothing_written(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "plotly", None)  # import plotly raises ImportError
    robot_file = _robot_file(tmp_path, "6-UPS")
    status, _, err = cli(capsys, "simulate", "--robot", robot_file, "--motion", "heave",
                         "--samples", 5, "--output", tmp_path / "out", "--html",
                         tmp_path / "run.html")  # fmt: skip
    assert status == 2
    assert one_line(err) == (
        "prp3 simulate: error: --html of a spatial robot (the 3-D explorer, docs/spatial.md "
        "§22) needs plotly, which is not installed: pip install 'prp3[explore]'"
    )
    assert not (tmp_path / "out").exists() and not (tmp_path / "run.html").exists()
    status, _, err = cli(capsys, "explore", "--robot", robot_file, "--export", tmp_path / "e.html")
    assert status == 2 and "needs plotly, which is not installed" in one_line(err)


def test_a_failing_page_leaves_the_earlier_results(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
    spatial_run: tuple[Path, Path],
) -> None:  # fmt: skip
    robot_file, run = spatial_run
    before = listing(run)

    def fail(*args: object, **kwargs: object) -> str:
        raise Prp3Error("the page failed")

    monkeypatch.setattr("prp3.explorer.spatial_page.spatial_run_html", fail)
    status, _, err = cli(capsys, "simulate", "--robot", robot_file, "--motion", "heave",
                         "--samples", 5, "--output", run, "--html", tmp_path / "p.html")  # fmt: skip
    assert status == 2 and one_line(err) == "prp3 simulate: error: the page failed"
    assert listing(run) == before and not (tmp_path / "p.html").exists()


def test_explore_refuses_a_busy_port_in_one_line(
    capsys: pytest.CaptureFixture[str], spatial_run: tuple[Path, Path]
) -> None:
    robot_file, run = spatial_run
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        status, out, err = cli(capsys, "explore", "--robot", robot_file, "--results", run,
                               "--no-browser", "--port", port)  # fmt: skip
    assert status == 2 and out == ""
    assert one_line(err) == (
        f"prp3 explore: error: --port {port}: port {port} on 127.0.0.1 is busy (another "
        "program listens there): choose another with --port"
    )


def test_the_subtitle_names_the_first_of_tied_largest_forces() -> None:
    """The table is built so that two joints carry the largest force, equal to round-off
    (one slightly above the other, by 1e-13 relative), and another later joint the same
    force exactly: the first in time, leg, joint order is named, not the one round-off
    favours."""
    robot, table = _run("6-UPS")
    table = {name: np.array(column, dtype=float) for name, column in table.items()}
    leg = robot.legs[0]
    top = 1e3
    names = [f"F{c}_{i + 1}_{label}" for i in range(6) for label in leg.labels for c in "xyz"]
    for name in names:
        table[name][:] = 0.0
    table[f"Fz_3_{leg.labels[0]}"][2] = top  # the first (sample 2, leg 3)
    table[f"Fz_6_{leg.labels[0]}"][2] = top * (1 + 1e-13)  # round-off above it
    subtitle = spatial_page_figure(robot, table, "tie")["layout"]["title"]["text"]
    assert f"at {leg.labels[0]} of leg 3, t = {float(table['t'][2]):.3g} s" in subtitle


def test_the_explorer_functions_are_public_at_prp3_explorer() -> None:
    import prp3.explorer

    assert prp3.explorer.spatial_page_figure is spatial_page_figure
    assert prp3.explorer.read_spatial_run is read_spatial_run
    for name in ("spatial_run_html", "write_spatial_run_html"):
        assert callable(getattr(prp3.explorer, name)) and name in prp3.explorer.__all__


@pytest.mark.parametrize(
    ("table", "named"),
    [
        (None, "table must be a mapping"),
        ("t", "table must be a mapping"),
        ({"t": [0.0]}, "no column q_1_"),
    ],
)
def test_the_page_refuses_what_is_not_a_results_table(table: Any, named: str) -> None:
    robot, _ = _run("6-UPS")
    with pytest.raises(Prp3Error, match=named):
        spatial_page_figure(robot, table)


@pytest.mark.parametrize("bad", [math.nan, math.inf, "text"])
def test_the_page_refuses_a_column_that_is_not_a_finite_number(bad: Any) -> None:
    robot, table = _run("6-UPS")
    name = f"Fx_2_{robot.legs[0].labels[1]}"
    column = np.array(table[name], dtype=object)
    column[3] = bad
    with pytest.raises(Prp3Error, match="table: col"):
        spatial_page_figure(robot, {**table, name: column})
