"""End-to-end tests of the command line: ``prp3 simulate``, ``prp3 robot``, ``--version``.

Most tests call ``prp3.cli.main([...])`` in-process with ``tmp_path``; a few run
the installed ``prp3`` and ``python -m prp3`` in a subprocess.  Expected numbers
are derived by hand beside each test: the contract's column list is written out
from docs/model.md, energies come from the change of potential energy between two
poses at rest, stroke violations from the closed-form inverse of eq. (4).
"""

from __future__ import annotations

import csv
import math
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

import prp3
from clitools import cli
from prp3.apps.runs import simulate_table
from prp3.cli import main
from prp3.staged_files import MANIFEST_NAME
from read_only import NAMESPACES, run_read_only

#: The contract's columns (docs/model.md), written out here rather than imported.
PER_LEG = (
    "lambda10 dlambda10 ddlambda10 lambda32 dlambda32 ddlambda32 f10 p10 f21y f21z n10 m10 n32 m32"
).split()
CONTRACT = ["t", "x", "y", "phi"] + [f"{q}_{leg}" for leg in "ABC" for q in PER_LEG]

G = 9.81
W = math.pi / 3.0


def read_results(path: Path) -> tuple[list[str], dict[str, np.ndarray]]:
    with path.open(newline="") as stream:
        rows = list(csv.reader(stream))
    values = np.array([[float(v) for v in row] for row in rows[1:]])
    return rows[0], {name: values[:, j] for j, name in enumerate(rows[0])}


def trapezoid(values: np.ndarray, t: np.ndarray) -> float:
    return float(np.sum(0.5 * (values[1:] + values[:-1]) * np.diff(t)))


def assert_refused(status: int, err: str, out_dir: Path, *fragments: str) -> None:
    """Exit 2, one error line (after any warning) naming the fragments, no output at all."""
    assert status == 2
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert lines and lines[-1].startswith("prp3 simulate: error: ")
    assert all(": error" not in line for line in lines[:-1])
    for fragment in fragments:
        assert fragment in lines[-1], (fragment, lines[-1])
    assert not out_dir.exists()


def paper_law(t: np.ndarray, star: tuple[float, float, float]):
    """Eq. (4) by hand: q = q*(1 − cos wt), q̇ = q*·w·sin wt, q̈ = q*·w²·cos wt."""
    s = np.asarray(star)
    c, n = np.cos(W * t)[:, None], np.sin(W * t)[:, None]
    return s * (1.0 - c), s * W * n, s * W * W * c


def write_trajectory(path: Path, t, pose, velocity=None, acceleration=None, order=None) -> Path:
    data = {"t": t, "x": pose[:, 0], "y": pose[:, 1], "phi": pose[:, 2]}
    if velocity is not None:
        for j, name in enumerate(("dx", "dy", "dphi")):
            data[name] = velocity[:, j]
        for j, name in enumerate(("ddx", "ddy", "ddphi")):
            data[name] = acceleration[:, j]
    columns = order or list(data)
    lines = [",".join(columns)]
    lines += [",".join(repr(float(data[c][k])) for c in columns) for k in range(len(t))]
    path.write_text("\n".join(lines) + "\n")
    return path


# ---------------------------------------------------------------- results.csv
def test_vertical_motion_writes_the_contract_columns_and_301_samples(tmp_path, capsys):
    status, _, err = cli(capsys, "simulate", "--motion", "vertical", "--output", tmp_path / "o")
    assert status == 0, err
    assert err == ""  # no warning, no progress bar (stderr is not a terminal)
    header, table = read_results(tmp_path / "o" / "results.csv")
    assert header == CONTRACT
    assert len(table["t"]) == 301
    assert table["t"][0] == 0.0 and table["t"][-1] == 3.0
    np.testing.assert_allclose(table["y"], 0.025 * (1 - np.cos(W * table["t"])), atol=1e-15)
    assert sorted(p.name for p in (tmp_path / "o").iterdir()) == [MANIFEST_NAME, "results.csv"]


