"""docs/family.md says what the code does: its drawing is current, its file is the default."""

from __future__ import annotations

import importlib.util
import re
import tomllib
from pathlib import Path

import numpy as np

from prp3.family import FamilyRobot

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "family.md"


def test_the_drawing_is_the_one_the_script_draws(tmp_path: Path) -> None:
    import matplotlib.image

    spec = importlib.util.spec_from_file_location(
        "family_drawings", ROOT / "docs" / "examples" / "family_drawings.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    drawn = module.draw(tmp_path / "designs.png")
    committed = matplotlib.image.imread(ROOT / "docs" / "figures" / "family_designs.png")
    fresh = matplotlib.image.imread(drawn)
    assert committed.shape == fresh.shape
    assert float(np.abs(committed - fresh).mean()) < 1e-3
    assert "figures/family_designs.png" in DOC.read_text(encoding="utf-8")


def test_the_documented_file_is_the_default() -> None:
    text = DOC.read_text(encoding="utf-8")
    block = re.search(r"```toml\n(.*?)```", text.split("## §9", 1)[1], re.S)
    assert block is not None
    assert FamilyRobot.from_mapping(tomllib.loads(block[1])) == FamilyRobot.default("3-RPR")


def test_model_md_links_here() -> None:
    assert "(family.md)" in (ROOT / "docs" / "model.md").read_text(encoding="utf-8")
