"""The 3-D drawing and the animation of a spatial robot (``prp3 simulate --animate``, ``pose.png``;
docs/spatial.md §15).

What the figure draws is read back from its matplotlib artists and held against what it must
be: the joint points rebuilt here from the reported ``q`` columns by the joints' own
rotations (written out below, not the library's chain), and from the platform pose of the
built-in motions' formulas; the arrows against the reported ``F`` columns times the scale the
legend states.  The command line writes a GIF of ``--frames`` frames for each architecture
and refuses what it cannot draw in one line.
"""

from __future__ import annotations

import math
import re
from functools import cache
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

from clitools import cli, listing, one_line
from prp3.plotting.spatial_animation import (
    ARROW_FRACTION,
    SLEEVE_FRACTION,
    draw_spatial_frame,
    spatial_frame,
    spatial_robot_figure,
    spatial_samples,
)
from prp3.spatial.kinematics import complete_motion
from prp3.spatial.model import SpatialRobot, delta, hexapod, three_rps
from prp3.spatial.motion import spatial_motion
from prp3.spatial.outputs import spatial_inverse_dynamics, spatial_results_table

RUNS = {"6-UPS": (hexapod, "heave"), "3-RPS": (three_rps, "tilt"), "3-RUU": (delta, "circle")}
SAMPLES = 13


@cache
def _run(architecture: str) -> tuple[SpatialRobot, dict[str, np.ndarray]]:
    constructor, motion = RUNS[architecture]
    robot = constructor()
    done = complete_motion(robot, spatial_motion(robot, motion, SAMPLES))
    return robot, spatial_results_table(spatial_inverse_dynamics(robot, done, "newton-euler"))