def test_results_are_written_with_full_precision(tmp_path, capsys):
    cli(capsys, "simulate", "--motion", "rotation", "--samples", "11", "--output", tmp_path)
    _, table = read_results(tmp_path / "results.csv")
    kin, dyn = prp3.inverse_dynamics(prp3.Robot(), prp3.paper_motion("rotation", 11))
    # bit for bit: every float was printed with repr and reads back exactly
    assert table["f10_B"].tobytes() == dyn.f10[:, 1].copy().tobytes()
    assert table["ddlambda32_C"].tobytes() == kin.ddlambda32[:, 2].copy().tobytes()
    assert table["m32_A"].tobytes() == dyn.m32[:, 0].copy().tobytes()


def test_energy_delivered_equals_the_potential_energy_gained_vertical(tmp_path, capsys):
    # At rest at t = 0 and t = 3 s, so ∫Σp10 dt = ΔV. G rises by 0.05 m; the joint
    # P_i (where piston and link 2 have their centres of mass) is the crossing of
    # base edge i with platform edge i: P_A follows the horizontal platform edge
    # (Δy = 0.05), P_B stays on the horizontal base edge (Δy = 0), P_C slides on
    # the −60° base edge while the +60° platform edge rises (Δy = 0.05/2).
    # ΔV = g·[m3·0.05 + (m1 + m2)·(0.05 + 0 + 0.025)] = 9.81·0.28125 = 2.7590625 J.
    status, out, _ = cli(capsys, "simulate", "--motion", "vertical", "--output", tmp_path)
    assert status == 0
    _, table = read_results(tmp_path / "results.csv")
    energies = [trapezoid(table[f"p10_{leg}"], table["t"]) for leg in "ABC"]
    assert sum(energies) == pytest.approx(G * 0.28125, rel=1e-4)
    summary = re.search(r"energy \(J\)\s+(\S+)\s+(\S+)\s+(\S+)\s+total (\S+) J", out)
    assert summary is not None, out
    printed = [float(v) for v in summary.groups()]
    assert printed[:3] == pytest.approx(energies, rel=1e-5)
    assert printed[3] == pytest.approx(G * 0.28125, rel=1e-4)


def test_energy_of_the_rotation_is_zero_by_symmetry(tmp_path, capsys):
    # G stays at O; by the 3-fold symmetry the three pistons move by the same λ10
    # along e_i, and Σ sin α_i = 0: the potential energy does not change.
    cli(capsys, "simulate", "--motion", "rotation", "--output", tmp_path)
    _, table = read_results(tmp_path / "results.csv")
    total = sum(trapezoid(table[f"p10_{leg}"], table["t"]) for leg in "ABC")
    largest = max(trapezoid(np.abs(table[f"p10_{leg}"]), table["t"]) for leg in "ABC")
    assert abs(total) < 1e-6 * largest  # the trapezoid rule's error with h = 0.01 s


def test_summary_peaks_match_the_results_file(tmp_path, capsys):
    status, out, _ = cli(capsys, "simulate", "--motion", "rotation", "-o", tmp_path)
    assert status == 0
    _, table = read_results(tmp_path / "results.csv")
    rows = {
        "f10": [np.abs(table[f"f10_{leg}"]).max() for leg in "ABC"],
        "p10": [np.abs(table[f"p10_{leg}"]).max() for leg in "ABC"],
        "f21": [np.hypot(table[f"f21y_{leg}"], table[f"f21z_{leg}"]).max() for leg in "ABC"],
    }
    for name, expected in rows.items():
        found = re.search(rf"peak \|{name}\| \(\w\)\s+(\S+)\s+(\S+)\s+(\S+)", out)
        assert found is not None, out
        assert [float(v) for v in found.groups()] == pytest.approx(expected, rel=1e-5)
    assert "rotation motion" in out and "301 samples" in out and "fast method" in out
    assert f"  {tmp_path / 'results.csv'}" in out.splitlines()


def test_samples_option(tmp_path, capsys):
    cli(capsys, "simulate", "--motion", "vertical", "--samples", "7", "--output", tmp_path)
    _, table = read_results(tmp_path / "results.csv")
    assert table["t"].tolist() == [0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0]


