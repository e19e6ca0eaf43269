"""``prp3 forward`` says how far the open-loop motion is from its plan, and that it diverges.

The growth rate of :func:`prp3.analysis.forward.open_loop_growth_rate` (eigenvalues of
the linearised motion at rest) is held against an independent route: the
motion integrated from a tiny perturbation of the central configuration under
the constant forces that hold the platform still there, whose error grows by
``e^{rate}`` per second once the growing mode dominates.  The drift the
summary prints is recomputed here from the two ``results.csv`` files.
"""

from __future__ import annotations

import csv
import math
import re
from pathlib import Path

import numpy as np
import pytest

from clitools import cli
from prp3 import Motion, Robot, inverse_dynamics
from prp3.analysis.forward import forward_dynamics, open_loop_growth_rate
from prp3.cli import main


def poses(path: Path) -> tuple[np.ndarray, np.ndarray]:
    with path.open(newline="") as stream:
        rows = list(csv.DictReader(stream))
    t = np.array([float(row["t"]) for row in rows])
    return t, np.array([[float(row[q]) for q in ("x", "y", "phi")] for row in rows])


def measured_growth(robot: Robot, pose: np.ndarray) -> float:
    """ln(|e(2 s)| / |e(1 s)|) of a perturbed rest state under the forces that hold it."""
    still = Motion(t=0.0, pose=pose, velocity=np.zeros(3), acceleration=np.zeros(3))
    holding = inverse_dynamics(robot, still)[1].f10  # static forces, (3,)
    start = pose + np.array([1e-8, -2e-8, 3e-8])  # ~1e-3 at 2 s: still linear
    run = forward_dynamics(robot, lambda t: holding, [0.0, 1.0, 2.0], start, np.zeros(3),
                           rtol=1e-10, atol=1e-13)  # fmt: skip
    error = np.linalg.norm(run.motion.pose - pose, axis=1)
    return math.log(error[2] / error[1])


@pytest.mark.parametrize("pose", [[0.0, 0.0, 0.0], [0.01, -0.02, 0.2]])
def test_the_growth_rate_is_what_the_integrated_motion_shows(pose):
    robot = Robot()
    rate = open_loop_growth_rate(robot, pose)
    assert rate == pytest.approx(measured_growth(robot, np.array(pose)), rel=5e-3)
    if pose == [0.0, 0.0, 0.0]:
        assert rate == pytest.approx(6.18, abs=0.01)  # the "about 6.2 1/s"


def test_without_gravity_there_is_no_exponential_growth():
    assert open_loop_growth_rate(Robot(gravity=(0.0, 0.0)), [0.0, 0.0, 0.0]) == 0.0


@pytest.fixture(scope="module")
def planned(tmp_path_factory) -> Path:
    """``results.csv`` of the paper's rotation law over 1 s (eq. 4 with T = 1 s, by hand)."""
    folder = tmp_path_factory.mktemp("plan")
    t = np.linspace(0.0, 1.0, 101)
    w, star = math.pi, math.pi / 12  # phi = star (1 - cos w t)
    rows = [
        (tk, 0, 0, star * (1 - math.cos(w * tk)), 0, 0, star * w * math.sin(w * tk),
         0, 0, star * w * w * math.cos(w * tk))
        for tk in t
    ]  # fmt: skip
    (folder / "traj.csv").write_text(
        "t,x,y,phi,dx,dy,dphi,ddx,ddy,ddphi\n"
        + "".join(",".join(repr(float(v)) for v in row) + "\n" for row in rows)
    )
    assert main(["simulate", "--trajectory", str(folder / "traj.csv"), "-o", str(folder)]) == 0
    return folder / "results.csv"


def test_forward_reports_the_drift_from_the_plan(planned, tmp_path, capsys):
    # was: only "f10 of the integrated motion matches the input forces", which says
    # nothing about the plan (the paper's rotation ends ~1e-4 rad off after 3 s)
    capsys.readouterr()
    status, out, _ = cli(capsys, "forward", "--forces", planned, "-o", tmp_path / "fwd")
    assert status == 0
    t, plan = poses(planned)
    t_back, back = poses(tmp_path / "fwd" / "results.csv")
    assert np.array_equal(t, t_back)
    dG = np.hypot(*(back[:, :2] - plan[:, :2]).T)
    dphi = np.abs(back[:, 2] - plan[:, 2])
    assert 0.0 < dphi.max() < 1e-4
    expected = (
        f"  drift from the planned motion (x, y, phi of {planned}):\n"
        f"    max |dG| = {dG.max():.3g} m at t = {t[dG.argmax()]:.6g} s, "
        f"max |dphi| = {dphi.max():.3g} rad at t = {t[dphi.argmax()]:.6g} s\n"
        f"    final (t = 1 s): |dG| = {dG[-1]:.3g} m, |dphi| = {dphi[-1]:.3g} rad\n"
    )
    assert expected in out
    found = re.search(r"open-loop force control diverges: near the initial pose errors grow "
                      r"like e\^\(([0-9.]+) t\)", out)  # fmt: skip
    assert found is not None
    assert float(found[1]) == pytest.approx(measured_growth(Robot(), np.zeros(3)), rel=0.01)


def test_other_output_times_compare_with_the_interpolated_plan(planned, tmp_path, capsys):
    capsys.readouterr()
    status, out, _ = cli(capsys, "forward", "--forces", planned, "--samples", "11",
                         "-o", tmp_path / "fwd")  # fmt: skip
    assert status == 0
    assert "results.csv, interpolated by a cubic spline):" in out
    _, back = poses(tmp_path / "fwd" / "results.csv")
    t = np.linspace(0.0, 1.0, 11)
    plan_phi = math.pi / 12 * (1.0 - np.cos(math.pi * t))  # the law, by hand
    dphi = np.abs(back[:, 2] - plan_phi)
    printed = float(re.search(r"max \|dphi\| = (\S+) rad", out)[1])
    # 3 digits printed; the spline through 101 planned samples is within 1e-7 rad of the law
    assert printed == pytest.approx(dphi.max(), rel=5e-3, abs=1e-7)


def test_a_force_table_has_no_plan_but_still_diverges(tmp_path, capsys):
    table = tmp_path / "push.csv"
    table.write_text(
        "t,f10_A,f10_B,f10_C\n0,31.8589,-8.4957,-23.3632\n0.5,31.8589,-8.4957,-23.3632\n"
    )
    status, out, _ = cli(capsys, "forward", "--forces", table, "-o", tmp_path / "fwd")
    assert status == 0
    assert "drift from the planned motion" not in out
    assert "open-loop force control diverges" in out
