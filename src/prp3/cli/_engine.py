"""The engine of a command's run: ``--engine auto|numba|numpy`` (docs/cli.md, *Engines*).

The library's default engine is numba (:func:`prp3.engines.select.default_engine`):
in a program that runs the kernel many times its start-up is paid once.  A
command runs once per process, and there numba's start-up — importing numba
and loading its cached machine code, about 0.5 s on a 2-vCPU machine, whatever
the run — costs more than it saves on a short run.  ``--engine auto`` (the
command line's default) therefore runs the numba engine only from
:data:`NUMBA_FROM` samples on, where its speed repays its start-up, and the
numpy engine below; ``--engine numba`` or ``--engine numpy`` runs that engine.
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

#: Samples of a run from which ``--engine auto`` runs numba, per route: where the
#: numba engine's start-up (~0.5 s) is repaid.  Measured in one process per run
#: (``python benchmarks/bench_cli_engines.py``): the 3-PRP kernel on numpy arrays
#: runs ~1.3·10⁶ samples/s of a whole run's table against ~5·10⁶ for numba (break-even
#: ~7·10⁵); the family's fast route ~1.2·10⁵/s on numpy against ~1.5·10⁶ (~5·10⁴).
NUMBA_FROM: dict[str, int] = {"3-PRP": 1_000_000, "family": 50_000}


def add_engine_option(parser: argparse.ArgumentParser) -> None:
    """Add ``--engine auto|numba|numpy`` to a command's parser."""
    parser.add_argument(
        "--engine",
        choices=ENGINE_CHOICES,
        default="auto",
        help="the engine of the fast route: numba (compiled) or numpy; auto (default): "
        f"numba from {NUMBA_FROM['3-PRP']:,} samples ({NUMBA_FROM['family']:,} for a "
        "family-form robot), where its start-up of about 0.5 s per process is repaid, "
        "numpy below (docs/cli.md)",
    )


def run_engine(choice: str, samples: int, route: str) -> str:
    """The engine a run of ``samples`` samples on ``route`` (``"3-PRP"``, ``"family"``) runs.

    ``choice`` is the value of ``--engine``.  ``"auto"`` gives ``"numba"``
    from :data:`NUMBA_FROM` samples when numba is installed (else the numpy
    engine, with the library's one warning that numba is missing), ``"numpy"``
    below; ``"numba"`` without numba installed is refused (a Prp3Error).

    >>> run_engine("auto", 301, "3-PRP"), run_engine("numpy", 10**7, "family")
    ('numpy', 'numpy')
    """
    if choice != "auto":
        return resolve_engine(choice)
    if samples < NUMBA_FROM[route]:
        return "numpy"
    if importlib.util.find_spec("numba") is None:
        return resolve_engine(None)  # the numpy engine, and the warning that says why
    return "numba"