def test_newton_euler_method_gives_the_same_results(tmp_path, capsys):
    for method in ("fast", "paper", "newton-euler"):
        status, out, _ = cli(
            capsys, "simulate", "--motion", "rotation", "--samples", "31",
            "--method", method, "--output", tmp_path / method,
        )  # fmt: skip
        assert status == 0 and f"{method} method" in out
    _, paper = read_results(tmp_path / "fast" / "results.csv")
    for other in ("paper", "newton-euler"):
        _, table = read_results(tmp_path / other / "results.csv")
        for name in CONTRACT:
            scale = max(np.abs(paper[name]).max(), 1.0)
            np.testing.assert_allclose(table[name], paper[name], rtol=0, atol=1e-10 * scale)


def test_robot_file_changes_the_dynamics(tmp_path, capsys):
    # platform mass 6 kg: ΔV = 9.81·(6·0.05 + 1.75·0.075) = 9.81·0.43125 J (see above)
    robot = tmp_path / "robot.toml"
    robot.write_text("[platform]\nmass = 6.0\n")
    cli(capsys, "simulate", "--robot", robot, "--motion", "vertical", "--output", tmp_path / "o")
    _, table = read_results(tmp_path / "o" / "results.csv")
    total = sum(trapezoid(table[f"p10_{leg}"], table["t"]) for leg in "ABC")
    assert total == pytest.approx(G * 0.43125, rel=1e-4)
    # no gravity: the motion starts and ends at rest, so no net energy
    robot.write_text("gravity = [0.0, 0.0]\n")
    cli(capsys, "simulate", "--robot", robot, "--motion", "vertical", "--output", tmp_path / "g")
    _, table = read_results(tmp_path / "g" / "results.csv")
    total = sum(trapezoid(table[f"p10_{leg}"], table["t"]) for leg in "ABC")
    assert abs(total) < 1e-6


def test_max_force_limit_is_a_warning(tmp_path, capsys):
    robot = tmp_path / "robot.toml"
    robot.write_text("[limits]\nmax_force = 20.0\n")  # |f10_A| reaches ~32 N (summary above)
    status, _, err = cli(
        capsys, "simulate", "--robot", robot, "--motion", "vertical", "-o", tmp_path
    )
    assert status == 0
    assert re.search(
        r"warning: \|f10_A\| reaches 3\d\.\d+ N at t = .* above limits.max_force = 20 N", err
    )
    assert "f10_B" not in err  # leg B stays below 20 N
    assert (tmp_path / "results.csv").exists()


# ---------------------------------------------------------------- trajectories
def test_trajectory_with_derivatives_reproduces_the_named_motion(tmp_path, capsys):
    t = np.linspace(0.0, 3.0, 301)
    pose, velocity, acceleration = paper_law(t, (0.0, 0.025, 0.0))
    order = ["phi", "ddy", "t", "dx", "y", "ddx", "x", "dy", "ddphi", "dphi"]  # any order
    traj = write_trajectory(tmp_path / "traj.csv", t, pose, velocity, acceleration, order)
    status, out, err = cli(capsys, "simulate", "--trajectory", traj, "--output", tmp_path / "a")
    assert status == 0 and err == ""
    assert f"trajectory {traj}" in out
    cli(capsys, "simulate", "--motion", "vertical", "--output", tmp_path / "b")
    _, mine = read_results(tmp_path / "a" / "results.csv")
    _, named = read_results(tmp_path / "b" / "results.csv")
    for name in CONTRACT:
        np.testing.assert_allclose(mine[name], named[name], rtol=1e-12, atol=1e-15)


def test_positions_only_trajectory_warns_and_is_accurate(tmp_path, capsys):
    t = np.arange(3001) * 1e-3  # every millisecond
    star = (0.01, 0.02, 0.1)
    pose, velocity, acceleration = paper_law(t, star)
    traj = write_trajectory(tmp_path / "pos.csv", t, pose)
    exact = write_trajectory(tmp_path / "exact.csv", t, pose, velocity, acceleration)
    status, _, err = cli(capsys, "simulate", "--trajectory", traj, "--output", tmp_path / "a")
    assert status == 0
    (warning,) = err.strip().splitlines()
    assert warning.startswith(f"prp3 simulate: warning: {traj}: positions only")
    assert "spline" in warning and "make_interp_spline" in warning
    cli(capsys, "simulate", "--trajectory", exact, "--output", tmp_path / "b")
    _, estimated = read_results(tmp_path / "a" / "results.csv")
    _, analytic = read_results(tmp_path / "b" / "results.csv")
    inner = slice(30, -30)
    for name in ("dlambda10_A", "ddlambda10_B", "f10_C", "f21y_A", "p10_B"):
        scale = np.abs(analytic[name]).max()
        error = np.abs(estimated[name][inner] - analytic[name][inner]).max()
        assert error <= 1e-5 * scale, (name, error / scale)