def _rot_z(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _rot_y(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _expected_points(robot: SpatialRobot, table: dict[str, np.ndarray], k: int) -> np.ndarray:
    """The joint points ``(legs, 3, 3)`` of sample ``k`` from the reported ``q`` columns
    (docs/spatial.md §2): the base joint fixed; a UPS leg's P point and S centre where the
    slide ``q_P`` along the U-turned axis ends; a RPS leg's likewise, turned by its R; a RUU
    leg's elbow U at the arm's length turned by its R, its platform U at the platform pose."""
    points = np.empty((len(robot.legs), 3, 3))
    for i, leg in enumerate(robot.legs):
        base = np.array(leg.joints[0].position)
        r_j = np.array(leg.joints[0].rotation)
        q = {c: float(table[f"q_{i + 1}_{c}"][k]) for c in leg.coordinates}
        if leg.pattern == "RUU":
            elbow = base + r_j @ _rot_z(q["R1"]) @ np.array(leg.joints[1].position)
            t = float(table["t"][k])
            theta = 2.0 * math.pi * t / 3.0
            p = np.array(robot.home_position) + 0.1 * robot.scale * np.array(
                [math.cos(theta) - 1.0, math.sin(theta), 0.0]
            )  # docs/spatial.md §15's circle; the Delta's platform keeps its orientation
            end = p + np.array(leg.attachment_position)
            points[i] = [base, elbow, end]
            continue
        turn = _rot_z(q["U1_a"]) @ _rot_y(q["U1_b"]) if leg.pattern == "UPS" else _rot_z(q["R1"])
        slide = q["P2"] + leg.joints[1].position[0] + leg.joints[2].position[0]
        end = base + r_j @ turn @ np.array([slide, 0.0, 0.0])
        points[i] = [base, end, end]
    return points


def _figure(architecture: str):
    robot, table = _run(architecture)
    t, q, force = spatial_samples(robot, table)
    frames = [spatial_frame(robot, q[k], force[k], t=float(t[k])) for k in range(t.size)]
    return robot, table, frames, spatial_robot_figure(robot, frames, dpi=40)


def _data(line) -> np.ndarray:
    return np.stack(line.get_data_3d(), axis=-1)


@given(
    architecture=st.sampled_from(sorted(RUNS)),
    sample=st.integers(0, SAMPLES - 1),
)
@settings(max_examples=12, deadline=None)
def test_the_drawn_joints_are_the_models_joint_points(architecture: str, sample: int) -> None:
    robot, table, frames, artists = _figure(architecture)
    draw_spatial_frame(artists, frames[sample])
    expected = _expected_points(robot, table, sample)
    leg = robot.legs[0]
    for k, kind in enumerate(leg.pattern):
        drawn = _data(artists.joints[k])
        np.testing.assert_allclose(drawn, expected[:, k], rtol=0.0, atol=1e-12)
        for i in range(len(robot.legs)):  # every arrow starts at its joint point
            np.testing.assert_allclose(_data(artists.arrows[i][k])[0], expected[i, k], atol=1e-12)
        if kind == "P":  # the sleeve: from the base joint along the leg, SLEEVE_FRACTION of
            # this frame's q_P (the frames were built without a run-wide sleeve length)
            q_p = np.array([table[f"q_{i + 1}_P2"][sample] for i in range(len(robot.legs))])
            bars = _data(artists.sleeves[k]).reshape(len(robot.legs), 3, 3)[:, :2]
            np.testing.assert_allclose(bars[:, 0], expected[:, 0], atol=1e-12)
            leg_axis = expected[:, 1] - expected[:, 0]
            along = leg_axis / np.linalg.norm(leg_axis, axis=1, keepdims=True)
            expected_bar = SLEEVE_FRACTION * q_p[:, None] * along
            np.testing.assert_allclose(bars[:, 1] - bars[:, 0], expected_bar, atol=1e-12)
    if architecture == "6-UPS":  # and where docs/spatial.md §15's heave puts the S centres
        theta = 2.0 * math.pi * float(table["t"][sample]) / 3.0
        p = np.array(robot.home_position) + [0.0, 0.0, 0.1 * robot.scale * math.sin(theta)]
        attached = p + np.array([leg.attachment_position for leg in robot.legs])
        np.testing.assert_allclose(_data(artists.joints[2]), attached, rtol=0.0, atol=1e-12)
    # the platform polygon: the legs' last joint points, once each
    polygon = frames[sample].platform
    assert sorted(map(tuple, polygon.round(12))) == sorted(map(tuple, expected[:, -1].round(12)))


@pytest.mark.parametrize("architecture", sorted(RUNS))
def test_the_arrows_are_the_reported_forces_on_the_legends_scale(architecture: str) -> None:
    robot, table, frames, artists = _figure(architecture)
    legend = artists.figure.legends[0]
    stated = re.search(r"force arrows: ([0-9.]+) N per m", legend.get_title().get_text())
    assert stated is not None
    per_metre = float(stated.group(1))
    assert per_metre == artists.scale
    labels = robot.legs[0].labels
    largest = 0.0
    for sample, frame in enumerate(frames):
        draw_spatial_frame(artists, frame)
        for i in range(len(robot.legs)):
            for k, label in enumerate(labels):
                force = np.array([table[f"F{c}_{i + 1}_{label}"][sample] for c in "xyz"])
                tail, tip = _data(artists.arrows[i][k])
                np.testing.assert_allclose(tip - tail, force / per_metre, rtol=0.0, atol=1e-12)
                largest = max(largest, float(np.linalg.norm(tip - tail)))
    # the run's largest force drawn at most ARROW_FRACTION of the robot's size, and the scale
    # rounded up to 1, 2 or 5 x 10^n: no less than 1 / 2.5 of that
    points = np.concatenate([_expected_points(robot, table, k) for k in range(SAMPLES)])
    size = float((points.reshape(-1, 3).max(axis=0) - points.reshape(-1, 3).min(axis=0)).max())
    assert ARROW_FRACTION * size / 2.5 <= largest <= ARROW_FRACTION * size * (1 + 1e-12)
    mantissa = per_metre / 10.0 ** math.floor(math.log10(per_metre))
    assert round(mantissa, 9) in (1.0, 2.0, 5.0)


def _robot_file(folder: Path, architecture: str) -> Path:
    path = folder / f"{architecture}.toml"
    path.write_text(f'architecture = "{architecture}"\n', encoding="utf-8")
    return path


@pytest.mark.parametrize("architecture", sorted(RUNS))
def test_simulate_animate_writes_a_gif_of_frames_frames(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, architecture: str
) -> None:
    out = tmp_path / "out"
    status, stdout, err = cli(
        capsys, "simulate", "--robot", _robot_file(tmp_path, architecture), "--motion",
        RUNS[architecture][1], "--samples", 21, "--animate", "--frames", 4, "--output", out,
    )  # fmt: skip
    assert status == 0, err
    assert err == ""
    assert f"{out / 'mechanism.gif'}" in stdout
    with Image.open(out / "mechanism.gif") as image:
        assert image.n_frames == 4
        assert image.size == (720, 720)
        durations = []
        for k in range(image.n_frames):
            image.seek(k)
            durations.append(image.info["duration"])
            grey = np.asarray(image.convert("L"), dtype=np.float64)
            assert grey.std() > 10.0  # a drawing, not a blank frame
    assert sum(durations[:-1]) == 3000  # the 3 s motion in real time, then the end held
    assert sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == [
        "mechanism.gif",
        "results.csv",
    ]


def test_plots_add_the_pose_figure(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    out = tmp_path / "out"
    status, _, err = cli(capsys, "simulate", "--robot", _robot_file(tmp_path, "3-RUU"),
                         "--motion", "heave", "--samples", 5, "--plots", "--output", out)  # fmt: skip
    assert status == 0, err
    with Image.open(out / "pose.png") as image:
        assert image.size == (720, 720)  # 7.2 in at 100 dpi, as the animation


@pytest.mark.parametrize(
    "options, words",
    [
        (["--animate", "--frames", 0], "argument --frames: expected an integer >= 2, got '0'"),
        (
            ["--animate", "--frames", 22],
            "--frames 22 is more than the motion's 21 samples (one frame a sample at most): "
            "give --frames 21 or fewer, or more --samples",
        ),
        (["--frames", 4], "--frames 4 applies to the animation only: add --animate"),
    ],
)
def test_simulate_refuses_frames_it_cannot_draw(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, options: list[object], words: str
) -> None:
    out = tmp_path / "out"
    status, _, err = cli(capsys, "simulate", "--robot", _robot_file(tmp_path, "6-UPS"),
                         "--motion", "heave", "--samples", 21, *options, "--output", out)  # fmt: skip
    assert status == 2
    assert words in one_line(err)
    assert not out.exists()


def test_a_failing_animation_leaves_the_earlier_results(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    out = tmp_path / "out"
    robot = _robot_file(tmp_path, "3-RPS")
    status, _, err = cli(capsys, "simulate", "--robot", robot, "--motion", "heave",
                         "--samples", 5, "--output", out)  # fmt: skip
    assert status == 0, err
    before = listing(out)

    def fail(*args: object, **kwargs: object) -> int:
        from prp3.errors import OutputFileError

        raise OutputFileError("mechanism.gif: the disk is full")

    monkeypatch.setattr("prp3.plotting.spatial_animation.save_spatial_animation", fail)
    status, _, err = cli(capsys, "simulate", "--robot", robot, "--motion", "tilt",
                         "--samples", 5, "--animate", "--output", out)  # fmt: skip
    assert status == 2
    assert "the disk is full" in one_line(err)
    assert listing(out) == before


def test_the_figure_of_docs_spatial_md_is_the_one_its_script_draws(tmp_path: Path) -> None:
    import importlib.util

    import matplotlib.image

    root = Path(__file__).resolve().parents[1]
    spec = importlib.util.spec_from_file_location(
        "spatial_pose", root / "docs" / "examples" / "spatial_pose.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    drawn, _ = module.draw(tmp_path)
    committed = matplotlib.image.imread(root / "docs" / "figures" / "spatial_pose.png")
    fresh = matplotlib.image.imread(drawn)
    assert committed.shape == fresh.shape
    assert float(np.abs(committed - fresh).mean()) < 1e-3
    text = (root / "docs" / "spatial.md").read_text("utf-8")
    assert "figures/spatial_pose.png" in text
    # the constants docs/spatial.md §15 states
    from prp3.plotting.animation import MAX_FRAMES
    from prp3.plotting.spatial_animation import VIEW

    said = " ".join(text.split("## §15", 1)[1].split())
    assert (
        f"sleeve (a thick bar from its joint frame's origin along its slide, {SLEEVE_FRACTION:g} of"
        in said
    )
    assert f"force is at most {ARROW_FRACTION:g} of the robot's size long" in said
    assert f"(elevation {VIEW[0]:g}°, azimuth −{-VIEW[1]:g}°)" in said
    assert f"`--frames N` samples (default {MAX_FRAMES}," in said
