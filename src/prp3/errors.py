"""The one exception family of prp3, with structured locations.

Every error a user can cause (bad parameters, a bad trajectory, a singular or
unreachable pose, a malformed file) is raised as a subclass of
:class:`Prp3Error` at the public boundary.  Besides its one-line message, an
error carries *where* it happened as attributes — the file, line and column of
an input file, the key of a parameter, the sample index, its time, the leg and
the pose — so that a caller (the command line) can add what it knows
(:meth:`Prp3Error.located`) without ever parsing a message.

The message is assembled from the fields::

    [file[:line[:column]] | origin]: [subject]: [sample k[, t = T s][, leg L]]: reason

>>> issubclass(SingularPoseError, Prp3Error)
True
>>> error = TrajectoryError("not finite (nan)", subject="motion: pose", sample=3)
>>> str(error)
'motion: pose: sample 3: not finite (nan)'
>>> error.sample, error.line
(3, None)
>>> str(error.located(file="traj.csv", line=5, time=0.25, subject=None))
'traj.csv:5: sample 3, t = 0.25 s: not finite (nan)'
"""

from __future__ import annotations

import copy
from typing import Any, Self

__all__ = [
    "InputFileError",
    "OutputFileError",
    "ParameterError",
    "Prp3Error",
    "SingularPoseError",
    "TrajectoryError",
    "UnreachablePoseError",
]

_UNSET: Any = object()


def one_line(text: str) -> str:
    r"""``text`` on one line: each line break and the indentation after it become one space.

    A message quotes the user's values, and the ``repr`` of a 2-D array or of a
    long mapping spans lines; the command line prints every error on one line.

    >>> one_line("robot must be a prp3.Robot, got array([[0.],\n       [0.]])")
    'robot must be a prp3.Robot, got array([[0.], [0.]])'
    """
    return (
        " ".join(part.strip() for part in text.splitlines())
        if "\n" in text or "\r" in text
        else text
    )


class Prp3Error(ValueError):
    """Base class of every error prp3 raises for bad user input.

    Parameters
    ----------
    reason : str
        What is wrong, without the location (which the fields give).
    file : str or Path, optional
        The input or output file concerned.
    line, column : int, optional
        1-based line and column in ``file``.
    origin : str, optional
        Where the value came from when it is not a file (a command-line
        option such as ``--motion vertical``); shown in place of ``file``.
    subject : str, optional
        The argument or quantity concerned (``"pose"``, ``"robot"``, ...).
    key : str, optional
        The parameter key (``"platform.mass"``) or the column name of a table.
    sample : int, optional
        Index of the offending sample (0-based) in the motion or table.
    time : float, optional
        Time of that sample (s).
    leg : str, optional
        ``"A"``, ``"B"`` or ``"C"``.
    pose : tuple of float, optional
        ``(x, y, φ)`` of the offending sample.

    Attributes
    ----------
    reason, file, line, column, origin, subject, key, sample, time, leg, pose
        As given; ``None`` when not known.
    """

    def __init__(
        self,
        reason: str,
        *,
        file: object = None,
        line: int | None = None,
        column: int | None = None,
        origin: str | None = None,
        subject: str | None = None,
        key: str | None = None,
        sample: int | None = None,
        time: float | None = None,
        leg: str | None = None,
        pose: tuple[float, float, float] | None = None,
    ) -> None:
        reason = one_line(reason)
        super().__init__(reason)
        self.reason = reason
        self.file = None if file is None else str(file)
        self.line = line
        self.column = column
        self.origin = origin
        self.subject = subject
        self.key = key
        self.sample = sample
        self.time = time
        self.leg = leg
        self.pose = pose
        self.args = (str(self),)

    def located(
        self,
        *,
        file: object = _UNSET,
        line: int | None = _UNSET,
        column: int | None = _UNSET,
        origin: str | None = _UNSET,
        subject: str | None = _UNSET,
        sample: int | None = _UNSET,
        time: float | None = _UNSET,
    ) -> Self:
        """A copy of this error with the given location fields replaced (``None`` removes one)."""
        other = copy.copy(self)
        changes = {
            "file": file,
            "line": line,
            "column": column,
            "origin": origin,
            "subject": subject,
            "sample": sample,
            "time": time,
        }
        for name, value in changes.items():
            if value is not _UNSET:
                setattr(other, name, str(value) if name == "file" and value is not None else value)
        other.args = (str(other),)
        return other

    @property
    def where(self) -> str:
        """The location part of the message (empty when nothing is known)."""
        parts: list[str] = []
        if self.file is not None:
            place = self.file
            if self.line is not None:
                place += f":{self.line}"
                if self.column is not None:
                    place += f":{self.column}"
            parts.append(place)
        elif self.origin is not None:
            parts.append(self.origin)
        if self.subject:
            parts.append(self.subject)
        if self.sample is not None:
            sample = f"sample {self.sample}"
            if self.time is not None:
                sample += f", t = {self.time:.9g} s"
            if self.leg is not None:
                sample += f", leg {self.leg}"
            parts.append(sample)
        return ": ".join(parts)

    def __str__(self) -> str:
        where = self.where
        return f"{where}: {self.reason}" if where else self.reason

    def __reduce__(self) -> Any:  # keep the fields through pickling (dask workers)
        return (_rebuild, (type(self), self.reason, dict(self.__dict__)))


def _rebuild(kind: type[Prp3Error], reason: str, fields: dict[str, Any]) -> Prp3Error:
    error = kind(reason)
    error.__dict__.update(fields)
    return error


class ParameterError(Prp3Error):
    """Invalid robot parameters (non-positive length or mass, unknown key, ...)."""


class TrajectoryError(Prp3Error):
    """Invalid motion: wrong shapes, non-finite values, non-increasing time, ..."""


class SingularPoseError(Prp3Error):
    """A pose at or too near a singular configuration of the mechanism."""


class UnreachablePoseError(Prp3Error):
    """A pose the robot cannot reach (outside the actuator strokes)."""


class InputFileError(Prp3Error):
    """A malformed input file (TOML or CSV); the fields name file, line and column."""


class OutputFileError(Prp3Error):
    """An output file or directory that cannot be written (names the path and the reason)."""
