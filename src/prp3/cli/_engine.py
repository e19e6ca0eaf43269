"""The engine of a command's run: ``--engine auto|numba|numpy`` (docs/cli.md, *Engines*).

The library's default engine is numba (:func:`prp3.engines.select.default_engine`):
in a program that runs the kernel many times its start-up is paid once.  A
command runs once per process, and there numba's start-up — importing numba
and loading its cached machine code, about 0.5 s on a 2-vCPU machine, whatever
the run — costs more than it saves on a short run.  ``--engine auto`` (the
command line's default) therefore runs the numba engine only where a whole
run was measured to be faster on it, start-up included (:data:`NUMBA_FROM`),
and the numpy engine elsewhere; ``--engine numba`` or ``--engine numpy`` runs that engine.
The summary names the engine that ran.  Both engines give the same numbers to
round-off (``tests/test_kernel.py``, ``tests/test_family_compiled.py``).
"""

from __future__ import annotations

import argparse
import importlib.util

from prp3.engines.select import resolve_engine

__all__ = ["ENGINE_CHOICES", "NUMBA_FROM", "add_engine_option", "run_engine"]

#: The values of ``--engine``.
ENGINE_CHOICES: tuple[str, ...] = ("auto", "numba", "numpy")

#: Samples of a run from which ``--engine auto`` runs numba, per route (``None``: never):
#: where a whole ``prp3 simulate`` in a new process is faster on numba, start-up
#: included (``python benchmarks/bench_cli_engines.py``, benchmarks/README.md).  The
#: family's fast route on numpy arrays is ~10× slower than on numba, and numba is
#: the faster from about 10⁵ samples.  The 3-PRP kernel on numpy arrays is fast enough
#: that writing ``results.csv`` dominates a run: up to 3·10⁶ samples (the largest
#: measured) the numpy engine was the faster by 0.5–1 s, so ``auto`` never starts numba.
NUMBA_FROM: dict[str, int | None] = {"3-PRP": None, "family": 100_000}


def add_engine_option(parser: argparse.ArgumentParser) -> None:
    """Add ``--engine auto|numba|numpy`` to a command's parser."""
    parser.add_argument(
        "--engine",
        choices=ENGINE_CHOICES,
        default="auto",
        help="the engine of the fast route: numba (compiled) or numpy; auto (default): "
        f"numba for a family-form robot from {NUMBA_FROM['family']:,} samples, where its "
        "start-up of about 0.5 s per process is repaid, else numpy (for the 3-PRP the "
        "numpy engine is the faster in a command; docs/cli.md)",
    )


def run_engine(choice: str, samples: int, route: str) -> str:
    """The engine a run of ``samples`` samples on ``route`` (``"3-PRP"``, ``"family"``) runs.

    ``choice`` is the value of ``--engine``.  ``"auto"`` gives ``"numba"``
    from :data:`NUMBA_FROM` samples of the route when numba is installed (else
    the numpy engine, with the library's one warning that numba is missing),
    ``"numpy"`` below or where the route has no threshold; ``"numba"`` without
    numba installed is refused (a Prp3Error).

    >>> run_engine("auto", 301, "3-PRP"), run_engine("numpy", 10**7, "family")
    ('numpy', 'numpy')
    """
    if choice != "auto":
        return resolve_engine(choice)
    threshold = NUMBA_FROM[route]
    if threshold is None or samples < threshold:
        return "numpy"
    if importlib.util.find_spec("numba") is None:
        return resolve_engine(None)  # the numpy engine, and the warning that says why
    return "numba"
