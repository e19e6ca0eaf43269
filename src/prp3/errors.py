"""The one exception family of prp3.

Every error a user can cause (bad parameters, a bad trajectory, a singular or
unreachable pose, a malformed file) is raised as a subclass of
:class:`Prp3Error` at the public boundary, with a one-line message that names
the offending argument and value.  The command line turns it into one line on
stderr and exit status 2.

>>> issubclass(SingularPoseError, Prp3Error)
True
"""

from __future__ import annotations

__all__ = [
    "InputFileError",
    "OutputFileError",
    "ParameterError",
    "Prp3Error",
    "SingularPoseError",
    "TrajectoryError",
    "UnreachablePoseError",
]


class Prp3Error(ValueError):
    """Base class of every error prp3 raises for bad user input."""


class ParameterError(Prp3Error):
    """Invalid robot parameters (non-positive length or mass, unknown key, ...)."""


class TrajectoryError(Prp3Error):
    """Invalid motion: wrong shapes, non-finite values, non-increasing time, ..."""


class SingularPoseError(Prp3Error):
    """A pose at or too near a singular configuration of the mechanism."""


class UnreachablePoseError(Prp3Error):
    """A pose the robot cannot reach (outside the actuator strokes)."""


class InputFileError(Prp3Error):
    """A malformed input file (TOML or CSV); the message names file, line and column."""


class OutputFileError(Prp3Error):
    """An output file or directory that cannot be written (names the path and the reason)."""
