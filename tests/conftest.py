"""Test configuration: hypothesis profiles and the import path of the shared helpers.

Profiles (choose with the environment variable ``PRP3_HYPOTHESIS_PROFILE``):

* ``default`` — 40 examples per property, no deadline, derandomized (the same
  examples on every run and every machine, so a CI failure reproduces locally)
  and no example database (nothing written to the working tree).
* ``thorough`` — 1000 random examples per property, for an occasional deep run:
  ``PRP3_HYPOTHESIS_PROFILE=thorough python -m pytest tests``.

Two things keep the whole suite short on a few cores (pytest-xdist, ``-n auto``):

* the tests marked ``slow`` run first, then the doctests of the documents
  (:func:`pytest_collection_modifyitems`): a long test started last would run
  alone on one core at the end;
* on a fresh checkout the numba engines are compiled once, shared out among
  the workers (:func:`_compiled_engines`), instead of each worker compiling
  every loop the first time one of its tests calls it (seconds per loop; the
  machine code is then read from numba's disk cache).
"""

from __future__ import annotations

import contextlib
import os
import sys
from collections.abc import Callable, Iterator
from importlib import util as importlib_util
from pathlib import Path

import pytest
from hypothesis import settings

# ``tests/strategies.py`` is a helper module imported by the test files
# (``from strategies import ...``); make it importable whatever the import mode.
_TESTS_DIR = str(Path(__file__).resolve().parent)
if _TESTS_DIR not in sys.path:
    sys.path.insert(0, _TESTS_DIR)

settings.register_profile(
    "default", max_examples=40, deadline=None, derandomize=True, database=None
)
settings.register_profile(
    "thorough", max_examples=1000, deadline=None, derandomize=False, database=None
)
settings.load_profile(os.environ.get("PRP3_HYPOTHESIS_PROFILE", "default"))


def pytest_configure(config: pytest.Config) -> None:
    """Keep a failing hypothesis test a plain failure under ``filterwarnings = error``.

    When hypothesis reports a falsifying example it touches
    ``mypy_extensions.TypedDict``, whose DeprecationWarning, turned into an error,
    aborts the whole session with an INTERNALERROR instead of showing the example.
    """
    config.addinivalue_line(
        "filterwarnings", "ignore:mypy_extensions.TypedDict is deprecated:DeprecationWarning"
    )


@pytest.fixture
def earlier_run(tmp_path: Path) -> Path:
    """An output directory holding the files of an earlier run (and a file of the user's)."""
    folder = tmp_path / "run"
    folder.mkdir()
    (folder / "results.csv").write_text("t,x\n0.0,1.0\n")
    (folder / "notes.txt").write_text("the user's own file\n")
    return folder


@pytest.fixture(scope="module")
def browser() -> Iterator[object]:
    """A headless Chromium for the browser tests (``tests/browsertools.py``), closed after."""
    from browsertools import chromium_browser

    yield from chromium_browser()


@pytest.fixture(scope="module")
def scheduler() -> Iterator[str]:
    """Address of an in-process Dask cluster (1 worker thread) shared by the module (the
    sweep tests)."""
    from dask.distributed import LocalCluster

    from prp3.apps.cluster import QUIET_SCHEDULER

    with LocalCluster(
        n_workers=1,
        threads_per_worker=1,
        processes=False,
        dashboard_address=None,
        scheduler_kwargs=QUIET_SCHEDULER,
    ) as cluster:
        yield cluster.scheduler_address


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Run the ``slow`` tests first, then the doctests of the documents, then the rest.

    The sort is stable (each group keeps pytest's order) and the same in every
    xdist worker, which all collect the same items.
    """

    def group(item: pytest.Item) -> int:
        if item.get_closest_marker("slow") is not None:
            return 0
        return 1 if item.path.suffix == ".md" else 2

    items.sort(key=group)


def _engine_warmups() -> list[Callable[[], object]]:
    """One call per compiled loop of the numba engines (each compiles one machine code)."""
    import numpy as np

    from prp3 import Robot, compile_robot, paper_forces, sample_forces
    from prp3.engines.entries import actuator_forces, solve_batch
    from prp3.engines.numba import PARALLEL_MIN_SAMPLES
    from prp3.engines.sample_entries import sample_actuator_forces
    from prp3.family import FamilyRobot, family_inverse_dynamics
    from prp3.model.motion import paper_motion

    robot = Robot.from_mapping({"limits": {"stroke": [-0.2, 0.2]}})
    compiled = compile_robot(robot)
    rest = np.zeros((2, 3))
    states = (rest, rest, rest)
    big = (np.zeros((PARALLEL_MIN_SAMPLES, 3)),) * 3  # the loops on every thread
    still = ((0.0, 0.0, 0.0),) * 3
    load = (0.0, -1.0, 0.0)
    family = FamilyRobot.from_mapping({"architecture": "3-RRR"})
    return [  # the family's kernel first (about 26 s), then the 3-PRP's loops (18 s together)
        lambda: family_inverse_dynamics(family, paper_motion("vertical", 3), engine="numba"),
        lambda: solve_batch(compiled, *states, load=rest, engine="numba"),
        lambda: solve_batch(compiled, *states, engine="numba"),
        lambda: paper_forces(compiled, *states, reactions=True, engine="numba"),
        lambda: paper_forces(compiled, *states, engine="numba"),
        lambda: actuator_forces(compiled, *states, engine="numba"),
        lambda: sample_forces(compiled, *still, engine="numba"),
        lambda: sample_forces(compiled, *still, load=load, engine="numba"),
        lambda: sample_actuator_forces(compiled, *still, engine="numba"),
        lambda: sample_actuator_forces(compiled, *still, load=load, engine="numba"),
        lambda: solve_batch(compiled, *big, load=big[0], engine="numba"),
        lambda: solve_batch(compiled, *big, engine="numba"),
        lambda: paper_forces(compiled, *big, reactions=True, engine="numba"),
        lambda: paper_forces(compiled, *big, engine="numba"),
        lambda: actuator_forces(compiled, *big, engine="numba"),
    ]


@pytest.fixture(scope="session", autouse=True)
def _compiled_engines(request: pytest.FixtureRequest) -> Iterator[None]:
    """Under xdist, the workers share the compiling of the engines' loops out first.

    The first worker compiles the family's kernel (the longest, as long as the
    3-PRP's loops together); the others share the 3-PRP's loops, worker ``k``
    of the other ``n - 1`` every ``(n - 1)``-th.  Each worker then reads the
    others' machine code from numba's disk cache
    instead of compiling it again (with a warm cache this only loads it).
    Without xdist, or without numba, nothing is done: the tests compile what
    they call.  A warm-up that fails is left to the tests that call it.
    """
    workerinput = getattr(request.config, "workerinput", None)
    count = int(workerinput["workercount"]) if workerinput else 1
    if count > 1 and importlib_util.find_spec("numba") is not None:
        index = int(str(workerinput["workerid"]).removeprefix("gw"))  # type: ignore[index]
        warmups = _engine_warmups()  # a moved import fails here, loudly
        share = warmups[:1] if index == 0 else warmups[1:][index - 1 :: count - 1]
        for warmup in share:
            with contextlib.suppress(Exception):
                warmup()
    yield