# ---------------------------------------------------------------- figures, animation
def test_plots_of_the_paper_motions(tmp_path, capsys):
    expected = {
        "vertical": ["fig3_p10.png", "fig4_f21y.png", "fig5_f21z.png"],
        "rotation": ["fig6_p10.png", "fig7_f21y.png", "fig8_f21z.png"],
    }
    for motion, figures in expected.items():
        out_dir = tmp_path / motion
        status, out, _ = cli(
            capsys,
            "simulate",
            "--motion",
            motion,
            "--samples",
            "31",
            "--output",
            out_dir,
            "--plots",
        )
        assert status == 0
        names = sorted(p.name for p in out_dir.iterdir() if p.name != MANIFEST_NAME)
        assert names == sorted([*figures, "f10.png", "lambda10.png", "results.csv"])
        for name in names[:-1]:
            assert (out_dir / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
            assert f"  {out_dir / name}" in out.splitlines()


def test_plots_and_animation_of_a_trajectory(tmp_path, capsys):
    t = np.linspace(0.0, 2.0, 41)
    pose, velocity, acceleration = paper_law(t, (0.01, -0.01, 0.1))
    traj = write_trajectory(tmp_path / "traj.csv", t, pose, velocity, acceleration)
    out_dir = tmp_path / "out"
    status, out, _ = cli(
        capsys, "simulate", "--trajectory", traj, "--output", out_dir, "--plots", "--animate",
        "--frames", "12",
    )  # fmt: skip
    assert status == 0
    assert sorted(p.name for p in out_dir.iterdir()) == [
        MANIFEST_NAME, "f10.png", "f21y.png", "f21z.png", "lambda10.png", "mechanism.gif",
        "p10.png", "results.csv",
    ]  # fmt: skip
    from PIL import Image

    with Image.open(out_dir / "mechanism.gif") as gif:
        assert gif.n_frames == 12
    assert f"  {out_dir / 'mechanism.gif'}" in out.splitlines()


def test_animation_of_a_named_motion_has_at_most_100_frames(tmp_path, capsys):
    from PIL import Image

    status, _, err = cli(capsys, "simulate", "--motion", "rotation", "-o", tmp_path, "--animate")
    assert status == 0 and "\r" not in err
    with Image.open(tmp_path / "mechanism.gif") as gif:
        assert gif.n_frames == 100


def test_a_failure_while_plotting_leaves_no_output(tmp_path, capsys, monkeypatch):
    import prp3.plotting.figures as figures

    (tmp_path / "results.csv").write_text("older run\n")

    def broken(figure, path):
        Path(path).write_bytes(b"\x89PNG half")
        raise RuntimeError("disk full")

    monkeypatch.setattr(figures, "save_figure", broken)
    with pytest.raises(RuntimeError, match="disk full"):
        main(["simulate", "--motion", "vertical", "--output", str(tmp_path), "--plots"])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["results.csv"]  # no staging left
    assert (tmp_path / "results.csv").read_text() == "older run\n"


def test_reruns_replace_the_files_of_the_same_name(tmp_path, capsys):
    cli(capsys, "simulate", "--motion", "vertical", "--samples", "5", "-o", tmp_path)
    cli(capsys, "simulate", "--motion", "vertical", "--samples", "9", "-o", tmp_path)
    _, table = read_results(tmp_path / "results.csv")
    assert len(table["t"]) == 9
    assert sorted(p.name for p in tmp_path.iterdir()) == [MANIFEST_NAME, "results.csv"]


# (the progress bar: tests/test_progress.py)


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    ("text", "fragments"),
    [
        ("t,x,y\n0,0,0\n1,0,0\n", ["traj.csv:1", "missing column(s) phi"]),
        ("t,x,y,phi,z\n0,0,0,0,0\n1,0,0,0,0\n", ["traj.csv:1", "unknown column 'z'"]),
        (
            "t,x,y,phi,ddx\n0,0,0,0,0\n1,0,0,0,0\n",
            ["traj.csv:1", "missing dx, dy, dphi, ddy, ddphi"],
        ),
        ("time,x,y,phi\n0,0,0,0\n1,0,0,0\n", ["traj.csv:1", "unknown column 'time'"]),
        ("t,x,y,phi\n0,0,0,0\n0.1,0,1e-3,0\n0.2,0,abc,0\n", ["traj.csv:4", "column 'y'", "'abc'"]),
        ("t,x,y,phi\n0,0,0,0\n0.1,0,0,nan\n", ["traj.csv:3", "column 'phi'", "not a finite"]),
        ("t,x,y,phi\n0,0,0,0\n0.1,0,0,0\n0.1,0,0,0\n", ["traj.csv:4", "time must increase"]),
        ("t,x,y,phi\n0,0,0,0\n", ["traj.csv", "at least 2 samples, got 1"]),
        ("t,x,y,phi\n", ["traj.csv", "no data rows"]),
        ("", ["traj.csv", "empty trajectory file"]),
        (
            "t,x,y,phi\n0,0,0,0\n0.1,0,0,0.5\n0.2,0,0,1.0471975511965976\n0.3,0,0,1.3\n",
            ["traj.csv:4: sample 2, t = 0.2 s: singular pose", "phi=1.0471975511965976"],
        ),
    ],
)
def test_bad_trajectories_are_refused_with_file_and_line(tmp_path, capsys, text, fragments):
    traj = tmp_path / "traj.csv"
    traj.write_text(text)
    out_dir = tmp_path / "out"
    status, _, err = cli(capsys, "simulate", "--trajectory", traj, "--output", out_dir)
    assert_refused(status, err, out_dir, *fragments)


