"""Runs of the command line, built outside it: the results table of a run and its summary.

:func:`simulate_table` computes the columns of ``results.csv`` for a motion in
chunks (bounded memory), :func:`summarize` the peaks and energies that
``prp3 simulate`` reports, and :func:`estimate_bytes` / :func:`check_memory`
what a run needs before anything is allocated.  The command line only reads
the options, calls these and prints.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from prp3.analysis.inverse_dynamics import METHODS, Method, inverse_dynamics
from prp3.engines.compiled_robot import CompiledRobot, Engine, compile_robot
from prp3.engines.entries import solve_batch
from prp3.engines.select import resolve_engine
from prp3.errors import ParameterError, Prp3Error
from prp3.io.results import LOAD_RESULT_COLUMNS, OUTPUT_QUANTITIES, result_columns, results_table
from prp3.model.motion import Motion, name_overflow_input
from prp3.model.robot import Robot
from prp3.path_validation import check_path
from prp3.validation import LEGS, check_choice, check_instance, check_integer, check_robot

__all__ = [
    "CHUNK_SAMPLES",
    "RunSummary",
    "available_memory",
    "check_memory",
    "simulate_table",
    "summarize",
    "summary_text",
]

FloatArray = NDArray[np.float64]

#: Samples computed at a time (bounds the memory of big runs; drives the progress bar).
CHUNK_SAMPLES: int = 50_000


def simulate_table(
    robot: Robot,
    motion: Motion,
    method: Method = "fast",
    *,
    progress: Callable[[int, int], None] | None = None,
    chunk: int = CHUNK_SAMPLES,
    near_lock: list[int] | None = None,
    engine: Engine = None,
) -> dict[str, FloatArray]:
    """The columns of ``results.csv`` for a batch motion, computed ``chunk`` samples at a time.

    The same numbers as ``results_table(*inverse_dynamics(robot, motion,
    method))``: every sample is computed on its own, so splitting the batch
    changes nothing but the memory used.  An error's ``sample`` field is the
    sample's index in the whole motion.

    ``near_lock``: a list to which the indices of the samples near a lock of
    the joint friction are appended (robots with ``μ`` terms; the kernel's
    definition, :data:`prp3.mechanics.implicit_friction.NEAR_LOCK_MU`, whatever the ``method``).
    ``engine``: the kernel's engine (:mod:`prp3.engines.select`; ``None``: the default).

    >>> from prp3.model.motion import paper_motion
    >>> table = simulate_table(Robot(), paper_motion("vertical", 7), chunk=3)
    >>> len(table), list(table)[:5], table["f10_A"].shape
    (46, ['t', 'x', 'y', 'phi', 'lambda10_A'], (7,))
    """
    check_robot(robot)
    samples = check_instance("motion", motion, Motion, "a prp3.Motion").samples
    method = check_choice("method", method, METHODS)  # type: ignore[assignment]
    chunk = check_integer("chunk", chunk, 1, 2**31)
    engine = resolve_engine(engine)  # type: ignore[assignment]
    check_path(motion.t, motion.pose)  # the whole motion: a crossing between two chunks too
    columns = result_columns(robot.friction is not None, load=motion.load is not None)
    table = {name: np.empty(samples) for name in columns}
    implicit = robot.friction is not None and robot.friction.has_mu
    compiled = compile_robot(robot) if method == "fast" or implicit else None
    for start in range(0, samples, chunk):
        stop = min(start + chunk, samples)
        piece = motion[start:stop]
        try:
            flags = None
            if method == "fast":  # the kernel's outputs are the columns: no vectors needed
                assert compiled is not None
                part, flags = _kernel_table(compiled, piece, engine)
            else:
                part = results_table(*inverse_dynamics(robot, piece, method, engine=engine))
                if near_lock is not None and compiled is not None:  # the kernel's test, too
                    flags = solve_batch(
                        compiled, piece.pose, piece.velocity, piece.acceleration,
                        load=piece.load, engine=engine,
                    ).get("near_lock")  # fmt: skip
        except Prp3Error as error:
            error = name_overflow_input(error, piece)  # results that overflow: name the input
            if error.sample is None:
                raise error from None
            moved = error.located(sample=error.sample + start)
            if error.subject == "motion" and error.time is None:
                moved = moved.located(time=float(piece.t[error.sample]))
            raise moved from None
        if near_lock is not None and flags is not None:
            near_lock.extend((np.flatnonzero(flags) + start).tolist())
        for name, column in part.items():
            table[name][start:stop] = column
        if progress is not None:
            progress(stop, samples)
    return table


def _kernel_table(
    compiled: CompiledRobot, motion: Motion, engine: Engine
) -> tuple[dict[str, FloatArray], FloatArray | None]:
    """The columns of ``results.csv`` straight from the kernel (``method="fast"``), and the
    near-lock flags of its samples (``None`` without ``μ`` terms).

    The same numbers, bit for bit, as ``results_table(*inverse_dynamics(...))``
    (:func:`prp3.engines.entries.solve_batch` returns every per-leg column), without the
    joint and body vectors of :func:`~prp3.mechanics.kinematics.inverse_kinematics` that
    ``results.csv`` does not hold; the same refusals (poses, stroke, overflow).
    """
    values = solve_batch(
        compiled, motion.pose, motion.velocity, motion.acceleration, load=motion.load, engine=engine
    )
    single = {"t": motion.t, "x": motion.pose[:, 0], "y": motion.pose[:, 1]}
    single["phi"] = motion.pose[:, 2]
    if motion.load is not None:  # the time-varying load, last
        single.update(zip(LOAD_RESULT_COLUMNS, motion.load.T, strict=True))
    columns = result_columns(compiled.robot.friction is not None, load=motion.load is not None)
    table = {
        name: single[name] if name in single else values[name[:-2]][:, LEGS.index(name[-1])]
        for name in columns
    }
    return table, values.get("near_lock")


@dataclass(frozen=True)
class RunSummary:
    """Peaks and energies of a run, per leg A, B, C (arrays of shape (3,)).

    Attributes
    ----------
    peak_f10, peak_p10, peak_f21 : ndarray (3,)
        Largest ``|f10|`` (N), ``|p10|`` (W) and ``|f21| = √(f21y² + f21z²)`` (N).
    peak_f10_time : ndarray (3,)
        When ``|f10|`` peaks (s).
    energy : ndarray (3,)
        Energy each actuator delivers, ``∫ p10 dt`` by the trapezoid rule (J).
    dissipated : ndarray (3,) or None
        With friction columns: the energy friction dissipates in the actuator
        guides, the revolute joints and the sleeves (the three legs together),
        ``∫ −Σ fric·rate dt`` by the trapezoid rule (J); else ``None``.
    """

    peak_f10: FloatArray
    peak_f10_time: FloatArray
    peak_p10: FloatArray
    peak_f21: FloatArray
    energy: FloatArray
    dissipated: FloatArray | None = None

    @property
    def total_energy(self) -> float:
        """Energy the three actuators deliver together (J)."""
        return float(self.energy.sum())


def summarize(table: Mapping[str, FloatArray], dphi: FloatArray | None = None) -> RunSummary:
    """Peaks and energies of the columns of ``results.csv`` (``N >= 1`` samples).

    ``dphi`` (``φ̇`` of the samples) is needed for the energy dissipated in the
    revolute joints when the table has the friction columns.

    >>> t = np.array([0.0, 1.0, 2.0])
    >>> table = {"t": t} | {f"{q}_{leg}": np.array([0.0, 2.0, -1.0])
    ...                     for q in ("f10", "p10", "f21y", "f21z") for leg in "ABC"}
    >>> s = summarize(table)
    >>> s.peak_f10.tolist(), s.peak_f21.round(6).tolist()[0], s.energy.tolist()
    ([2.0, 2.0, 2.0], 2.828427, [1.5, 1.5, 1.5])
    """
    check_instance("table", table, Mapping, "a mapping of results.csv columns")  # type: ignore[type-abstract]
    missing = [
        name
        for name in ("t", *(f"{q}_A" for q in ("f10", "p10", "f21y", "f21z")))
        if name not in table
    ]
    if missing:
        raise ParameterError(
            f"table lacks the results.csv columns {', '.join(missing)}", key="table"
        )
    t = np.asarray(table["t"], dtype=np.float64)
    dt = np.diff(t)

    def legs(name: str) -> FloatArray:
        return np.stack([np.asarray(table[f"{name}_{leg}"]) for leg in LEGS], axis=-1)

    def column(name: str, leg: str) -> FloatArray:
        return np.asarray(table[f"{name}_{leg}"], dtype=np.float64)

    peaks: list[list[float]] = [[], [], [], [], []]  # |f10|, its time, |p10|, |f21|, energy
    for leg in LEGS:  # column by column: no (N, 3) copies of a big run
        f10, p10 = np.abs(column("f10", leg)), column("p10", leg)
        k = int(f10.argmax())
        peaks[0].append(float(f10[k]))
        peaks[1].append(float(t[k]))
        peaks[2].append(float(np.abs(p10).max()))
        peaks[3].append(float(np.hypot(column("f21y", leg), column("f21z", leg)).max()))
        peaks[4].append(float((0.5 * (p10[1:] + p10[:-1]) * dt).sum()))  # trapezoid rule
    dissipated = None
    if "fric10_A" in table:
        rate = np.zeros_like(t) if dphi is None else np.asarray(dphi, dtype=np.float64)
        powers = np.stack(
            [
                -(legs("fric10") * legs("dlambda10")).sum(axis=-1),
                -(legs("fric21") * rate[:, None]).sum(axis=-1),
                -(legs("fric32") * legs("dlambda32")).sum(axis=-1),
            ],
            axis=-1,
        )
        dissipated = (0.5 * (powers[1:] + powers[:-1]) * np.diff(t)[:, None]).sum(axis=0)
    peak_f10, peak_f10_time, peak_p10, peak_f21, energy = (np.array(p) for p in peaks)
    return RunSummary(
        peak_f10=peak_f10,
        peak_f10_time=peak_f10_time,
        peak_p10=peak_p10,
        peak_f21=peak_f21,
        energy=energy,
        dissipated=dissipated,
    )


def summary_text(summary: RunSummary, heading: str, files: list[str]) -> str:
    """The summary ``prp3 simulate`` prints: peaks and energies per leg, then ``files`` lines."""

    def row(label: str, values: FloatArray, extra: str = "") -> str:
        return f"  {label:<16}" + "".join(f"{v:>14.6g}" for v in values.tolist()) + extra

    lines = [
        heading,
        f"  {'':<16}" + "".join(f"{'leg ' + leg:>14}" for leg in LEGS),
        row(f"peak |f10| ({OUTPUT_QUANTITIES['f10'].unit})", summary.peak_f10),
        row(f"peak |p10| ({OUTPUT_QUANTITIES['p10'].unit})", summary.peak_p10),
        row(f"peak |f21| ({OUTPUT_QUANTITIES['f21y'].unit})", summary.peak_f21),
        row("energy (J)", summary.energy, f"   total {summary.total_energy:.6g} J"),
    ]
    if summary.dissipated is not None:
        kinds = ", ".join(
            f"{kind} {value:.6g} J"
            for kind, value in zip(
                ("guides", "revolute joints", "sleeves"), summary.dissipated, strict=True
            )
        )
        lines.append(f"  dissipated by friction (3 legs): {kinds}")
    lines += files
    return "\n".join(lines)


# ---------------------------------------------------------------- memory
def available_memory() -> int | None:
    """Memory the system can give this process now (bytes), or None when unknown.

    ``MemAvailable`` of ``/proc/meminfo`` (Linux), else the free physical pages.
    """
    try:
        with open("/proc/meminfo", encoding="ascii") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return int(os.sysconf("SC_AVPHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (OSError, ValueError, AttributeError):
        return None


def _size(nbytes: float) -> str:
    for unit, scale in (("TiB", 1024**4), ("GiB", 1024**3), ("MiB", 1024**2)):
        if nbytes >= scale:
            return f"{nbytes / scale:.3g} {unit}"
    return f"{nbytes / 1024:.3g} KiB"


def check_memory(what: str, needed: float, available: int | None = None) -> None:
    """Refuse a run that needs more memory than is available, saying how much, before it starts.

    ``needed`` is the estimate of the run's peak memory (bytes);
    ``available`` defaults to :func:`available_memory`.

    >>> check_memory("--samples 1000000000", 1e12, available=8 * 1024**3)
    Traceback (most recent call last):
    ...
    prp3.errors.Prp3Error: --samples 1000000000: the run needs about 931 GiB of memory, 8 GiB are available: ask for fewer samples
    """
    if available is None:
        available = available_memory()
    if available is None or needed <= available:
        return
    raise Prp3Error(
        f"the run needs about {_size(needed)} of memory, {_size(available)} are available: "
        "ask for fewer samples",
        origin=what,
    )
