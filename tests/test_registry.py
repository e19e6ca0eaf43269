"""One registry of the output quantities (``prp3.io.results.OUTPUT_QUANTITIES``).

The columns of ``results.csv``, the labels of the figures and the units of the
run summary come from it: a quantity's unit or symbol is written once.  The
expected texts below are written out here, not taken from the registry.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings

import prp3
from prp3.apps.runs import simulate_table, summarize, summary_text
from prp3.errors import ParameterError
from prp3.io.results import OUTPUT_QUANTITIES, output_quantity, result_columns, results_table
from prp3.model.parameters import Friction, JointFriction
from strategies import scenarios

#: The contract's units (docs/model.md, section *Quantities and signs*).
UNITS = {
    "t": "s", "x": "m", "y": "m", "phi": "rad",
    "lambda10": "m", "dlambda10": "m/s", "ddlambda10": "m/s²",
    "lambda32": "m", "dlambda32": "m/s", "ddlambda32": "m/s²",
    "f10": "N", "p10": "W", "f21y": "N", "f21z": "N",
    "n10": "N", "m10": "N·m", "n32": "N", "m32": "N·m",
    "fric10": "N", "fric21": "N·m", "fric32": "N",
    "fx": "N", "fy": "N", "mz": "N·m",
}  # fmt: skip

FRICTION = Friction(actuator=JointFriction(viscous=2.0), revolute=JointFriction(viscous=0.1))


def test_the_registry_gives_every_quantity_its_documented_unit() -> None:
    assert {name: q.unit for name, q in OUTPUT_QUANTITIES.items()} == UNITS
    assert all(q.description and q.symbol for q in OUTPUT_QUANTITIES.values())


def test_the_columns_written_are_the_registry_in_order() -> None:
    robot = prp3.Robot(friction=FRICTION)
    table = simulate_table(robot, prp3.paper_motion("vertical", 5))
    expected = ["t", "x", "y", "phi"]
    expected += [f"{q}_{leg}" for leg in "ABC" for q in list(UNITS)[4:18]]
    expected += [f"{q}_{leg}" for leg in "ABC" for q in ("fric10", "fric21", "fric32")]
    assert list(table) == expected == list(result_columns(friction=True))
    assert [output_quantity(c).name for c in table][-1] == "fric32"
    with pytest.raises(ParameterError, match=r"not a column of results\.csv"):
        output_quantity("f10_D")


def test_figure_labels_and_summary_units_come_from_the_registry() -> None:
    pytest.importorskip("matplotlib")
    from prp3.plotting.figures import friction_figure, results_figures

    robot = prp3.Robot(friction=FRICTION)
    table = simulate_table(robot, prp3.paper_motion("vertical", 7))
    figures = results_figures(table, motion="vertical")
    labels = {name: fig.axes[0].get_ylabel() for name, fig in figures.items()}
    assert labels["fig3_p10.png"] == "$p_{10}$ (W)"
    assert labels["f10.png"] == "$f_{10}$ (N)"
    assert labels["lambda10.png"] == "$\\lambda_{10}$ (mm)"
    friction = friction_figure(table, motion="vertical")
    assert [a.get_ylabel() for a in friction.axes if a.get_ylabel()] == [
        "fric10 (N)",
        "fric21 (N·m)",
        "fric32 (N)",
    ]
    text = summary_text(summarize(table, np.zeros(7)), "heading", [])
    assert "peak |f10| (N)" in text and "peak |p10| (W)" in text and "peak |f21| (N)" in text


@settings(max_examples=8, deadline=None)
@given(scenario=scenarios())
def test_the_run_table_is_the_results_table_bit_for_bit(scenario) -> None:
    # simulate_table takes the columns straight from the kernel (no joint and body vectors)
    robot, analytic = scenario
    motion = analytic.motion(np.linspace(0.0, analytic.duration, 20))
    friction = Friction(actuator=JointFriction(viscous=1.5, coulomb=0.3))
    for subject in (robot, replace(robot, friction=friction)):
        expected = results_table(*prp3.inverse_dynamics(subject, motion))
        table = simulate_table(subject, motion, chunk=7)
        assert list(table) == list(expected)
        for name, column in expected.items():
            assert np.array_equal(table[name], column), name


def test_an_overflow_in_a_later_chunk_names_its_sample_and_time() -> None:
    motion = prp3.paper_motion("vertical", 10)
    velocity = motion.velocity.copy()
    velocity[8] = [0.0, 0.0, 1e200]
    spoilt = prp3.Motion(
        t=motion.t, pose=motion.pose, velocity=velocity, acceleration=motion.acceleration
    )
    with pytest.raises(prp3.TrajectoryError, match="the results overflow") as info:
        simulate_table(prp3.Robot(), spoilt, chunk=3)
    assert (info.value.sample, info.value.time) == (8, float(motion.t[8]))