def test_contract_singular_trajectory_with_derivatives(tmp_path, capsys):
    traj = tmp_path / "singular.csv"
    traj.write_text(
        "t,x,y,phi,dx,dy,dphi,ddx,ddy,ddphi\n"
        + "".join(f"{k * 0.1},0,0,{math.pi / 3},0,0,0,0,0,0\n" for k in range(3))
    )
    status, _, err = cli(capsys, "simulate", "--trajectory", traj, "--output", tmp_path / "o")
    assert_refused(status, err, tmp_path / "o", "singular.csv:2: sample 0, t = 0 s: singular pose")


def test_unreachable_pose_names_the_sample_and_leg(tmp_path, capsys):
    # stroke ±0.01 m. In the vertical motion λ10_A = y/sin 60° (P_A rises with the
    # platform edge) and |λ10_C| = (y/2)/sin 60° < λ10_A, so leg A leaves the stroke
    # first, when 0.025·(1 − cos wt) > 0.01·sin 60°, i.e. after
    # t* = arccos(1 − 0.01·sin 60°/0.025)/w; with 301 samples t_k = k/100.
    t_star = math.acos(1 - 0.01 * math.sin(math.pi / 3) / 0.025) / W
    k = math.ceil(t_star * 100)
    robot = tmp_path / "robot.toml"
    robot.write_text("[limits]\nstroke = [-0.01, 0.01]\n")
    out_dir = tmp_path / "out"
    status, _, err = cli(
        capsys, "simulate", "--robot", robot, "--motion", "vertical", "-o", out_dir
    )
    at = f"sample {k}, t = {k / 100:.9g} s, leg A: unreachable pose"
    assert_refused(status, err, out_dir, f"--motion vertical: {at}", "lambda10_A")
    # the same motion from a file: the message names the file and the line (k + 2)
    t = np.linspace(0.0, 3.0, 301)
    traj = write_trajectory(tmp_path / "traj.csv", t, *paper_law(t, (0.0, 0.025, 0.0)))
    status, _, err = cli(capsys, "simulate", "--robot", robot, "--trajectory", traj, "-o", out_dir)
    assert_refused(status, err, out_dir, f"traj.csv:{k + 2}: {at}", "lambda10_A")


