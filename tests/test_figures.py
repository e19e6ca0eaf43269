"""Figures that show their data: nothing covers a curve or the region, every axis says
what it is, coinciding curves stay visible, the animation names its legs and plays in
real time.

Geometry of the drawn artists is checked in display coordinates after a draw
(what the PNG shows); colours against the legs' styles.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

import prp3
from prp3.analysis.workspace import orientation_scan, workspace_slice
from prp3.io.results import results_table
from prp3.plotting.animation import END_HOLD_MS, frame_schedule, mechanism_figure, save_animation
from prp3.plotting.figures import LEG_STYLES, results_figures
from prp3.plotting.workspace import workspace_figure


def _drawn(figure):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(figure)
    canvas.draw()
    return canvas.get_renderer()


# ---------------------------------------------------------------- workspace map
@pytest.mark.parametrize("stroke", [(-0.05, 0.05), None])
def test_the_workspace_map_covers_nothing_and_says_what_it_plots(stroke):
    # was: a text box over the region (or the A0 corner), the legend over the fraction
    # curve, a right title that did not match, and an unlabelled log axis
    robot = prp3.Robot(limits=prp3.Limits(stroke=stroke))
    grid = np.linspace(-0.07, 0.07, 31) if stroke else np.linspace(-0.3, 0.3, 31)
    ws = workspace_slice(robot, 0.1, grid, grid)
    scan = orientation_scan(robot, grid, grid, np.linspace(-0.4, 0.5, 19))
    figure = workspace_figure(robot, ws, scan)
    renderer = _drawn(figure)
    left, right = figure.axes[0], figure.axes[1]
    for axes in (left, right):
        window = axes.get_window_extent(renderer)
        legend = axes.get_legend()
        assert legend is not None
        assert not legend.get_window_extent(renderer).overlaps(window)  # outside the data
        assert len(axes.texts) == 0  # no note drawn over the data
    assert "no singular point at this φ" in left.get_title()
    assert "reachable area" in left.get_legend().get_texts()[0].get_text() or stroke is None
    title = right.get_title()
    assert ("reachable area" if stroke else "reachable fraction of the grid") in title
    assert "κ" in title and "log scale" in title
    twin = [a for a in figure.axes if a.get_yscale() == "log"]
    assert twin and all("log scale" in a.get_ylabel() for a in twin)


@pytest.mark.parametrize("stroke", [(-0.05, 0.05), None])
def test_the_workspace_map_is_whole_and_its_colour_bar_beside_it(stroke):
    # was: the triangles' tips cut at the window's edge, the colour bar far from the map, the
    # area in cm² beside m² everywhere else, the base triangle in the red of the singularities
    from matplotlib.colors import to_hex

    robot = prp3.Robot(limits=prp3.Limits(stroke=stroke))
    grid = np.linspace(-0.07, 0.07, 31) if stroke else np.linspace(-0.3, 0.3, 31)
    ws = workspace_slice(robot, 0.1, grid, grid)
    scan = orientation_scan(robot, grid, grid, np.linspace(-0.4, 0.5, 19))
    figure = workspace_figure(robot, ws, scan)
    renderer = _drawn(figure)
    left, right = figure.axes[0], figure.axes[1]
    x0, x1 = left.get_xlim()
    y0, y1 = left.get_ylim()
    for line in left.get_lines():  # every drawn outline lies inside the window
        xs, ys = np.asarray(line.get_xdata()), np.asarray(line.get_ydata())
        assert xs.min() > x0 and xs.max() < x1 and ys.min() > y0 and ys.max() < y1, line
        if "triangle" in line.get_label():
            assert to_hex(line.get_color()) != to_hex("tab:red")
    (bar,) = left.child_axes  # an inset of the map's axes: it follows the map
    assert "condition number κ of J" in bar.get_ylabel()
    gap = bar.get_window_extent(renderer).x0 - left.get_window_extent(renderer).x1
    assert 0 <= gap <= 0.05 * figure.bbox.width  # beside the map, not across the panel
    labels = [text.get_text() for text in left.get_legend().get_texts()]
    if stroke:
        assert any("m²" in text for text in labels) and not any("cm" in t for t in labels)
        assert right.get_ylabel() == "reachable area (m²)"
    else:
        assert "unreachable grid points" not in labels  # there is none
    assert min(text.get_fontsize() for text in left.get_legend().get_texts()) >= 9
    _inside_the_figure(figure, renderer)


def test_a_log_colour_scale_says_so():
    robot = prp3.Robot()
    grid = np.linspace(-0.3, 0.3, 41)
    ws = workspace_slice(robot, 0.9, grid, grid)  # κ spans more than a decade near π/3
    finite = ws.condition[ws.reachable & np.isfinite(ws.condition)]
    assert finite.max() / finite.min() > 10.0
    figure = workspace_figure(robot, ws)
    _drawn(figure)
    (colorbar,) = figure.axes[0].child_axes  # the colour bar is an inset of the map's axes
    assert colorbar.get_yscale() == "log" and "(log scale)" in colorbar.get_ylabel()


# ---------------------------------------------------------------- curves of the legs
@pytest.mark.parametrize(
    ("motion", "note"),
    [("rotation", "legs A, B and C coincide"), ("vertical", "legs B and C coincide")],
)
def test_coinciding_curves_are_said_and_stay_visible(motion, note):
    # was: lambda10.png of the rotation showed one curve, leg A hidden, without a word
    table = results_table(*prp3.inverse_dynamics(prp3.Robot(), prp3.paper_motion(motion, 61)))
    figure = results_figures(table, motion=motion)["lambda10.png"]
    axes = figure.axes[0]
    assert note in axes.get_title()
    lines = axes.get_lines()[:3]
    assert len({line.get_marker() for line in lines}) == 3
    # the markers of the legs fall on different samples: each leg shows its own
    shown = [set(np.flatnonzero(_marked(line))) for line in lines]
    assert all(shown) and not (shown[0] & shown[1] or shown[0] & shown[2] or shown[1] & shown[2])
    # curves that differ get no such note
    assert "coincide" not in results_figures(table, motion=motion)["f10.png"].axes[0].get_title()


def _marked(line) -> np.ndarray:
    start, step = line.get_markevery()
    marked = np.zeros(len(line.get_xdata()), dtype=bool)
    marked[start::step] = True
    return marked


# ---------------------------------------------------------------- animation
def test_the_animation_is_large_names_its_legs_and_colours_its_pistons():
    # was: 448 px, a blue "pistons" swatch for three colours, legs not named
    robot = prp3.Robot()
    kin = prp3.inverse_kinematics(robot, prp3.paper_motion("rotation", 11))
    artists = mechanism_figure(robot, kin)
    artists.canvas.draw()
    width, height = artists.canvas.get_width_height()
    assert min(width, height) >= 640
    axes = artists.figure.axes[0]
    names = {t.get_text(): t.get_color() for t in axes.texts}
    for leg in "ABC":
        assert names[f"leg {leg}"] == LEG_STYLES[leg][0]
    legend = axes.get_legend()
    labels = [t.get_text() for t in legend.get_texts()]
    assert "pistons of legs A, B, C" in labels
    from matplotlib.colors import to_hex

    swatch = legend.legend_handles[labels.index("pistons of legs A, B, C")]
    pistons = [to_hex(line.get_color()) for line in artists.pistons]
    assert pistons == [to_hex(LEG_STYLES[leg][0]) for leg in "ABC"]
    # the swatch is drawn by the piston lines themselves (a tuple handle): their colours
    assert swatch is not None and "real time" in axes.get_title()


def test_a_two_second_motion_plays_in_two_seconds(tmp_path):
    # was: 100 frames at 30 frames per second: 2 s of motion over 3.3 s
    robot = prp3.Robot()
    motion = prp3.law_motion([0.01, 0.0, 0.1], 201)  # eq. (4) law over 3 s, resampled below
    t = np.linspace(0.0, 2.0, 201)
    two = prp3.Motion(t=t, pose=motion.pose, velocity=motion.velocity * 1.5,
                      acceleration=motion.acceleration * 2.25)  # fmt: skip
    kin = prp3.inverse_kinematics(robot, two)
    path = tmp_path / "m.gif"
    frames = save_animation(robot, kin, path)
    with Image.open(path) as gif:
        durations = []
        for k in range(gif.n_frames):
            gif.seek(k)
            durations.append(gif.info["duration"])
    assert len(durations) == frames <= 100
    assert sum(durations[:-1]) == 2000 and durations[-1] == END_HOLD_MS


@settings(max_examples=60, deadline=None)
@given(
    st.integers(2, 3000),
    st.floats(0.02, 100.0),
    st.integers(2, 200),
    st.booleans(),
)
def test_frame_schedule_plays_in_real_time(samples, duration, max_frames, uneven):
    t = np.linspace(0.0, duration, samples)
    if uneven and samples > 2:
        t = duration * np.sort(np.random.default_rng(samples).uniform(0, 1, samples))
        t[0], t[-1] = 0.0, duration
        t = np.unique(t)
    indices, durations = frame_schedule(t, max_frames)
    assert indices[0] == 0 and indices[-1] == t.size - 1 and (np.diff(indices) > 0).all()
    assert len(indices) == len(durations) <= max_frames
    assert all(d % 10 == 0 and d >= 20 for d in durations)
    assert durations[-1] == END_HOLD_MS
    # the frames add up to the motion's duration (GIF delays count hundredths of a second)
    assert abs(sum(durations[:-1]) - 1000.0 * (t[-1] - t[0])) <= 5.0 + 1e-9
    # each frame is shown from its sample's time to the next frame's (within 10 ms)
    starts = np.cumsum([0, *durations[:-1]]) / 1000.0
    assert np.abs(starts - (t[indices] - t[0])).max() <= 0.005 + 1e-9


# ---------------------------------------------------------------- friction figure
@pytest.mark.parametrize(
    ("motion", "notes"),
    [
        ("rotation", ["legs A, B and C coincide"] * 3),
        ("vertical", ["legs B and C coincide", "zero for every leg", "legs A and C coincide"]),
    ],
)
def test_the_friction_figure_says_which_curves_coincide(motion, notes):
    # was: three revolute curves of the rotation on top of each other, without a word
    from prp3.model.parameters import Friction, JointFriction
    from prp3.plotting.figures import friction_figure

    joint = JointFriction(viscous=1.0, coulomb=0.5, smoothing=1e-3)
    robot = prp3.Robot(friction=Friction(actuator=joint, revolute=joint, sleeve=joint))
    table = results_table(*prp3.inverse_dynamics(robot, prp3.paper_motion(motion, 61)))
    figure = friction_figure(table, motion=motion)
    for axes, note in zip(figure.axes[:3], notes, strict=True):
        assert note in axes.get_title(loc="left")
        lines = axes.get_lines()[:3]
        assert len({line.get_marker() for line in lines}) == 3
        shown = [set(np.flatnonzero(_marked(line))) for line in lines]
        assert not (shown[0] & shown[1] or shown[0] & shown[2] or shown[1] & shown[2])


# ---------------------------------------------------------------- tracking figure
def test_the_tracking_figure_marks_the_stop_and_names_only_gains_in_use(tmp_path, capsys):
    # was: a run stopped at 0.42 s drawn as if it ended there, and KP, KD printed for the
    # feed-forward controller, which has no gains
    from prp3.cli import main
    from prp3.plotting.control import tracking_figure

    robot, model = tmp_path / "r.toml", tmp_path / "m.toml"
    robot.write_text("[limits]\nstroke = [-0.06, 0.06]\n")
    model.write_text("[platform]\nmass = 3.3\n[limits]\nstroke = [-0.06, 0.06]\n")
    argv = ["control", "--robot", str(robot), "--model", str(model), "--motion", "vertical",
            "--plant", "prp3", "--controller", "feedforward", "--rate", "200"]  # fmt: skip
    assert main([*argv, "-o", str(tmp_path / "ff")]) == 1  # stopped at the stroke
    out = capsys.readouterr().out
    assert "KP" not in out and "no gains" in out
    import csv

    with open(tmp_path / "ff" / "tracking.csv", newline="") as stream:
        rows = list(csv.DictReader(stream))
    table = {name: np.array([float(row[name]) for row in rows]) for name in rows[0]}
    figure = tracking_figure(table, title="t", subtitle="s", stop="stroke", end=3.0)
    renderer = _drawn(figure)
    last = float(table["t"][-1])
    assert last < 1.0
    for axes in figure.axes:
        assert axes.get_xlim() == (0.0, 3.0)  # the plan's span: the stop shows
        stops = [line for line in axes.get_lines() if "stop" in str(line.get_label())]
        assert len(stops) == 1 and list(stops[0].get_xdata()) == [last, last]
    assert "stopped early: stroke" in figure.axes[-1].get_xlabel()
    _inside_the_figure(figure, renderer)
    completed = tracking_figure(table, title="t")
    assert not any(
        "stop" in str(line.get_label()) for a in completed.axes for line in a.get_lines()
    )


def _inside_the_figure(figure, renderer) -> None:
    """Every title, axis label and legend lies inside the figure (nothing clipped at its edge)."""
    bounds = figure.bbox
    texts = [figure._suptitle] if figure._suptitle is not None else []
    for axes in figure.axes:
        texts += [axes.title, axes._left_title, axes._right_title, axes.xaxis.label,
                  axes.yaxis.label]  # fmt: skip
        if axes.get_legend() is not None:
            texts.append(axes.get_legend())
    texts += list(figure.legends)
    for text in texts:
        if text.get_visible() and (not hasattr(text, "get_text") or text.get_text()):
            box = text.get_window_extent(renderer)
            assert box.x0 >= bounds.x0 - 1 and box.x1 <= bounds.x1 + 1, text
            assert box.y0 >= bounds.y0 - 1 and box.y1 <= bounds.y1 + 1, text


# ---------------------------------------------------------------- design figures
@pytest.fixture(scope="module")
def one_parameter_designs():
    from prp3.apps.design_evaluation import evaluate_designs
    from prp3.apps.sweep_spec import design_values, sweep_spec

    spec = sweep_spec({"designs": 9, "sampling": "grid",
                       "parameters": {"platform.mass": [2.0, 4.0]},
                       "task": {"motions": ["vertical"], "samples": 31}})  # fmt: skip
    return evaluate_designs(spec.evaluator, design_values(spec))


def test_the_pareto_legend_lies_beside_the_designs(one_parameter_designs):
    # was: the legend drawn in the axes, over the designs
    from prp3.plotting.design import pareto_figure

    columns = one_parameter_designs
    row = {name: values[4] for name, values in columns.items()}
    figure = pareto_figure(columns, "platform.mass", "peak_f10", nominal=row,
                           marks={"optimum": row})  # fmt: skip
    renderer = _drawn(figure)
    (axes,) = figure.axes
    assert axes.get_legend() is None and len(figure.legends) == 1
    assert (
        not figure.legends[0].get_window_extent(renderer).overlaps(axes.get_window_extent(renderer))
    )
    _inside_the_figure(figure, renderer)


def test_the_sensitivity_of_one_parameter_has_its_whole_title(one_parameter_designs):
    # was: "Sensitivity of peak_f10 to the parameters (..." cut at both edges, and a "mean over
    # the other parameters" when there is none
    from prp3.plotting.design import sensitivity_figure

    columns = one_parameter_designs
    row = {name: values[4] for name, values in columns.items()}
    figure = sensitivity_figure(columns, ("platform.mass",), "peak_f10", nominal=row)
    renderer = _drawn(figure)
    assert figure._suptitle.get_text() == "Sensitivity of peak_f10 to platform.mass (9 designs)"
    labels = [text.get_text() for text in figure.legends[0].get_texts()]
    assert labels == ["mean of the designs in 12 bins", "nominal design"]
    assert (
        not figure.legends[0]
        .get_window_extent(renderer)
        .overlaps(figure.axes[0].get_window_extent(renderer))
    )
    _inside_the_figure(figure, renderer)
    two = sensitivity_figure(columns, ("platform.mass", "platform.mass"), "peak_f10")
    assert "to 2 parameters" in two._suptitle.get_text()
