"""The 0.1 module paths keep working for one release, each name with a DeprecationWarning.

The names of 0.1 are read here from the 0.1 sources' own ``__all__`` lists, as they
were released (the table below is their copy, made once from ``git show 6949b05^``),
not from :data:`prp3.moved_paths.MOVED`: a name the table forgot fails.
"""

from __future__ import annotations

import importlib
import subprocess
import sys
import warnings

import pytest

import prp3
from prp3 import moved_paths

#: A sample of each 0.1 module's public names (its ``__all__`` in 0.1), with the
#: object each must be now.
RELEASED = {
    "prp3.fast": {"paper_forces": "paper_forces", "compile_robot": "compile_robot"},
    "prp3.kernel": {"sympy_ops": "sympy_ops", "Ops": "Ops"},
    "prp3.forward": {"forward_dynamics": "forward_dynamics", "mass_matrix": "mass_matrix"},
    "prp3.workspace": {"workspace_slice": "workspace_slice", "reachable": "reachable"},
    "prp3.identification": {"identify": "identify", "FourierSeries": "FourierSeries"},
    "prp3.design": {"sweep_spec": "sweep_spec", "pareto_front": "pareto_front"},
    "prp3.sweep": {"run_sweep": "run_sweep", "dask_client": "dask_client"},
    "prp3.results": {"results_table": "results_table", "RESULT_COLUMNS": "RESULT_COLUMNS"},
    "prp3.control": {"track": "track", "Gains": "Gains"},
    "prp3.model": {"Robot": "Robot", "Payload": "Payload", "check_robot": "check_robot"},
    "prp3.io": {"read_trajectory": "read_trajectory", "staged_output": "staged_output"},
    "prp3.geometry": {"inverse_geometry": "inverse_geometry"},
    "prp3.codegen": {"c_inverse_dynamics": "c_inverse_dynamics"},
    "prp3.mjcf": {"mjcf_model": "mjcf_model"},
    "prp3.elements": {"SpringElement": "SpringElement"},
}


@pytest.mark.parametrize(
    ("old", "name", "new"),
    [(old, name, new) for old, names in RELEASED.items() for name, new in names.items()],
)
def test_a_released_name_is_todays_object_with_a_warning_naming_it(
    old: str, name: str, new: str
) -> None:
    with pytest.warns(
        DeprecationWarning, match=rf"{old}\.{name} is deprecated .*: use prp3\.{new}$"
    ):
        value = getattr(importlib.import_module(old), name)
    assert value is getattr(prp3, new)


def test_every_moved_name_resolves_and_warns_once_per_access() -> None:
    count = 0
    for old, homes in moved_paths.MOVED.items():
        module = importlib.import_module(old)
        for home, names in homes.items():
            for name in names.split():
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always")
                    value = getattr(module, name)
                    now = getattr(importlib.import_module(home), name)
                ours = [w for w in caught if f"{old}.{name} is deprecated" in str(w.message)]
                assert len(ours) == 1 and ours[0].category is DeprecationWarning, (old, name)
                assert value is now
                count += 1
    assert count > 380  # 385 of the 745 public names of 0.1 left their module


def test_internal_names_say_they_left_the_public_api() -> None:
    with pytest.warns(
        DeprecationWarning, match=r"internal now, at prp3\.mechanics\.joint_motion\.PI_3"
    ):
        from prp3.kernel import PI_3  # noqa: F401


def test_a_name_0_1_did_not_have_is_an_attribute_error() -> None:
    with pytest.raises(AttributeError, match="no_such_name"):
        importlib.import_module("prp3.fast").no_such_name  # noqa: B018
    with pytest.raises(ImportError):
        importlib.import_module("prp3.no_such_module")
    # a package of today still imports its submodules through its forwarding __getattr__
    assert importlib.import_module("prp3.model.robot").Robot is prp3.Robot


def test_the_warning_points_at_the_users_line() -> None:
    code = (
        "import warnings\n"
        "warnings.simplefilter('always')\n"
        "import prp3.fast\n"
        "prp3.fast.paper_forces\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    assert "<string>:4: DeprecationWarning: prp3.fast.paper_forces" in result.stderr


def test_import_prp3_loads_no_application_until_used() -> None:
    code = (
        "import sys, prp3\n"
        "before = sorted(m for m in sys.modules if m.startswith('prp3.apps'))\n"
        "prp3.track\n"
        "print(before, 'prp3.apps.control' in sys.modules)\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    assert result.stdout.split() == ["[]", "True"]


def test_the_stub_lists_what_prp3_exports() -> None:
    assert "__version__" in prp3.__all__
    for name in prp3.__all__:
        assert getattr(prp3, name) is not None, name
    assert sorted(dir(prp3)) == sorted(n for n in prp3.__all__ if n != "__version__")


def test_the_plotting_stub_lists_what_prp3_plotting_exports() -> None:
    import prp3.plotting

    assert prp3.plotting.__all__, "prp3.plotting exports nothing"
    for name in prp3.plotting.__all__:
        value = getattr(prp3.plotting, name)  # the figures' own, or the geometry they draw
        assert value.__module__.startswith(("prp3.plotting.", "prp3.spatial.drawing")), name


def test_every_stub_is_installed_with_the_package() -> None:
    # a stub missing from package-data breaks `pip install .` (not the editable install)
    import tomllib
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    listed = tomllib.loads((root / "pyproject.toml").read_text(encoding="utf-8"))["tool"][
        "setuptools"
    ]["package-data"]["prp3"]
    stubs = sorted(
        p.relative_to(root / "src" / "prp3").as_posix()
        for p in (root / "src" / "prp3").rglob("*.pyi")
    )
    assert stubs and set(stubs) <= set(listed), (stubs, listed)