def test_sample_index_of_an_error_counts_from_the_start_of_the_whole_motion():
    # simulate_table computes in chunks; a singular pose in the 3rd chunk of 3
    phi = np.zeros(9)
    phi[7] = math.pi / 3
    pose = np.stack([np.zeros(9), np.zeros(9), phi], axis=-1)
    motion = prp3.Motion(t=np.arange(9.0), pose=pose, velocity=0 * pose, acceleration=0 * pose)
    with pytest.raises(prp3.SingularPoseError, match=r"sample 7: singular pose "):
        simulate_table(prp3.Robot(), motion, chunk=3)


@pytest.mark.parametrize(
    ("text", "fragments"),
    [
        ("[platform]\nmass = -3.0\n", ["robot.toml", "platform.mass", "-3.0"]),
        ("[platfrom]\nmass = 3.0\n", ["robot.toml", "unknown key 'platfrom'"]),
        ("l0 = \n", ["robot.toml:1:6", "invalid TOML"]),
        ("gravity = [0.0]\n", ["robot.toml", "gravity", "[0.0]"]),
        ('l0 = "big"\n', ["robot.toml", "l0", "'big'"]),
        ("[limits]\nstroke = [0.1, 0.2]\n", ["robot.toml", "limits.stroke"]),
    ],
)
def test_bad_robot_files_are_refused(tmp_path, capsys, text, fragments):
    robot = tmp_path / "robot.toml"
    robot.write_text(text)
    out_dir = tmp_path / "out"
    status, _, err = cli(
        capsys, "simulate", "--robot", robot, "--motion", "vertical", "-o", out_dir
    )
    assert_refused(status, err, out_dir, *fragments)


def test_missing_input_files(tmp_path, capsys):
    out_dir = tmp_path / "out"
    status, _, err = cli(
        capsys, "simulate", "--robot", tmp_path / "none.toml", "--motion", "vertical", "-o", out_dir
    )
    assert_refused(status, err, out_dir, "none.toml: cannot read robot file")
    status, _, err = cli(capsys, "simulate", "--trajectory", tmp_path / "none.csv", "-o", out_dir)
    assert_refused(status, err, out_dir, "none.csv: cannot read trajectory file")


def test_unwritable_output_directory(tmp_path, capsys):
    blocker = tmp_path / "file.txt"
    blocker.write_text("")
    status, _, err = cli(capsys, "simulate", "--motion", "vertical", "-o", blocker / "out")
    assert_refused(status, err, blocker / "out", "file.txt/out", "not a directory")
    status, _, err = cli(capsys, "simulate", "--motion", "vertical", "-o", blocker)
    assert_refused(status, err, tmp_path / "never", "file.txt", "not a directory")
    assert blocker.read_text() == ""


@NAMESPACES
def test_read_only_output_directory(tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir()
    status, err = run_read_only(locked, "simulate", "--motion", "vertical", "-o", locked / "out")
    assert_refused(status, err, locked / "out", "locked", "not writable")


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (["simulate", "--motion", "vertical"], "--output"),
        (["simulate", "--output", "x"], "one of the arguments --motion --trajectory is required"),
        (["simulate", "--motion", "spiral", "-o", "x"], "invalid choice: 'spiral'"),
        (["simulate", "--motion", "vertical", "--samples", "1", "-o", "x"], "--samples"),
        (["simulate", "--motion", "vertical", "--samples", "ten", "-o", "x"], "'ten'"),
        (["simulate", "--motion", "vertical", "--method", "lagrange", "-o", "x"], "'lagrange'"),
        (["simulate", "--motion", "vertical", "--frames", "0", "-o", "x"], "--frames"),
        (["simulate", "--motion", "vertical", "--trajectory", "t.csv", "-o", "x"], "not allowed"),
        (["robot"], "one of the arguments --template --check is required"),
        (["frobnicate"], "invalid choice: 'frobnicate'"),
    ],
)
def test_usage_errors_exit_2_with_one_line(tmp_path, capsys, monkeypatch, argv, fragment):
    monkeypatch.chdir(tmp_path)
    status, out, err = cli(capsys, *argv)
    assert status == 2 and out == ""
    (line,) = err.strip().splitlines()
    assert line.startswith("prp3") and fragment in line
    assert list(tmp_path.iterdir()) == []


