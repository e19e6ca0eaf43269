"""prp3: kinematics and complete inverse dynamics of the 3-PRP planar parallel robot.

After S. Staicu and D. Chablat, *Internal joint forces in dynamics of a 3-PRP
planar parallel robot*.  The robot is an immutable :class:`Robot`; the
algorithms are pure functions of ``(robot, motion)`` that return typed
result dataclasses.

>>> import prp3
>>> kin, dyn = prp3.inverse_dynamics(prp3.Robot(), prp3.paper_motion("vertical"))
>>> dyn.f10.shape
(301, 3)
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version

from prp3.analysis.equations_of_motion import (
    bias_forces,
    gravity_forces,
    mass_matrix,
    platform_dynamics,
)
from prp3.analysis.force_histories import ActuatorForces
from prp3.analysis.forward import ForwardDynamics, forward_dynamics
from prp3.analysis.forward_kinematics import (
    forward_acceleration,
    forward_kinematics,
    forward_velocity,
)
from prp3.analysis.inverse_dynamics import METHODS, inverse_dynamics, kernel_method
from prp3.analysis.reachability import (
    jacobian_condition,
    orientation_range,
    reachable,
    reachable_region,
)
from prp3.analysis.workspace import orientation_scan, workspace_slice, workspace_statics
from prp3.engines.compiled_robot import CompiledRobot, compile_robot
from prp3.engines.entries import FastForces, paper_forces
from prp3.engines.sample_entries import sample_forces
from prp3.errors import (
    InputFileError,
    OutputFileError,
    ParameterError,
    Prp3Error,
    SingularPoseError,
    TrajectoryError,
    UnreachablePoseError,
)
from prp3.mechanics.forces import InverseDynamics
from prp3.mechanics.geometry import (
    ForwardGeometry,
    InverseGeometry,
    forward_geometry,
    inverse_geometry,
    platform_vertices,
)
from prp3.mechanics.kinematics import Kinematics, inverse_kinematics, jacobian
from prp3.model.motion import Motion, law_motion, paper_motion
from prp3.model.parameters import Limits, LinkParameters, PistonParameters, PlatformParameters
from prp3.model.robot import Robot
from prp3.references.newton_euler import newton_euler
from prp3.validation import LEGS

try:
    __version__ = version("prp3")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0"

__all__ = [
    "LEGS",
    "METHODS",
    "ActuatorForces",
    "CompiledRobot",
    "FastForces",
    "ForwardDynamics",
    "ForwardGeometry",
    "InputFileError",
    "InverseDynamics",
    "InverseGeometry",
    "Kinematics",
    "Limits",
    "LinkParameters",
    "Motion",
    "OutputFileError",
    "ParameterError",
    "PistonParameters",
    "PlatformParameters",
    "Prp3Error",
    "Robot",
    "SingularPoseError",
    "TrajectoryError",
    "UnreachablePoseError",
    "__version__",
    "bias_forces",
    "compile_robot",
    "forward_acceleration",
    "forward_dynamics",
    "forward_geometry",
    "forward_kinematics",
    "forward_velocity",
    "gravity_forces",
    "inverse_dynamics",
    "inverse_geometry",
    "inverse_kinematics",
    "jacobian",
    "jacobian_condition",
    "kernel_method",
    "law_motion",
    "mass_matrix",
    "newton_euler",
    "orientation_range",
    "orientation_scan",
    "paper_forces",
    "paper_motion",
    "platform_dynamics",
    "platform_vertices",
    "reachable",
    "reachable_region",
    "sample_forces",
    "workspace_slice",
    "workspace_statics",
]
