"""Tests of prp3.plotting: the figures show the right columns, the animation draws the mechanism.

The drawn joint positions are compared with the independent reference geometry
of ``tests/strategies.py`` (written from docs/model.md alone) and with the pixels of
the GIF itself.
"""

from __future__ import annotations

import contextlib
import io
import math
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from PIL import Image

import prp3
from prp3.cli import main
from prp3.drawing import PISTON_HALF_LENGTH, SLEEVE_HALF_LENGTH
from prp3.io.results import results_table
from prp3.model.parameters import Friction, JointFriction
from prp3.plotting import (
    draw_frame,
    figure_names,
    frame_indices,
    mechanism_figure,
    mechanism_frame,
    results_figures,
    save_animation,
    save_figure,
    save_figures,
)
from strategies import REF_E, analytic_motions, ref_base, ref_geometry, ref_slide

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def vertical_table():
    return results_table(*prp3.inverse_dynamics(prp3.Robot(), prp3.paper_motion("vertical", 31)))


def test_importing_prp3_and_plotting_does_not_import_matplotlib():
    code = (
        "import sys, prp3, prp3.plotting, prp3.cli;"
        "print(any(m.startswith('matplotlib') for m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_figure_names_follow_the_paper_numbers():
    assert figure_names("vertical") == {
        "p10": "fig3_p10.png",
        "f21y": "fig4_f21y.png",
        "f21z": "fig5_f21z.png",
        "f10": "f10.png",
        "lambda10": "lambda10.png",
    }
    assert list(figure_names("rotation").values())[:3] == [
        "fig6_p10.png",
        "fig7_f21y.png",
        "fig8_f21z.png",
    ]
    assert list(figure_names(None).values()) == [
        "p10.png",
        "f21y.png",
        "f21z.png",
        "f10.png",
        "lambda10.png",
    ]


def test_each_figure_plots_the_three_legs_columns_with_labels_and_units(vertical_table):
    figures = results_figures(vertical_table, motion="vertical")
    expected = {  # file name -> (column, factor to the plotted unit, unit)
        "fig3_p10.png": ("p10", 1.0, "(W)"),
        "fig4_f21y.png": ("f21y", 1.0, "(N)"),
        "fig5_f21z.png": ("f21z", 1.0, "(N)"),
        "f10.png": ("f10", 1.0, "(N)"),
        "lambda10.png": ("lambda10", 1000.0, "(mm)"),  # metres drawn in millimetres
    }
    assert list(figures) == list(expected)
    for name, (column, factor, unit) in expected.items():
        (axes,) = figures[name].axes
        lines = [line for line in axes.get_lines() if line.get_label().startswith("leg")]
        assert [line.get_label().split()[1] for line in lines] == ["A", "B", "C"]
        for line, leg in zip(lines, "ABC", strict=True):
            x, y = line.get_data()
            assert np.array_equal(x, vertical_table["t"])
            np.testing.assert_allclose(y, factor * vertical_table[f"{column}_{leg}"], rtol=1e-15)
        assert axes.get_xlabel() == "time $t$ (s)"
        assert axes.get_ylabel().endswith(unit)
        assert axes.get_legend() is not None
        assert "vertical motion" in axes.get_title()
    assert figures["fig3_p10.png"]._suptitle.get_text().startswith("Fig. 3")
    assert figures["fig5_f21z.png"]._suptitle.get_text().startswith("Fig. 5")
    assert not figures["f10.png"]._suptitle.get_text().startswith("Fig.")


def test_user_trajectory_figures_name_the_file(vertical_table):
    figures = results_figures(vertical_table, source="path.csv")
    assert next(iter(figures)) == "p10.png"
    assert figures["p10.png"].axes[0].get_title() == "trajectory path.csv"


def test_save_figures_writes_png_files(tmp_path, vertical_table):
    paths = save_figures(vertical_table, tmp_path, motion="rotation")
    assert [p.name for p in paths] == list(figure_names("rotation").values())
    for path in paths:
        assert path.read_bytes()[:8] == PNG_MAGIC
        with Image.open(path) as image:
            assert image.size == (960, 552)  # 8 x 4.6 in at 120 dpi
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(p.name for p in paths)


def test_save_figure_failure_leaves_no_file(tmp_path, vertical_table):
    figure = results_figures(vertical_table)["f10.png"]
    with pytest.raises(prp3.OutputFileError):
        save_figure(figure, tmp_path / "missing" / "f10.png")
    assert list(tmp_path.iterdir()) == []


# ---------------------------------------------------------------- animation
def test_frame_indices_keep_the_ends_and_at_most_max_frames():
    assert frame_indices(3, 100).tolist() == [0, 1, 2]
    picked = frame_indices(301, 100)
    assert len(picked) == 100 and picked[0] == 0 and picked[-1] == 300
    assert (np.diff(picked) > 0).all()


def test_mechanism_frame_at_the_central_configuration_by_hand():
    # φ = 0, G = O, l0 = 0.3: P_i = B_i0 + s·e_i with s = l0/√3 and h = l0·√3/2:
    # P_A = (0, −l0) + s·(1/2, √3/2) = (s/2, −0.15)
    # P_B = (h, 0.15) + s·(−1, 0)     = (h − s, 0.15)
    # P_C = (−h, 0.15) + s·(1/2, −√3/2) = (−h + s/2, 0)
    robot = prp3.Robot()
    kin = prp3.inverse_kinematics(robot, prp3.paper_motion("rotation", 3))
    frame = mechanism_frame(robot, kin, 0)
    s, h = 0.3 / math.sqrt(3.0), 0.3 * math.sqrt(3.0) / 2.0
    np.testing.assert_allclose(
        frame.joints, [[s / 2, -0.15], [h - s, 0.15], [-h + s / 2, 0.0]], atol=1e-15
    )
    # platform = base turned by 180°: vertices at 90°, 210°, 330° at distance l0
    np.testing.assert_allclose(frame.platform, [[0, 0.3], [-h, -0.15], [h, -0.15]], atol=1e-15)
    assert frame.t == 0.0 and frame.trace.shape == (1, 2)


@settings(max_examples=25)
@given(analytic_motions(l0=0.3))
def test_drawn_mechanism_matches_the_reference_geometry(motion):
    robot = prp3.Robot()
    kin = prp3.inverse_kinematics(robot, motion.motion(np.linspace(0.0, motion.duration, 9)))
    for index in (0, 4, 8):
        frame = mechanism_frame(robot, kin, index)
        pose = kin.motion.pose[index]
        ref = ref_geometry(robot.l0, pose)
        np.testing.assert_allclose(frame.joints, ref.joint, atol=1e-12)
        np.testing.assert_allclose(frame.base, ref_base(robot.l0), atol=1e-15)
        np.testing.assert_allclose(frame.centre, pose[:2], atol=0)
        # the piston bar lies on the base edge, centred on P_i; the sleeve along d_i
        half_piston = PISTON_HALF_LENGTH * robot.l0 * REF_E
        half_sleeve = SLEEVE_HALF_LENGTH * robot.l0 * ref_slide(pose[2])
        np.testing.assert_allclose(
            frame.pistons[:, 1] - frame.pistons[:, 0], 2 * half_piston, atol=1e-12
        )
        np.testing.assert_allclose(frame.pistons.mean(axis=1), ref.joint, atol=1e-12)
        np.testing.assert_allclose(
            frame.sleeves[:, 1] - frame.sleeves[:, 0], 2 * half_sleeve, atol=1e-12
        )
        # the platform edge i (vertices i+1, i+2) passes through the sleeve at P_i, along d_i
        for i in range(3):
            a, b = frame.platform[(i + 1) % 3], frame.platform[(i + 2) % 3]
            edge = (b - a) / np.linalg.norm(b - a)
            offset = frame.joints[i] - a
            assert abs(edge[0] * offset[1] - edge[1] * offset[0]) < 1e-12
            assert abs(abs(edge @ ref.slide[i]) - 1.0) < 1e-12
            assert (np.abs(frame.platform.mean(axis=0) - pose[:2]) < 1e-12).all()  # centroid is G


def test_draw_frame_puts_the_artists_where_the_frame_says():
    robot = prp3.Robot()
    kin = prp3.inverse_kinematics(robot, prp3.law_motion([0.02, -0.01, 0.2], 11))
    artists = mechanism_figure(robot, kin)
    for index in (3, 10):
        frame = mechanism_frame(robot, kin, index)
        draw_frame(artists, frame)
        joints = np.column_stack(artists.joints.get_data())
        np.testing.assert_array_equal(joints, kin.geometry.joint[index])
        np.testing.assert_allclose(
            joints, ref_geometry(robot.l0, kin.motion.pose[index]).joint, atol=1e-12
        )
        np.testing.assert_array_equal(artists.platform.get_xy()[:3], frame.platform)
        for j in range(3):
            np.testing.assert_array_equal(
                np.column_stack(artists.pistons[j].get_data()), frame.pistons[j]
            )
            np.testing.assert_array_equal(
                np.column_stack(artists.sleeves[j].get_data()), frame.sleeves[j]
            )
        assert np.column_stack(artists.trace.get_data()).shape == (index + 1, 2)
        assert artists.clock.get_text() == f"t = {kin.motion.t[index]:7.3f} s"


def test_gif_has_the_frames_and_the_joints_are_drawn_at_their_pixels(tmp_path):
    robot = prp3.Robot()
    kin = prp3.inverse_kinematics(robot, prp3.paper_motion("rotation", 7))
    reports = []
    path = tmp_path / "mechanism.gif"
    assert save_animation(robot, kin, path, progress=lambda d, n: reports.append((d, n))) == 7
    assert reports[-1] == (7, 7) and len(reports) == 7
    assert [p.name for p in tmp_path.iterdir()] == ["mechanism.gif"]
    # the same layout the writer used: lay out once, then freeze (as save_animation does)
    artists = mechanism_figure(robot, kin)
    artists.canvas.draw()
    to_pixels = artists.figure.axes[0].transData
    with Image.open(path) as gif:
        assert gif.n_frames == 7
        assert gif.info["loop"] == 0
        for index in (0, 3, 6):
            gif.seek(index)
            rgb = np.asarray(gif.convert("RGB")).astype(int)
            height = rgb.shape[0]
            joints = ref_geometry(robot.l0, kin.motion.pose[index]).joint
            for x, y in to_pixels.transform(joints):
                row, col = round(height - y), round(x)
                # the joint marker is a white disc on the coloured piston and black sleeve
                assert (rgb[row - 1 : row + 2, col - 1 : col + 2] >= 250).all()
                ring = rgb[row - 6 : row + 7, col - 6 : col + 7]
                assert (ring.min(axis=-1) < 100).any()  # dark edge or sleeve around it


# ------------------------------------------------------------------ friction
@pytest.fixture(scope="module")
def friction_table():
    robot = prp3.Robot(
        friction=Friction(
            actuator=JointFriction(viscous=20.0, coulomb=2.0, mu=0.05, smoothing=1e-3),
            revolute=JointFriction(viscous=0.01, coulomb=0.005),
            sleeve=JointFriction(viscous=5.0, coulomb=1.0),
        )
    )
    return results_table(*prp3.inverse_dynamics(robot, prp3.paper_motion("rotation", 31)))


def test_friction_figure_plots_the_three_kinds_per_leg(friction_table):
    figures = results_figures(friction_table, motion="rotation")
    assert list(figures)[-1] == "friction.png"
    assert list(figures)[:-1] == list(figure_names("rotation").values())
    figure = figures["friction.png"]
    assert [axes.get_ylabel() for axes in figure.axes] == [
        "fric10 (N)",
        "fric21 (N·m)",
        "fric32 (N)",
    ]
    for axes, column in zip(figure.axes, ("fric10", "fric21", "fric32"), strict=True):
        lines = [line for line in axes.get_lines() if line.get_label().startswith("leg")]
        assert [line.get_label() for line in lines] == ["leg A", "leg B", "leg C"]
        for line, leg in zip(lines, "ABC", strict=True):
            x, y = line.get_data()
            assert np.array_equal(x, friction_table["t"])
            assert np.array_equal(y, friction_table[f"{column}_{leg}"])
            assert np.abs(y).max() > 0.0  # every kind of joint rubs in the rotation
    assert figure.axes[-1].get_xlabel() == "time $t$ (s)"
    assert "rotation" in figure._suptitle.get_text()
    # no friction columns, no friction figure
    assert "friction.png" not in results_figures(
        results_table(*prp3.inverse_dynamics(prp3.Robot(), prp3.paper_motion("rotation", 5)))
    )


def test_simulate_plots_write_the_friction_figure(tmp_path):
    robot = tmp_path / "robot.toml"
    robot.write_text("[friction.sleeve]\nviscous = 5.0\n")
    out = tmp_path / "out"
    with contextlib.redirect_stdout(io.StringIO()):
        status = main(
            ["simulate", "--robot", str(robot), "--motion", "vertical", "-o", str(out), "--plots"]
        )
    assert status == 0
    path = out / "friction.png"
    assert path.read_bytes()[:8] == PNG_MAGIC
    with Image.open(path) as image:
        assert image.size == (960, 864)  # 8 x 7.2 in at 120 dpi
