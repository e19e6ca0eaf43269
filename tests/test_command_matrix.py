"""Every command for every architecture: the cells of the table of docs/cli.md stay what they are.

``docs/examples/command_matrix.py`` runs each command form of ``prp3`` on the robot file of each
architecture and actuation (docs/cli.md, "Every command for every architecture").  The cells
expected here are written out, not taken from the script: a cell that was ``ok`` and stops being
``ok`` (or a refusal that changes its reason) fails the test of its row; ``tests/test_docs.py``
checks that docs/cli.md quotes what the script prints.
"""

from __future__ import annotations

import importlib.util
import runpy
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "docs" / "examples" / "command_matrix.py"
MATRIX: dict[str, Any] = runpy.run_path(str(SCRIPT))

#: The table, as docs/cli.md shows it (every extra installed: dask, pyarrow, plotly, bokeh,
#: mujoco).
EXPECTED = """\
| robot | robot --check | simulate fast | simulate paper | simulate newton-euler | --plots | --animate | --html | workspace --statics | forward | export c | export mjcf | export urdf | excite | identify | control prp3 | control mujoco | sweep | optimize | explore --export | explore --results |
|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|
| 3-PRP (model form) | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-PRP a=1 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-PRP a=3 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-RPR a=1 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-RPR a=2 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-RPR a=3 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-RRR a=1 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-RRR a=2 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-RRR a=3 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-PRR a=1 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-PRR a=2 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-PRR a=3 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-PPR a=1 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-PPR a=2 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-RPP a=2 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-RPP a=3 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-RRP a=1 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-RRP a=3 | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | refused: spatial robots only | ok | ok | ok | ok | ok | ok | ok | ok |
| 6-UPS | ok | n.a.¹ | n.a.¹ | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-RPS | ok | n.a.¹ | n.a.¹ | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok |
| 3-RUU | ok | n.a.¹ | n.a.¹ | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok | ok |
"""

#: The lines of the table by robot (the first cell).
EXPECTED_ROWS = {line.split(" | ")[0][2:]: line for line in EXPECTED.splitlines()[2:]}


def test_the_table_has_every_architecture_and_command() -> None:
    header = EXPECTED.splitlines()[0]
    assert header == "| robot | " + " | ".join(c.title for c in MATRIX["COLUMNS"]) + " |"
    assert list(EXPECTED_ROWS) == [row.name for row in MATRIX["rows"]()]
    # the model form, 17 family robots (the allowed actuations of docs/family.md §3), 3 spatial
    assert len(EXPECTED_ROWS) == 21
    assert {row.architecture for row in MATRIX["rows"]()} == {
        "3-PRP", "3-RPR", "3-RRR", "3-PRR", "3-PPR", "3-RPP", "3-RRP", "6-UPS", "3-RPS", "3-RUU",
    }  # fmt: skip


def test_docs_cli_md_shows_the_expected_table() -> None:
    text = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    marker = "<!-- output of: python docs/examples/command_matrix.py -->\n"
    assert marker + EXPECTED + "\n" in text
    assert "<!-- output of: python docs/examples/command_matrix.py --notes -->\n" in text


def test_a_cell_says_what_went_wrong(tmp_path: Path) -> None:
    # the cells can fail: a refused command gives its reason, an unexpected success is named
    row, column = MATRIX["rows"]()[0], MATRIX["COLUMNS"][0]
    assert column.title == "robot --check"
    (tmp_path / "robot.toml").write_text("[platform]\nmass = -3.0\n", encoding="utf-8")
    words = MATRIX["cell"](row, column, tmp_path, {})
    assert words == "robot: platform.mass must be a positive"
    n_a = MATRIX["Column"]("robot --check", column.argv, lambda row: 1)
    (tmp_path / "robot.toml").write_text("", encoding="utf-8")
    assert MATRIX["cell"](row, n_a, tmp_path, {}) == "exit 0 (n.a.1)"
    needs = MATRIX["Column"]("forward", column.argv, needs="run")
    assert MATRIX["cell"](row, needs, tmp_path, {"run": (2, "")}) == "needs run"
    line = "prp3 sweep: error: design studies need dask: pip install 'prp3[design]'"
    assert MATRIX["reason"](line) == "needs prp3[design]"


@pytest.fixture(scope="module")
def scheduler() -> Iterator[None]:
    """The script's in-process Dask cluster, shared by the rows."""
    for name in ("distributed", "pyarrow", "plotly", "bokeh", "mujoco"):
        pytest.importorskip(name)
    with MATRIX["scheduler"]():
        yield


@pytest.mark.slow  # 5-20 s a row: every command on one robot
@pytest.mark.parametrize("name", list(EXPECTED_ROWS))
def test_every_command_does_on_the_robot_what_the_table_says(
    name: str, scheduler: None, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    (row,) = [row for row in MATRIX["rows"]() if row.name == name]
    assert importlib.util.find_spec("mujoco") is not None
    lines = MATRIX["table"]([row])
    assert lines[2] == EXPECTED_ROWS[name]
