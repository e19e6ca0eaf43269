"""The options of the command line say what they do (issue 21, API and command line).

* no silent prefix abbreviations on any parser: ``--samp 5`` is not ``--samples 5``;
* a misspelled option is named (with the closest known one), even when
  argparse has something else to complain about first;
* an option that only applies with another is refused without it;
* ``--frames N`` says why the animation has fewer frames;
* warnings carry no internal ``file.py:line``; ``control`` says why it
  stopped once; ``history.csv`` counts generations in integers; "1 parameter".
"""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

import pytest

from clitools import cli, one_line
from prp3.cli import build_parser, one_line_warnings


def _parsers(parser: argparse.ArgumentParser) -> list[argparse.ArgumentParser]:
    found = [parser]
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for child in action.choices.values():
                found += _parsers(child)
    return found


def test_no_parser_accepts_abbreviations() -> None:
    parsers = _parsers(build_parser())
    assert len(parsers) >= 12  # prp3, its commands and export's
    assert [p.prog for p in parsers if p.allow_abbrev] == []


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (["simulate", "--motion", "vertical", "--samp", "5", "-o", "x"],
         "unrecognized arguments: --samp (did you mean --samples?) 5"),
        (["simulate", "--mot", "vertical", "-o", "x"],
         "unknown option --mot (did you mean --motion?)"),
        (["workspace", "--phi", "-0.5", "--poin", "5", "-o", "x"], "--poin (did you mean --points?)"),
        (["export", "mjcf", "--robo", "r.toml"], "--robo (did you mean --robot?)"),
        (["--verson"], "--verson (did you mean --version?)"),
    ],
)  # fmt: skip
def test_a_misspelled_option_is_named(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, argv: list[str], fragment: str
) -> None:
    argv = [str(tmp_path / "x") if word == "x" else word for word in argv]  # not into the cwd
    status, out, err = cli(capsys, *argv)
    assert status == 2 and out == ""
    assert fragment in one_line(err)
    assert not (tmp_path / "x").exists()


def test_a_command_misspelled_does_not_blame_its_options(
    capsys: pytest.CaptureFixture[str],
) -> None:
    status, _, err = cli(capsys, "simulat", "--motion", "vertical")
    line = one_line(err)
    assert status == 2 and "invalid choice: 'simulat'" in line and "unknown option" not in line


@pytest.mark.parametrize("option", [("--pareto", "l0,peak_f10"), ("--sensitivity", "energy")])
def test_figure_options_of_sweep_need_plots(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, option: tuple[str, str]
) -> None:
    spec = tmp_path / "spec.toml"
    spec.write_text("designs = 2\n[parameters]\nl0 = [0.25, 0.3]\n[task]\nsamples = 5\n")
    status, _, err = cli(capsys, "sweep", "--spec", spec, *option, "--output", tmp_path / "o")
    line = one_line(err)
    assert status == 2 and f"{option[0]} {option[1]} applies to the figures only" in line
    assert "--plots" in line and not (tmp_path / "o").exists()


def test_frames_says_why_it_makes_fewer(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    status, _out, err = cli(
        capsys, "simulate", "--motion", "vertical", "--samples", "31", "--animate",
        "--frames", "301", "--output", tmp_path / "o",
    )  # fmt: skip
    assert status == 0
    assert one_line(err) == (
        "prp3 simulate: warning: --frames 301: the animation has 31 frames: the motion has 31 "
        "samples"
    )
    from PIL import Image

    with Image.open(tmp_path / "o" / "mechanism.gif") as gif:
        assert gif.n_frames == 31


def test_warnings_name_no_internal_file(capsys: pytest.CaptureFixture[str]) -> None:
    show = one_line_warnings("prp3 workspace")
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        warnings.showwarning = show
        warnings.warn("overflow encountered", RuntimeWarning, stacklevel=1)
    err = capsys.readouterr().err
    assert err == "prp3 workspace: warning: overflow encountered\n"


def test_control_says_why_it_stopped_once(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    status, out, err = cli(
        capsys, "control", "--motion", "rotation", "--controller", "feedforward", "--plant",
        "prp3", "--rate", "100", "--output", tmp_path / "o",
    )  # fmt: skip
    assert status == 1  # open loop: it drifts into the singularity
    warning = one_line(err)
    assert warning.startswith("prp3 control: warning: stopped at t = ")
    reason = warning.split("warning: ", 1)[1]
    assert (out + err).count(reason) == 1 and "stopped" not in out


def test_history_counts_generations_in_integers_and_one_parameter(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    spec = tmp_path / "spec.toml"
    spec.write_text(
        '[parameters]\nl0 = [0.25, 0.3]\n[task]\nmotions = ["vertical"]\nsamples = 5\n'
        '[optimize]\nobjective = "peak_f10"\nmaxiter = 2\npopsize = 3\n'
    )
    status, out, err = cli(capsys, "optimize", "--spec", spec, "--output", tmp_path / "o")
    assert status == 0, err
    assert "over 1 parameter," in out
    rows = (tmp_path / "o" / "history.csv").read_text().splitlines()
    assert rows[0].startswith("generation,l0,")
    generations = [row.split(",")[0] for row in rows[1:]]
    assert generations[0] == "0" and all(g.isdigit() for g in generations)
    assert int(generations[-1]) >= 1