def test_samples_with_a_trajectory_is_refused(tmp_path, capsys):
    t = np.linspace(0.0, 1.0, 5)
    traj = write_trajectory(tmp_path / "t.csv", t, *paper_law(t, (0.0, 0.01, 0.0)))
    status, _, err = cli(
        capsys, "simulate", "--trajectory", traj, "--samples", "9", "-o", tmp_path / "o"
    )
    assert_refused(status, err, tmp_path / "o", "--samples applies to --motion only")


def test_no_command_prints_the_help_and_exits_2(capsys):
    status, _, err = cli(capsys)
    assert status == 2 and "simulate" in err and "usage: prp3" in err


# ---------------------------------------------------------------- robot, version, help
def test_robot_template_is_the_default_robot_with_units(capsys):
    status, out, _ = cli(capsys, "robot", "--template")
    assert status == 0
    assert prp3.Robot.from_mapping(tomllib.loads(out)) == prp3.Robot()
    data = tomllib.loads(out)
    assert data["l0"] == 0.3 and data["gravity"] == [0.0, -9.81]
    assert data["piston"] == {"mass": 1.0, "inertia": 0.0, "com": [0.0, 0.0]}
    assert data["link"] == {"mass": 0.75, "inertia": 6.25e-4, "com": [0.0, 0.0]}
    assert data["platform"]["mass"] == 3.0
    assert "0.0675" in out  # the platform inertia m3·l²/12 = 3·0.27/12, shown commented
    for unit in ("# m,", "# kg,", "kg m^2", "m/s^2", "# N,"):
        assert unit in out


def test_robot_check(tmp_path, capsys):
    robot = tmp_path / "robot.toml"
    robot.write_text("l0 = 0.4\n[link]\nmass = 0.5\n")
    status, out, _ = cli(capsys, "robot", "--check", robot)
    assert status == 0
    assert out.startswith(f"# {robot}: valid")
    checked = prp3.Robot.from_mapping(tomllib.loads(out))
    assert checked.l0 == 0.4 and checked.link.mass == 0.5 and checked.piston.mass == 1.0
    robot.write_text("[link]\nmass = 0\n")
    status, out, err = cli(capsys, "robot", "--check", robot)
    assert status == 2 and out == ""
    assert err.startswith("prp3 robot: error: ") and "link.mass" in err and str(robot) in err


def test_version(capsys):
    status, out, _ = cli(capsys, "--version")
    assert status == 0 and out.strip() == f"prp3 {prp3.__version__}"


@pytest.mark.parametrize("command", [[], ["simulate"], ["robot"]])
def test_help_of_every_command_has_an_example(capsys, command):
    status, out, _ = cli(capsys, *command, "--help")
    assert status == 0
    assert "example" in out and "prp3 " in out
    if command == ["simulate"]:
        for option in ("--robot", "--motion", "--trajectory", "--samples", "--method",
                       "--output", "--plots", "--animate", "--frames"):  # fmt: skip
            assert option in out


# ---------------------------------------------------------------- real processes
def test_installed_prp3_in_a_subprocess(tmp_path):
    exe = shutil.which("prp3")
    if exe is None:
        pytest.skip("the prp3 script is not on PATH")
    ok = subprocess.run(
        [exe, "simulate", "--motion", "vertical", "--samples", "11", "--output", tmp_path / "o"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert ok.returncode == 0, ok.stderr
    assert ok.stderr == ""
    assert (tmp_path / "o" / "results.csv").read_text().splitlines()[0] == ",".join(CONTRACT)
    bad = tmp_path / "bad.toml"
    bad.write_text("[platform]\nmass = -3.0\n")
    refused = subprocess.run(
        [exe, "simulate", "--robot", bad, "--motion", "vertical", "--output", tmp_path / "b"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert refused.returncode == 2
    assert refused.stderr.count("\n") == 1 and "Traceback" not in refused.stderr
    assert "platform.mass" in refused.stderr and not (tmp_path / "b").exists()


def test_python_dash_m_prp3(tmp_path):
    done = subprocess.run(
        [sys.executable, "-m", "prp3", "simulate", "--motion", "rotation", "--samples", "5",
         "--output", tmp_path],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "files written:" in done.stdout
    assert len((tmp_path / "results.csv").read_text().splitlines()) == 6
