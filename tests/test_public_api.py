"""Every public function refuses every kind of bad argument the same way.

The test walks the public API (``prp3.__all__`` and the ``__all__`` of the
modules listed in :data:`MODULES`): every callable there is either in
:data:`CASES`, with good arguments and the kind of each argument it takes, or
in :data:`EXEMPT` with the reason it takes no user values to check.  A new
public function without an entry makes :func:`test_every_public_callable_is_covered`
fail.

Each argument of each case is spoilt in every way its kind allows (booleans,
text, ``None``, ``10**400``, masked arrays, wrong shapes, NaN and infinity for
arrays and numbers; booleans, floats and huge values for integers; wrong types
for robots and motions; unknown names for choices), the others kept good.  The
call must raise a :class:`~prp3.errors.Prp3Error` (never ``TypeError``,
``AttributeError``, ``ValueError`` or a numpy warning) whose message is one
line and names the argument.
"""

from __future__ import annotations

import importlib
import inspect
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from functools import cache
from typing import Any

import numpy as np
import pytest

import prp3
import prp3.analysis.equations_of_motion
import prp3.analysis.forward
import prp3.analysis.workspace
import prp3.apps.base_parameters
import prp3.apps.codegen
import prp3.apps.control
import prp3.apps.control_law
import prp3.apps.design
import prp3.apps.design_evaluation
import prp3.apps.design_objective
import prp3.apps.excitation
import prp3.apps.identification
import prp3.apps.mjcf
import prp3.apps.regressor
import prp3.apps.runs
import prp3.apps.sweep_spec
import prp3.engines.entries
import prp3.engines.sample_entries
import prp3.engines.select
import prp3.mechanics.geometry
import prp3.model.motion
import prp3.model.parameters
import prp3.model.robot
import prp3.references.paper
import prp3.references.paper_kinematics
import prp3.references.paper_wrenches
from prp3.errors import Prp3Error

#: Modules whose ``__all__`` is walked besides ``prp3``'s own.
MODULES = (
    "prp3.apps.control",
    "prp3.apps.control_law",
    "prp3.apps.plants",
    "prp3.apps.design",
    "prp3.apps.design_evaluation",
    "prp3.apps.design_objective",
    "prp3.apps.sweep_spec",
    "prp3.analysis.inverse_dynamics",
    "prp3.engines.select",
    "prp3.engines.entries",
    "prp3.engines.compiled_robot",
    "prp3.engines.sample_entries",
    "prp3.analysis.forward",
    "prp3.analysis.forward_kinematics",
    "prp3.analysis.equations_of_motion",
    "prp3.analysis.force_histories",
    "prp3.mechanics.geometry",
    "prp3.apps.identification",
    "prp3.apps.regressor",
    "prp3.apps.base_parameters",
    "prp3.apps.excitation",
    "prp3.mechanics.kinematics",
    "prp3.apps.mjcf",
    "prp3.apps.codegen",
    "prp3.model.parameters",
    "prp3.model.robot",
    "prp3.model.motion",
    "prp3.references.newton_euler",
    "prp3.references.paper",
    "prp3.references.paper_kinematics",
    "prp3.references.paper_wrenches",
    "prp3.apps.runs",
    "prp3.analysis.reachability",
    "prp3.analysis.workspace",
)

#: The modules of the validation layer (their checks are what the cases exercise).
VALIDATION_MODULES = ("prp3.validation", "prp3.pose_validation", "prp3.path_validation")

#: Public callables that take no user value to validate, with the reason.
EXEMPT: dict[str, str] = {
    # result types: built by prp3 from validated values, not by users
    "InverseDynamics": "result type",
    "InverseGeometry": "result type",
    "Kinematics": "result type",
    "FastForces": "result type",
    "SampleForces": "result type",
    "ForwardDynamics": "result type",
    "ForwardGeometry": "result type",
    "PlatformDynamics": "result type",
    "CompiledRobot": "built by compile_robot from a validated robot",
    "CompiledSpatial": "built by compile_spatial from a validated robot",
    "SpatialSample": "result type",
    "SpatialSamples": "result type",
    "JointWrenches": "result type",
    "OrientationScan": "result type",
    "WorkspaceSlice": "result type",
    "WorkspaceStatics": "result type",
    "Tracking": "result type",
    "RecursiveMatrixResult": "result type",
    "PaperGeometry": "result type",
    "PaperVelocities": "result type",
    "PaperAccelerations": "result type",
    "VirtualVelocities": "result type",
    "FixedFrameKinematics": "result type",
    "RunSummary": "result type",
    "BaseParameters": "result type",
    "ExcitingTrajectory": "result type",
    "Identification": "result type",
    "IdentifiedRobot": "result type",
    "Regressor": "result type",
    "CSource": "result type",
    "MjcfWarning": "a warning category",
    "DesignEvaluator": "built by sweep_spec from a validated sweep file",
    "DesignObjective": "built by sweep_spec from a validated sweep file",
    "SweepSpec": "built by sweep_spec / read_sweep_spec",
    "Friction": "holds JointFriction values, each validated",
    "Spring": "holds SpringParameters values, each validated",
    "name_overflow_input": "reads an error prp3 raised and a Motion (validated when built)",
    "InputFileError": "exception",
    "OutputFileError": "exception",
    "ParameterError": "exception",
    "Prp3Error": "exception",
    "SingularPoseError": "exception",
    "TrajectoryError": "exception",
    "UnreachablePoseError": "exception",
    # files: paths, opened with the file named in every error (tests/test_faults.py)
    "read_sweep_spec": "reads a file (tests/test_faults.py)",
    # internal numerics documented as unchecked
    "sample_forces_unchecked": "the unchecked inner call of sample_forces, by its name",
    "cross2": "2-vector helper of the geometry (internal numerics)",
    "dot2": "2-vector helper of the geometry (internal numerics)",
    "perp": "2-vector helper of the geometry (internal numerics)",
    "rot": "3x3 matrix helper of the paper's method (internal numerics)",
    "skew": "3x3 matrix helper of the paper's method (internal numerics)",
    "vee": "3x3 matrix helper of the paper's method (internal numerics)",
    "theta_alpha": "3x3 matrix helper of the paper's method (internal numerics)",
    "platform_centre": "constant vector of the paper's method (internal numerics)",
    # the stages of the paper's method, on the arrays paper_method has validated
    "orientation_condition": "stage of the paper's method (internal numerics)",
    "paper_geometry": "stage of the paper's method (internal numerics)",
    "paper_velocities": "stage of the paper's method (internal numerics)",
    "paper_accelerations": "stage of the paper's method (internal numerics)",
    "virtual_velocities": "stage of the paper's method (internal numerics)",
    "fixed_frame_kinematics": "stage of the paper's method (internal numerics)",
    "body_constants": "stage of the paper's method (takes a validated Robot)",
    "weight_wrenches": "stage of the paper's method (internal numerics)",
    "inertia_wrenches": "stage of the paper's method (internal numerics)",
    "chain_wrenches": "stage of the paper's method (internal numerics)",
    "virtual_work": "stage of the paper's method (internal numerics)",
    "other_reactions": "stage of the paper's method (internal numerics)",
    "excitation_refusal": "identify's criterion on the regressor it built (shared with excite)",
    "samples_refusal": "identify's count of samples, of a validated motion or excite's option",
    "check_forward_friction": "a check itself (takes a validated Robot)",
    "check_stroke": "a check itself, called by inverse_geometry on validated arrays",
    "check_memory": "a check itself (tests/test_faults.py)",
    "available_memory": "no arguments",
    "summary_text": "formats a RunSummary built by summarize",
    "design_columns": "names of columns from a validated sweep file",
    "design_mapping": "used by design_robot (covered)",
    "design_values": "takes a SweepSpec built by sweep_spec",
    "parameter_paths": "a parsed [parameters] table of a sweep file (its key paths checked)",
    "nominal_value": "looks up a path of a validated sweep file",
    "nominal_design_row": "the metadata row of a validated sweep spec's nominal design",
    "penalized_objective": "takes columns computed by evaluate_designs",
    "quantity": "takes columns computed by evaluate_designs",
    "control_force": "the controller's inner step, called by track on validated values",
    "check_model": "a check itself, called by track",
    "check_plant": "a check itself, called by track",
    "symbolic_parameters": "sympy",
    # the engines: they receive validated inputs and never validate (test_no_engine_sees_...)
    "run_numpy": "an engine: called by prp3.engines.entries with validated samples",
    "runs_on": "which engine runs a validated robot (internal)",
    "resolve_engine": "a check itself (the engine argument, covered through every entry)",
    "default_engine": "no arguments",
    "numba_module": "no arguments",
    "EngineWarning": "a warning category",
    # result types and models of the family and the other public names of 0.2
    "Body": "a FamilyRobot's body, validated by FamilyRobot (tests/test_family_model.py)",
    "LegDesign": "a FamilyRobot's leg, validated by FamilyRobot (tests/test_family_model.py)",
    "PlatformBody": "a FamilyRobot's platform, validated by FamilyRobot (tests/test_family_model.py)",
    "FamilyRobot": "validated in __post_init__ (tests/test_family_model.py)",
    "FamilyCSource": "result type",
    "SpatialCSource": "result type (spatial_c_inverse_dynamics)",
    "FamilyEffortModel": "result type",
    "FamilyForward": "result type",
    "FamilyKinematics": "result type",
    "FamilyOrientationScan": "result type",
    "FamilySolution": "result type",
    "FamilyStatics": "result type",
    "FamilySweepSpec": "built by family_sweep_spec from a validated sweep file",
    "FamilyWorkspace": "result type",
    "ForceInput": "result type (read_forces)",
    "Measurements": "result type (read_measurements)",
    "Trajectory": "result type (read_trajectory)",
    "KernelSolution": "result type",
    "OptimizeOutcome": "result type",
    "SweepRun": "result type",
    "StagedOutput": "built by staged_output",
    "Run": "result type (read_run)",
    "Element": "the base class of the elements (an interface)",
    "FrictionElement": "built by the Robot from validated Friction values",
    "GravityElement": "built by the Robot from its validated gravity",
    "LoadElement": "built by the Robot from a validated Load",
    "PayloadElement": "built by the Robot from a validated Payload",
    "SpringElement": "built by the Robot from validated Spring values",
    "WrenchElement": "built from a validated Motion's load columns",
    "Ops": "the arithmetic interface of the kernel (numpy, math, sympy), not called with user values",
    "sympy_ops": "no user values (the sympy arithmetic of the kernel)",
    "symbolic_solution": "sympy symbols, no user values",
    "spring_force": "the spring's law on the kernel's Ops values (internal numerics)",
    "read_trajectory": "reads a file (tests/test_faults.py, tests/test_io.py)",
    "read_spatial_robot": "reads a file (tests/test_spatial_cli.py, a hypothesis test of its keys)",
    "read_spatial_trajectory": "reads a file (tests/test_spatial_cli.py)",
    "SpatialRobotFile": "result type (read_spatial_robot)",
    "FamilyRegressor": "result type (family_regressor)",
    "SpatialTrajectory": "result type (read_spatial_trajectory)",
    "read_spatial_measurements": "reads a file (tests/test_spatial_identification.py)",
    "SpatialMeasurements": "result type (read_spatial_measurements)",
    "SpatialRegressor": "result type (spatial_regressor)",
    "SpatialExcitation": "result type (spatial_exciting_trajectory)",
    "read_forces": "reads a file (tests/test_faults.py, tests/test_io.py)",
    "read_measurements": "reads a file (tests/test_faults.py, tests/test_io.py)",
    "read_table": "reads a file (tests/test_faults.py, tests/test_io.py)",
    "read_table_csv": "reads a file (tests/test_faults.py, tests/test_io.py)",
    "read_designs": "reads a file (tests/test_sweep.py)",
    "read_manifest": "reads a file (tests/test_faults.py)",
    "read_robot_file": "reads a file (tests/test_family_model.py)",
    "read_run": "reads a folder (tests/test_explore.py)",
    "robot_file_form": "which form a parsed ROBOT.toml is in (tests/test_family_model.py)",
    "write_table_csv": "writes a table prp3 built (tests/test_faults.py)",
    "write_table_parquet": "writes a table prp3 built (tests/test_faults.py)",
    "write_run_html": "writes a Run read by read_run (tests/test_explore.py)",
    "staged_output": "a folder's staging (tests/test_fault_injection.py)",
    "serve": "the Bokeh server (tests/test_explore_browser.py)",
    "dask_client": "a scheduler address or a LocalCluster (tests/test_sweep.py)",
    "run_sweep": "a sweep file's run (tests/test_sweep.py, tests/test_faults.py)",
    "optimize_design": "a sweep file's run (tests/test_sweep.py)",
    "run_family_sweep": "a sweep file's run (tests/test_family_design.py)",
    "optimize_family": "a sweep file's run (tests/test_family_design.py)",
    "family_sweep_spec": "a parsed sweep file (tests/test_family_design.py)",
    "spatial_sweep_spec": "a parsed sweep file (tests/test_spatial_sweep.py)",
    "read_spatial_sweep_spec": "reads a sweep file (tests/test_spatial_sweep.py)",
    "read_family_sweep_spec": "reads a sweep file (tests/test_family_design.py)",
    "SpatialSweepSpec": "built by spatial_sweep_spec from a validated sweep file",
    "optimize_spatial": "a sweep file's run (tests/test_spatial_sweep.py)",
    "RowEvaluator": "a Protocol (DesignEvaluator, SpatialEvaluator implement it)",
    "evaluate_rows": "takes an evaluator built by sweep_spec or spatial_sweep_spec",
    "sample_designs": "validated Parameter ranges of a sweep file (design_values' designs)",
    "spec_number": "a value of a parsed sweep file, named by its key (tests/test_spatial_sweep.py)",
    "evaluate_family_designs": "takes a FamilySweepSpec built by family_sweep_spec",
    "family_design_robot": "takes a FamilySweepSpec built by family_sweep_spec",
    "results_table": "formats an InverseDynamics built by prp3",
    "result_columns": "names of the columns of a validated Robot",
    "trajectory_table": "formats a validated Motion",
    "family_results_table": "formats a FamilySolution built by prp3",
    "family_template": "a documented ROBOT.toml of an architecture name (tests/test_family_model.py)",
    "family_c_inverse_dynamics": "C of a validated FamilyRobot (tests/test_family_codegen.py)",
    "family_mjcf_model": "MJCF of a validated FamilyRobot (tests/test_family_mjcf.py)",
    "spatial_mjcf_model": "MJCF of a validated SpatialRobot (tests/test_spatial_mjcf.py)",
    "spatial_mjcf_robot": "parses MJCF text (tests/test_spatial_mjcf.py: foreign, edited and mutated models)",
    "read_spatial_mjcf": "reads a file (tests/test_spatial_mjcf.py)",
    "spatial_urdf_model": "URDF of a validated SpatialRobot (tests/test_spatial_urdf.py)",
    "spatial_urdf_closures": "closures' YAML of a validated SpatialRobot (tests/test_spatial_urdf.py)",
    "spatial_urdf_robot": "parses URDF and YAML text (tests/test_spatial_urdf.py: foreign, edited and mutated files)",
    "read_spatial_urdf": "reads two files (tests/test_spatial_urdf.py)",
    "family_energy": "energies of a FamilyKinematics built by family_kinematics",
    "singularity_margin": "the measures of a FamilyKinematics built by family_kinematics",
    "newton_euler_dynamics": "Newton-Euler on a FamilyKinematics built by family_kinematics",
    "SpatialRobot": "validated in __post_init__ (tests/test_spatial_kinematics.py)",
    "Joint": "a SpatialRobot's joint, validated by SpatialRobot",
    "Leg": "a SpatialRobot's leg, validated by SpatialRobot",
    "PlatformMotion": "built by rpy_motion / quaternion_motion / at_rest (covered)",
    "SpatialKinematics": "result type",
    "SpatialSolution": "result type",
    "SpatialForward": "result type (spatial_forward_dynamics)",
    "SpatialTracking": "result type (spatial_track)",
    "SpatialPlatformDynamics": "result type (spatial_platform_dynamics)",
    "SpatialEfforts": "result type (read_spatial_efforts)",
    "read_spatial_efforts": "reads a file (tests/test_spatial_forward.py: prp3 forward's refusals)",
    "spatial_results_table": "formats a SpatialSolution built by prp3",
    "SpatialWorkspace": "result type (spatial_workspace)",
    "spatial_workspace_table": "formats a SpatialWorkspace built by prp3",
    "spatial_statics_table": "formats a SpatialWorkspace built by prp3 (refusal without statics: tests/test_spatial_workspace.py)",
    "python_sample": "one sample of the C's steps on floats, for the docs (tests/test_family_codegen.py)",
    "leg_chain": "the chain of docs/family.md on joint values (internal numerics)",
    "leg_jacobian": "the chain of docs/family.md on joint values (internal numerics)",
    "leg_measure": "the chain of docs/family.md on joint values (internal numerics)",
    "parallel_measure": "the chain of docs/family.md on joint values (internal numerics)",
    "transmitted_wrench": "the chain of docs/family.md on joint values (internal numerics)",
}

ROBOT = prp3.Robot()
LIMITED = prp3.Robot(limits=prp3.Limits(stroke=(-0.2, 0.2)))
SMALL = np.array([0.01, -0.02, 0.1])
ZERO = np.zeros(3)


@cache
def _motion() -> prp3.Motion:
    return prp3.paper_motion("vertical", 7)


@cache
def _hexapod() -> prp3.SpatialRobot:
    return prp3.hexapod()


@cache
def _rps_motion() -> prp3.PlatformMotion:
    return prp3.spatial_random_motion(prp3.three_rps(), 80, 0)


@cache
def _rps_efforts() -> np.ndarray:
    return prp3.spatial_inverse_dynamics(prp3.three_rps(), _rps_motion()).tau


@cache
def _rps_identification() -> prp3.Identification:
    return prp3.spatial_identify(prp3.three_rps(), _rps_motion(), _rps_efforts())


@cache
def _at_home() -> prp3.PlatformMotion:
    return prp3.PlatformMotion.at_rest(prp3.hexapod().home_position)


@cache
def _rrr() -> prp3.FamilyRobot:
    return prp3.FamilyRobot.default("3-RRR")


@cache
def _compiled() -> prp3.CompiledRobot:
    return prp3.compile_robot(ROBOT)


@cache
def _kinematics() -> prp3.Kinematics:
    return prp3.inverse_kinematics(ROBOT, _motion())


@cache
def _forces() -> prp3.ActuatorForces:
    return prp3.ActuatorForces(t=[0.0, 1.0], f10=np.zeros((2, 3)))


@cache
def _measured() -> np.ndarray:
    return prp3.inverse_dynamics(ROBOT, _motion())[1].f10


def _least_squares_regressor() -> np.ndarray:
    return np.random.default_rng(1).normal(size=(10, 3, 2))


def _noise() -> np.ndarray:
    return 1e-3 * np.random.default_rng(2).normal(size=(10, 3))


@cache
def _identification() -> prp3.Identification:
    return prp3.identify(ROBOT, _motion(), _measured(), ("platform_mass",))


@cache
def _design_evaluator() -> prp3.DesignEvaluator:
    return prp3.DesignEvaluator(nominal={}, paths=("l0",), motions=(_motion(),), workspace=False)


def _times_bad(good: np.ndarray) -> Iterator[tuple[str, Any]]:
    for label, value in _array_bad(good):
        yield label, np.stack([good, good], axis=-1) if label == "wrong shape" else value


def _array_bad(good: np.ndarray) -> Iterator[tuple[str, Any]]:
    yield "booleans", good.astype(bool)
    yield "text", good.astype(str)
    yield "None", None
    huge: Any = good.astype(int).tolist()
    if good.ndim == 0:
        huge = 10**400
    elif good.ndim == 1:
        huge[-1] = 10**400
    else:
        huge[-1][-1] = 10**400
    yield "huge integer", huge
    yield "masked array", np.ma.masked_array(good, mask=np.ones(good.shape, dtype=bool))
    if good.ndim >= 1:
        yield "wrong shape", good[..., :-1]
    yield "scalar for an array", 0.5 if good.ndim >= 1 else np.zeros((2, 2))
    for value in (math.nan, math.inf):
        spoilt = good.astype(float).copy()
        spoilt.reshape(-1)[-1] = value
        yield repr(value), spoilt


def _real_bad(good: float) -> Iterator[tuple[str, Any]]:
    yield "boolean", True
    yield "text", str(good)
    yield "None", None
    yield "huge integer", 10**400
    yield "nan", math.nan
    yield "inf", math.inf
    yield "masked", np.ma.masked_array([good], mask=[True])[0]
    yield "array", np.array([good, good])


def _int_bad(good: int) -> Iterator[tuple[str, Any]]:
    yield "boolean", True
    yield "text", str(good)
    yield "None", None
    yield "huge integer", 10**400
    yield "float", float(good) + 0.5
    yield "nan", math.nan
    yield "array", np.array([good, good])


def _object_bad(good: Any) -> Iterator[tuple[str, Any]]:
    yield "None", None
    yield "text", "robot"
    yield "number", 0.3
    yield "array", np.zeros(3)


def _choice_bad(good: str) -> Iterator[tuple[str, Any]]:
    yield "None", None
    yield "boolean", True
    yield "number", 3
    yield "unknown name", "no-such-choice"


def _names_bad(good: Any) -> Iterator[tuple[str, Any]]:
    yield "None", None
    yield "a bare string", "platform_mass"
    yield "booleans", [True]
    yield "unknown name", ["no_such_parameter"]
    yield "empty", []


SPOILERS: dict[str, Callable[[Any], Iterator[tuple[str, Any]]]] = {
    "array": _array_bad,
    "times": _times_bad,
    "real": _real_bad,
    "int": _int_bad,
    "object": _object_bad,
    "choice": _choice_bad,
    "names": _names_bad,
}


#: Labels a kind's modifier lets through: ``?`` None is a valid value (a default),
#: ``*`` elementwise (any shape), ``~`` NaN and infinity are valid (skipped), ``0`` may be empty.
ALLOWED = {
    "?": {"None"},
    "*": {"wrong shape", "scalar for an array"},
    "~": {"nan", "inf"},
    "0": {"empty"},
}


def _kind(kind: str) -> tuple[str, set[str]]:
    """The spoiler of ``kind`` and the labels its modifiers allow."""
    base = kind.rstrip("?*~0")
    allowed: set[str] = set()
    for mark in kind[len(base) :]:
        allowed |= ALLOWED[mark]
    return base, allowed


#: A good value of each kind, to list the labels of its bad values.
SAMPLE_GOOD: dict[str, Any] = {
    "times": np.zeros(1),
    "array": np.zeros(1),
    "real": 1.0,
    "int": 1,
    "object": None,
    "choice": "x",
    "names": (),
}


@dataclass(frozen=True)
class Case:
    """A public callable, its good arguments (by keyword) and the kind of each checked one."""

    call: Callable[..., object]
    good: Callable[[], dict[str, Any]]
    kinds: dict[str, str]
    #: words that name an argument in a message, when not (only) its own name
    names: dict[str, tuple[str, ...]] = field(default_factory=dict)


def _case(
    call: Callable[..., object],
    kinds: dict[str, str],
    names: dict[str, tuple[str, ...]] | None = None,
    **good: Any,
) -> Case:
    def arguments() -> dict[str, Any]:
        return {k: (v() if callable(v) and not isinstance(v, type) else v) for k, v in good.items()}

    return Case(call, arguments, kinds, names or {})


def _defaults(call: Callable[..., object]) -> dict[str, Any]:
    """The keyword defaults of ``call``: the good values of a default design's case."""
    return {
        name: parameter.default
        for name, parameter in inspect.signature(call).parameters.items()
        if parameter.default is not inspect.Parameter.empty
    }


A, T, R, INT, OBJ, C, N = "array", "times", "real", "int", "object", "choice", "names"
POSE = {"pose": A}
#: The arguments of the batch paths of prp3.engines.entries, and good values of them.
BATCH = {"robot": OBJ, "pose": A, "velocity": A, "acceleration": A, "chunk_size": INT}
BATCH_GOOD = {
    "robot": ROBOT,
    "pose": SMALL,
    "velocity": ZERO,
    "acceleration": ZERO,
    "chunk_size": 64,
}
#: The arguments of the single-sample paths of prp3.engines.sample_entries, and good values of them.
SINGLE = {
    "compiled": OBJ,
    "pose": A,
    "velocity": A,
    "acceleration": A,
    "load": A + "?",
    "engine": "choice?",
}
SINGLE_GOOD = {
    "compiled": _compiled,
    "pose": SMALL,
    "velocity": ZERO,
    "acceleration": ZERO,
    "load": ZERO,
    "engine": "numba",
}

CASES: dict[str, Case] = {
    # ---------------------------------------------------------------- prp3
    "Robot": _case(
        prp3.Robot,
        {
            "l0": R,
            "gravity": A,
            "piston": OBJ,
            "link": OBJ,
            "platform": OBJ,
            "limits": OBJ,
            "payload": OBJ,
            "load": OBJ,
            "friction": "object?",
        },
        l0=0.3,
        gravity=np.array([0.0, -9.81]),
        piston=prp3.PistonParameters(),
        link=prp3.LinkParameters(),
        platform=prp3.PlatformParameters(),
        limits=prp3.Limits(),
        payload=prp3.model.parameters.Payload(),
        load=prp3.model.parameters.Load(),
        friction=None,
    ),
    "Limits": _case(
        prp3.Limits,
        {"stroke": "array?", "max_force": "real?"},
        stroke=np.array([-0.2, 0.2]),
        max_force=100.0,
    ),
    "LinkParameters": _case(
        prp3.LinkParameters,
        {"mass": R, "inertia": R, "com": A},
        mass=0.75,
        inertia=6e-4,
        com=np.array([0.0, 0.0]),
    ),
    "PistonParameters": _case(
        prp3.PistonParameters,
        {"mass": R, "inertia": R, "com": A},
        mass=1.0,
        inertia=0.0,
        com=np.array([0.0, 0.0]),
    ),
    "PlatformParameters": _case(
        prp3.PlatformParameters, {"mass": R, "inertia": "real?"}, mass=3.0, inertia=0.01
    ),
    "Payload": _case(
        prp3.model.parameters.Payload,
        {"mass": R, "com": A, "inertia": R},
        mass=1.0,
        com=np.array([0.0, 0.0]),
        inertia=0.0,
    ),
    "Load": _case(
        prp3.model.parameters.Load,
        {"force": A, "moment": R},
        force=np.array([0.0, 0.0]),
        moment=0.0,
    ),
    "JointFriction": _case(
        prp3.model.parameters.JointFriction, {"viscous": R, "coulomb": R}, viscous=0.0, coulomb=0.0
    ),
    "SpringParameters": _case(
        prp3.model.parameters.SpringParameters,
        {"stiffness": R, "rest": R, "damping": R},
        stiffness=0.0,
        rest=0.0,
        damping=0.0,
    ),
    "Motion": _case(
        prp3.Motion,
        {"t": T, "pose": A, "velocity": A, "acceleration": A},
        t=np.array([0.0, 1.0]),
        pose=np.zeros((2, 3)),
        velocity=np.zeros((2, 3)),
        acceleration=np.zeros((2, 3)),
    ),
    "ActuatorForces": _case(
        prp3.ActuatorForces, {"t": T, "f10": A}, t=np.array([0.0, 1.0]), f10=np.zeros((2, 3))
    ),
    "compile_robot": _case(prp3.compile_robot, {"robot": OBJ}, robot=ROBOT),
    "forward_acceleration": _case(
        prp3.forward_acceleration,
        {"robot": OBJ, "pose": A, "velocity": A, "ddlambda10": A},
        robot=ROBOT,
        pose=SMALL,
        velocity=ZERO,
        ddlambda10=ZERO,
    ),
    "forward_dynamics": _case(
        prp3.forward_dynamics,
        {
            "robot": OBJ,
            "forces": OBJ,
            "t": T,
            "initial_pose": A,
            "initial_velocity": A,
            "rtol": R,
            "atol": R,
        },
        robot=ROBOT,
        forces=_forces,
        t=np.array([0.0, 0.01]),
        initial_pose=SMALL,
        initial_velocity=ZERO,
        rtol=1e-8,
        atol=1e-10,
    ),
    "forward_geometry": _case(
        prp3.forward_geometry, {"robot": OBJ, "lambda10": A}, robot=ROBOT, lambda10=ZERO
    ),
    "forward_kinematics": _case(
        prp3.forward_kinematics,
        {"robot": OBJ, "t": A, "lambda10": A, "dlambda10": A, "ddlambda10": A},
        robot=ROBOT,
        t=np.array(0.0),
        lambda10=ZERO,
        dlambda10=ZERO,
        ddlambda10=ZERO,
    ),
    "forward_velocity": _case(
        prp3.forward_velocity,
        {"robot": OBJ, "pose": A, "dlambda10": A},
        robot=ROBOT,
        pose=SMALL,
        dlambda10=ZERO,
    ),
    "inverse_dynamics": _case(
        prp3.inverse_dynamics,
        {"robot": OBJ, "motion": OBJ, "method": C, "engine": "choice?"},
        robot=ROBOT,
        motion=_motion,
        method="fast",
        engine="numpy",
    ),
    "inverse_geometry": _case(
        prp3.inverse_geometry, {"robot": OBJ, **POSE}, robot=ROBOT, pose=SMALL
    ),
    "inverse_kinematics": _case(
        prp3.inverse_kinematics, {"robot": OBJ, "motion": OBJ}, robot=ROBOT, motion=_motion
    ),
    "jacobian": _case(prp3.jacobian, {"robot": OBJ, **POSE}, robot=ROBOT, pose=SMALL),
    "mass_matrix": _case(
        prp3.mass_matrix,
        {"robot": OBJ, **POSE, "space": C},
        robot=ROBOT,
        pose=SMALL,
        space="platform",
    ),
    "bias_forces": _case(
        prp3.bias_forces,
        {"robot": OBJ, **POSE, "velocity": A, "space": C},
        robot=ROBOT,
        pose=SMALL,
        velocity=ZERO,
        space="platform",
    ),
    "gravity_forces": _case(
        prp3.gravity_forces,
        {"robot": OBJ, **POSE, "space": C},
        robot=ROBOT,
        pose=SMALL,
        space="actuator",
    ),
    "jacobian_condition": _case(
        prp3.jacobian_condition, {"robot": OBJ, **POSE}, robot=ROBOT, pose=SMALL
    ),
    "kernel_method": _case(
        prp3.kernel_method,
        {"robot": OBJ, "kin": OBJ, "engine": "choice?"},
        robot=ROBOT,
        kin=_kinematics,
        engine="numba",
    ),
    "law_motion": _case(
        prp3.law_motion,
        {"amplitude": A, "samples": INT, "duration": R},
        amplitude=SMALL,
        samples=5,
        duration=3.0,
    ),
    "newton_euler": _case(
        prp3.newton_euler, {"robot": OBJ, "motion": OBJ}, robot=ROBOT, motion=_motion
    ),
    "orientation_range": _case(prp3.orientation_range, {"robot": OBJ}, robot=LIMITED),
    "orientation_scan": _case(
        prp3.orientation_scan,
        {"robot": OBJ, "x": T, "y": T, "phi": T},
        robot=LIMITED,
        x=np.array([0.0, 0.01]),
        y=np.array([0.0, 0.01]),
        phi=np.array([0.0, 0.1]),
    ),
    "paper_forces": _case(
        prp3.paper_forces,
        {**BATCH, "engine": "choice?"},
        **BATCH_GOOD,
        engine="numpy",
    ),
    "paper_motion": _case(
        prp3.paper_motion,
        {"name": C, "samples": INT},
        names={"name": ("name", "motion")},
        name="vertical",
        samples=5,
    ),
    "platform_dynamics": _case(
        prp3.platform_dynamics,
        {"robot": OBJ, "pose": A, "velocity": A},
        robot=ROBOT,
        pose=SMALL,
        velocity=ZERO,
    ),
    "platform_vertices": _case(
        prp3.platform_vertices, {"robot": OBJ, **POSE}, robot=ROBOT, pose=SMALL
    ),
    "reachable": _case(prp3.reachable, {"robot": OBJ, **POSE}, robot=ROBOT, pose=SMALL),
    "reachable_region": _case(
        prp3.reachable_region, {"robot": OBJ, "phi": R}, robot=LIMITED, phi=0.1
    ),
    "actuator_forces": _case(
        prp3.engines.entries.actuator_forces,
        {**BATCH, "engine": "choice?"},
        **BATCH_GOOD,
        engine="numpy",
    ),
    "sample_forces": _case(prp3.sample_forces, SINGLE, **SINGLE_GOOD),
    "sample_actuator_forces": _case(
        prp3.engines.sample_entries.sample_actuator_forces, SINGLE, **SINGLE_GOOD
    ),
    "workspace_slice": _case(
        prp3.workspace_slice,
        {"robot": OBJ, "phi": R, "x": T, "y": T},
        robot=ROBOT,
        phi=0.1,
        x=np.array([0.0, 0.01]),
        y=np.array([0.0, 0.01]),
    ),
    "workspace_statics": _case(
        prp3.analysis.workspace.workspace_statics,
        {"robot": OBJ, "phi": R, "x": T, "y": T},
        robot=ROBOT,
        phi=0.1,
        x=np.array([0.0, 0.01]),
        y=np.array([0.0, 0.01]),
    ),
    # ---------------------------------------------------------------- submodules
    "solve_batch": _case(
        prp3.engines.entries.solve_batch,
        {**BATCH, "load": "array?", "engine": "choice?"},
        **BATCH_GOOD,
        load=ZERO,
        engine="numba",
    ),
    "open_loop_growth_rate": _case(
        prp3.analysis.equations_of_motion.open_loop_growth_rate,
        {"robot": OBJ, **POSE},
        robot=ROBOT,
        pose=SMALL,
    ),
    "base_vertices": _case(prp3.mechanics.geometry.base_vertices, {"robot": OBJ}, robot=ROBOT),
    "orientation_from_sum": _case(
        prp3.mechanics.geometry.orientation_from_sum,
        {"l0": R, "sum_lambda10": "array*"},
        l0=0.3,
        sum_lambda10=np.array([0.01]),
    ),
    "sum_from_orientation": _case(
        prp3.mechanics.geometry.sum_from_orientation,
        {"l0": R, "phi": "array*"},
        l0=0.3,
        phi=np.array([0.1]),
    ),
    "law_at": _case(
        prp3.model.motion.law_at, {"amplitude": A, "t": T}, amplitude=SMALL, t=np.array([0.0, 1.0])
    ),
    "differentiate_positions": _case(
        prp3.model.motion.differentiate_positions,
        {"t": T, "pose": A},
        t=np.linspace(0.0, 1.0, 8),
        pose=np.zeros((8, 3)),
    ),
    "recursive_matrix_method": _case(
        prp3.references.paper.recursive_matrix_method,
        {"robot": OBJ, "motion": OBJ},
        robot=ROBOT,
        motion=_motion,
    ),
    "paper_inverse_dynamics": _case(
        prp3.references.paper.paper_inverse_dynamics,
        {"robot": OBJ, "motion": OBJ},
        robot=ROBOT,
        motion=_motion,
    ),
    "paper_method": _case(
        prp3.references.paper.paper_method,
        {"robot": OBJ, "motion": OBJ},
        robot=ROBOT,
        motion=_motion,
    ),
    "mjcf_model": _case(prp3.apps.mjcf.mjcf_model, {"robot": OBJ}, robot=ROBOT),
    "unrepresented": _case(prp3.apps.mjcf.unrepresented, {"robot": OBJ}, robot=ROBOT),
    "c_inverse_dynamics": _case(prp3.apps.codegen.c_inverse_dynamics, {"robot": OBJ}, robot=ROBOT),
    "robot_template": _case(prp3.model.robot.robot_template, {"robot": "object?"}, robot=ROBOT),
    "simulate_table": _case(
        prp3.apps.runs.simulate_table,
        {"robot": OBJ, "motion": OBJ, "method": C, "chunk": INT, "engine": "choice?"},
        robot=ROBOT,
        motion=_motion,
        method="fast",
        chunk=4,
        engine="numpy",
    ),
    "summarize": _case(
        prp3.apps.runs.summarize,
        {"table": OBJ},
        table=lambda: prp3.apps.runs.simulate_table(ROBOT, _motion()),
    ),
    "Gains": _case(prp3.apps.control_law.Gains, {"kp": R, "kd": R}, kp=400.0, kd=40.0),
    "control_times": _case(
        prp3.apps.control.control_times,
        {"start": R, "stop": R, "rate": R},
        start=0.0,
        stop=0.1,
        rate=100.0,
    ),
    "hermite_reference": _case(
        prp3.apps.control.hermite_reference,
        {"motion": OBJ, "times": T},
        motion=_motion,
        times=np.array([0.0, 0.5]),
    ),
    "track": _case(
        prp3.apps.control.track,
        {
            "robot": OBJ,
            "reference": OBJ,
            "controller": C,
            "plant": C,
            "model": "object?",
            "gains": "object?",
        },
        robot=ROBOT,
        reference=lambda: prp3.paper_motion("vertical", 3),
        controller="pd",
        plant="prp3",
        model=ROBOT,
        gains=lambda: prp3.apps.control_law.Gains(),
    ),
    "standard_parameters": _case(
        prp3.apps.regressor.standard_parameters,
        {"robot": OBJ, "parameters": N},
        robot=ROBOT,
        parameters=("platform_mass",),
    ),
    "regressor": _case(
        prp3.apps.regressor.regressor,
        {"robot": OBJ, "motion": OBJ, "parameters": N, "chunk_size": INT},
        robot=ROBOT,
        motion=_motion,
        parameters=("platform_mass",),
        chunk_size=64,
    ),
    "weighted_least_squares": _case(
        prp3.apps.identification.weighted_least_squares,
        # W's every shape (N, 3, B) is a regressor: "wrong shape" of the spoilers is a valid one
        {"W": A + "*", "measured": A},
        W=_least_squares_regressor,
        measured=lambda: _least_squares_regressor() @ np.array([1.0, 2.0]) + _noise(),
    ),
    "robot_from_standard": _case(
        prp3.apps.identification.robot_from_standard,
        {"nominal": OBJ, "standard": OBJ},
        names={"standard": ("standard", "parameter")},
        nominal=ROBOT,
        standard=lambda: {"platform_mass": 1.5},
    ),
    "identified_robot": _case(
        prp3.apps.identification.identified_robot,
        {"nominal": OBJ, "result": OBJ},
        nominal=ROBOT,
        result=_identification,
    ),
    "FourierSeries": _case(
        prp3.apps.excitation.FourierSeries,
        {"period": R, "offset": A, "sine": A, "cosine": A},
        period=5.0,
        offset=np.zeros(3),
        sine=lambda: np.full((3, 2), 0.01),
        cosine=lambda: np.zeros((3, 2)),
    ),
    "spring_element": _case(prp3.spring_element, {"kind": C}, kind="sleeve"),
    "evaluate_designs": _case(
        prp3.apps.design_evaluation.evaluate_designs,
        {"evaluator": OBJ, "values": A},
        evaluator=_design_evaluator,
        values=lambda: np.array([[0.3], [0.25]]),
    ),
    "base_parameters": _case(
        prp3.apps.base_parameters.base_parameters,
        {"robot": OBJ, "parameters": N + "?"},  # None: the robot's own parameters
        robot=ROBOT,
        parameters=("platform_mass", "piston_mass"),
    ),
    "family_regressor": _case(
        prp3.family_regressor,
        {"robot": OBJ, "motion": OBJ, "parameters": N},
        robot=_rrr,
        motion=_motion,
        parameters=lambda: prp3.FAMILY_PARAMETERS[:2],
    ),
    "family_standard_parameters": _case(
        prp3.family_standard_parameters,
        {"robot": OBJ, "parameters": N},
        robot=_rrr,
        parameters=lambda: prp3.FAMILY_PARAMETERS[:2],
    ),
    "family_known_forces": _case(
        prp3.family_known_forces, {"robot": OBJ, "motion": OBJ}, robot=_rrr, motion=_motion
    ),
    "family_random_motion": _case(
        prp3.family_random_motion,
        {"robot": OBJ, "samples": INT, "seed": INT},
        robot=_rrr,
        samples=5,
        seed=0,
    ),
    "known_forces": _case(
        prp3.apps.regressor.known_forces,
        {"robot": OBJ, "motion": OBJ, "fixed": "names0"},
        robot=ROBOT,
        motion=_motion,
        fixed=("platform_mass",),
    ),
    "identify": _case(
        prp3.apps.identification.identify,
        {"robot": OBJ, "motion": OBJ, "f10": A, "parameters": N + "?"},  # None: the robot's own
        robot=ROBOT,
        motion=_motion,
        f10=_measured,
        parameters=("platform_mass",),
    ),
    "exciting_trajectory": _case(
        prp3.apps.excitation.exciting_trajectory,
        {"robot": OBJ, "period": R, "harmonics": INT, "reach": R, "samples": INT, "seed": INT},
        robot=ROBOT,
        period=5.0,
        harmonics=2,
        reach=0.1,
        samples=30,
        seed=0,
        max_iterations=2,
    ),
    "design_robot": _case(
        prp3.apps.design.design_robot,
        {"nominal": OBJ, "paths": N, "values": A},
        names={"paths": ("paths", "key", "values")},
        nominal=lambda: {"l0": 0.3},
        paths=("l0",),
        values=np.array([0.25]),
    ),
    "sweep_spec": _case(
        prp3.apps.sweep_spec.sweep_spec,
        {"data": OBJ},
        data=lambda: {"parameters": {"l0": [0.2, 0.4]}, "designs": 2},
    ),
    "pareto_front": _case(
        prp3.apps.design_objective.pareto_front,
        {"x": "array~", "y": "array~"},
        x=np.array([1.0, 2.0]),
        y=np.array([2.0, 1.0]),
    ),
    "Parameter": _case(
        prp3.apps.sweep_spec.Parameter, {"low": R, "high": R}, path="l0", low=0.2, high=0.4
    ),
    "OptimizeSpec": _case(
        prp3.apps.design_objective.OptimizeSpec,
        {"maxiter": INT, "popsize": INT, "tol": R},
        maxiter=30,
        popsize=10,
        tol=0.01,
    ),
    # ---------------------------------------------------------------- the family
    "paper_steps": _case(
        prp3.paper_steps, {"robot": OBJ, "motion": OBJ}, robot=_rrr, motion=_motion
    ),
    "joint_names": _case(prp3.joint_names, {"robot": OBJ}, robot=_rrr),
    # ---------------------------------------------------------------- spatial robots
    "hexapod": _case(
        prp3.hexapod,
        {
            "base_radius": R,
            "platform_radius": R,
            "base_half_angle": R,
            "platform_half_angle": R,
            "home_height": R,
            "stroke": A,
            "u_limit": R,
            "s_limit": R,
            "cylinder": OBJ + "?",
            "rod": OBJ + "?",
            "platform": OBJ + "?",
            "gravity": A,
            "scale": R,
        },
        **_defaults(prp3.hexapod),
    ),
    "three_rps": _case(
        prp3.three_rps,
        {
            "base_radius": R,
            "platform_radius": R,
            "home_height": R,
            "stroke": A,
            "r_limit": R,
            "s_limit": R,
            "cylinder": OBJ + "?",
            "rod": OBJ + "?",
            "platform": OBJ + "?",
            "gravity": A,
            "scale": R,
        },
        **_defaults(prp3.three_rps),
    ),
    "delta": _case(
        prp3.delta,
        {
            "base_radius": R,
            "arm": R,
            "forearm": R,
            "platform_radius": R,
            "home_height": R,
            "r_limit": R,
            "u_limit": R,
            "arm_body": OBJ + "?",
            "forearm_body": OBJ + "?",
            "platform": OBJ + "?",
            "gravity": A,
            "scale": R,
        },
        **_defaults(prp3.delta),
    ),
    "spatial_kinematics": _case(
        prp3.spatial_kinematics, {"robot": OBJ, "motion": OBJ}, robot=_hexapod, motion=_at_home
    ),
    "spatial_inverse_dynamics": _case(
        prp3.spatial_inverse_dynamics,
        {"robot": OBJ, "motion": OBJ, "method": C},
        robot=_hexapod,
        motion=_at_home,
        method="newton-euler",
    ),
    "recursive_newton_euler": _case(
        prp3.recursive_newton_euler, {"robot": OBJ, "motion": OBJ}, robot=_hexapod, motion=_at_home
    ),
    "compile_spatial": _case(prp3.compile_spatial, {"robot": OBJ}, robot=_hexapod),
    "spatial_c_inverse_dynamics": _case(
        prp3.spatial_c_inverse_dynamics, {"robot": OBJ}, robot=_hexapod
    ),
    "spatial_motion": _case(
        prp3.spatial_motion,
        {"robot": OBJ, "name": C, "samples": INT, "duration": R, "times": T + "?"},
        names={"name": ("name", "motion")},  # the command line's --motion
        robot=_hexapod,
        name="heave",
        samples=5,
        duration=1.0,
        times=lambda: [0.0, 0.25],
    ),
    "spatial_robot_from_mapping": _case(
        prp3.spatial_robot_from_mapping,
        {"data": OBJ},
        names={"data": ("data", "mapping", "robot", "architecture")},
        data=lambda: {"architecture": "6-UPS"},
    ),
    "spatial_forward_dynamics": _case(
        prp3.spatial_forward_dynamics,
        {"robot": OBJ, "efforts": A, "duration": R, "samples": INT, "rtol": R, "atol": R},
        robot=_hexapod,
        efforts=lambda: prp3.hold_efforts(prp3.hexapod()),
        duration=0.01,
        samples=2,
        rtol=1e-8,
        atol=1e-10,
    ),
    "spatial_track": _case(
        prp3.spatial_track,
        {
            "robot": OBJ,
            "reference": OBJ,
            "duration": R,
            "kp": R,
            "kd": R,
            "samples": INT,
            "plant": C,
            "timestep": R,
        },
        robot=_hexapod,
        reference=lambda: lambda t: prp3.PlatformMotion.at_rest(prp3.hexapod().home_position),
        duration=0.01,
        kp=100.0,
        kd=20.0,
        samples=2,
        plant="prp3",
        timestep=1e-3,
    ),
    "spatial_pose_error": _case(
        prp3.spatial_pose_error,
        {"reference": OBJ, "actual": OBJ},
        reference=_at_home,
        actual=_at_home,
    ),
    "spatial_platform_dynamics": _case(
        prp3.spatial_platform_dynamics,
        {"robot": OBJ, "motion": OBJ},
        robot=_hexapod,
        motion=_at_home,
    ),
    "hold_efforts": _case(prp3.hold_efforts, {"robot": OBJ}, robot=_hexapod),
    "state_from_joints": _case(
        prp3.state_from_joints,
        {"robot": OBJ, "t": T, "q": A, "dq": A},
        robot=_hexapod,
        t=np.array([0.0]),
        q=lambda: prp3.spatial_kinematics(prp3.hexapod(), _at_home()).q,
        dq=np.zeros((1, 6, 6)),
    ),
    "base_parameters_of": _case(
        prp3.apps.base_parameters.base_parameters_of,
        {"stacked": A},
        stacked=lambda: np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]),
        parameters=("a", "b"),
        forces=("tau",),
    ),
    "spatial_regressor": _case(
        prp3.spatial_regressor, {"robot": OBJ, "motion": OBJ}, robot=_hexapod, motion=_at_home
    ),
    "spatial_standard_parameters": _case(
        prp3.spatial_standard_parameters, {"robot": OBJ}, robot=_hexapod
    ),
    "spatial_parameter_names": _case(prp3.spatial_parameter_names, {"robot": OBJ}, robot=_hexapod),
    "spatial_random_motion": _case(
        prp3.spatial_random_motion,
        {"robot": OBJ, "samples": INT, "seed": INT},
        robot=prp3.three_rps,
        samples=3,
        seed=0,
    ),
    "spatial_base_parameters": _case(
        prp3.spatial_base_parameters,
        {"robot": OBJ, "samples": INT, "seed": INT},
        robot=prp3.three_rps,
        samples=20,
        seed=0,
    ),
    "spatial_identify": _case(
        prp3.spatial_identify,
        {"robot": OBJ, "motion": OBJ, "tau": A},
        robot=prp3.three_rps,
        motion=_rps_motion,
        tau=_rps_efforts,
    ),
    "spatial_identified_robot": _case(
        prp3.spatial_identified_robot,
        {"design": OBJ, "result": OBJ},
        design=lambda: prp3.spatial_robot_from_mapping({"architecture": "3-RPS"}),
        result=_rps_identification,
    ),
    "spatial_exciting_trajectory": _case(
        prp3.spatial_exciting_trajectory,
        {
            "robot": OBJ,
            "period": R,
            "harmonics": INT,
            "samples": INT,
            "reach": R,
            "rotation": R,
            "max_velocity": R + "?",
            "max_force": R + "?",
            "candidates": INT,
            "seed": INT,
        },
        robot=prp3.delta,
        period=5.0,
        harmonics=2,
        samples=40,
        reach=0.2,
        rotation=0.2,
        max_velocity=1.0,
        max_force=100.0,
        candidates=1,
        seed=0,
    ),
    "spatial_workspace": _case(
        prp3.spatial_workspace,
        {
            "robot": OBJ,
            "plane": "choice?",
            "offset": "real?",
            "rpy": "array?",
            "extent": "array?",
            "points": INT,
        },
        robot=_hexapod,
        plane="xy",
        offset=0.08,
        rpy=np.zeros(3),
        extent=np.array([-0.01, 0.01, -0.01, 0.01]),
        points=3,
    ),
    "spatial_planes": _case(prp3.spatial_planes, {"robot": OBJ}, robot=_hexapod),
    "complete_motion": _case(
        prp3.complete_motion, {"robot": OBJ, "motion": OBJ}, robot=_hexapod, motion=_at_home
    ),
    "rpy_motion": _case(
        prp3.rpy_motion,
        {"t": T + "*", "position": A, "rpy": A},
        t=np.array([0.0]),
        position=np.array([[0.0, 0.0, 0.08]]),
        rpy=np.array([[0.0, 0.0, 0.0]]),
    ),
    "quaternion_motion": _case(
        prp3.quaternion_motion,
        {"t": T + "*", "position": A, "quaternion": A},
        t=np.array([0.0]),
        position=np.array([[0.0, 0.0, 0.08]]),
        quaternion=np.array([[1.0, 0.0, 0.0, 0.0]]),
    ),
    "family_kinematics": _case(
        prp3.family_kinematics, {"robot": OBJ, "motion": OBJ}, robot=_rrr, motion=_motion
    ),
    "family_inverse_dynamics": _case(
        prp3.family_inverse_dynamics,
        {"robot": OBJ, "motion": OBJ, "method": C, "engine": C},
        robot=_rrr,
        motion=_motion,
        method="fast",
        engine="numpy",
    ),
    "family_workspace_slice": _case(
        prp3.family_workspace_slice,
        {"robot": OBJ, "phi": R, "x": A, "y": A},
        robot=_rrr,
        phi=0.0,
        x=np.array([0.0, 0.01]),
        y=np.array([0.0, 0.01]),
    ),
    "family_workspace_statics": _case(
        prp3.family_workspace_statics,
        {"robot": OBJ, "phi": R, "x": A, "y": A},
        robot=_rrr,
        phi=0.0,
        x=np.array([0.0, 0.01]),
        y=np.array([0.0, 0.01]),
    ),
    "family_orientation_scan": _case(
        prp3.family_orientation_scan,
        {"robot": OBJ, "x": A, "y": A, "phi": A + "*"},
        robot=_rrr,
        x=np.array([0.0, 0.01]),
        y=np.array([0.0, 0.01]),
        phi=np.array([0.0, 0.1]),
    ),
    "family_forward_dynamics": _case(
        prp3.family_forward_dynamics,
        {"robot": OBJ, "t": T, "initial_pose": A, "initial_velocity": A, "rtol": R, "atol": R},
        robot=_rrr,
        t_efforts=None,
        efforts=lambda: lambda time: np.zeros(3),
        t=np.array([0.0, 0.01]),
        initial_pose=lambda: prp3.FamilyRobot.default("3-RRR").home_poses[0],
        initial_velocity=np.zeros(3),
        rtol=1e-10,
        atol=1e-12,
    ),
}

#: Functions whose good call is too slow for this file (each has its own tests).
SLOW = {"track", "exciting_trajectory", "spatial_track"}

#: Refusals still missing, by (function, argument[, label]): strict xfails, so that
#: the fix makes them fail until the entry goes.
OPEN: dict[str, str] = {}
OPEN_CASES: set[tuple[str, ...]] = set()


def _public() -> dict[str, object]:
    found: dict[str, object] = {}
    for module in (prp3, *(importlib.import_module(name) for name in MODULES)):
        for name in module.__all__:
            value = getattr(module, name)
            if not (inspect.isfunction(value) or inspect.isclass(value)):
                continue  # constants and type aliases
            if value.__module__ in VALIDATION_MODULES:
                continue  # the validation layer itself, re-exported
            found.setdefault(name, value)
    return found


def test_every_public_callable_is_covered() -> None:
    missing = sorted(set(_public()) - set(CASES) - set(EXEMPT))
    assert missing == [], f"public callables without a case or an exemption: {missing}"
    stale = sorted((set(CASES) | set(EXEMPT)) - set(_public()) - {"symbolic_parameters"})
    assert stale == [], f"cases or exemptions of no public callable: {stale}"


def _spoilt() -> Iterator[Any]:
    for name, case in CASES.items():
        for argument, kind in case.kinds.items():
            signature = inspect.signature(case.call)
            assert argument in signature.parameters, (name, argument)
            base, allowed = _kind(kind)
            for label, _ in SPOILERS[base](SAMPLE_GOOD[base]):
                if label in allowed:
                    continue
                marks = (
                    [pytest.mark.xfail(reason=OPEN[name], strict=True)]
                    if ((name, argument, label) in OPEN_CASES or (name, argument) in OPEN_CASES)
                    else []
                )
                yield pytest.param(
                    name, argument, label, id=f"{name}-{argument}-{label}", marks=marks
                )


@pytest.mark.parametrize("name", sorted(n for n in CASES if n not in SLOW))
def test_the_good_arguments_are_accepted(name: str) -> None:
    case = CASES[name]
    case.call(**case.good())


@pytest.mark.parametrize(("name", "argument", "label"), list(_spoilt()))
def test_every_bad_argument_is_refused_naming_it(name: str, argument: str, label: str) -> None:
    case = CASES[name]
    arguments = case.good()
    good = arguments[argument]
    base, _ = _kind(case.kinds[argument])
    bad = dict(SPOILERS[base](np.asarray(good) if base in ("array", "times") else good))
    if label not in bad:
        pytest.skip(f"{label} does not apply to {argument}")
    arguments[argument] = bad[label]
    with pytest.raises(Prp3Error) as info:
        case.call(**arguments)
    message = str(info.value)
    assert "\n" not in message, message
    shown = case.names.get(argument, (argument,))
    assert any(word in message for word in shown), f"{name}({argument}={label}): {message}"


# ------------------------------------------------------------ validation before the engines
#: What runs the kernel on samples: the numpy engine, the numba engine's loops and
#: single-sample calls, the kernel on floats of one sample.
_ENGINE_ENTRIES = (
    ("prp3.engines.entries", "run_numpy"),
    ("prp3.engines.sample_entries", "_sample_floats"),
    *(("prp3.engines.numba", name) for name in (
        "f10_loop", "forces_loop", "reactions_loop", "solve_loop", "f10_loop_parallel",
        "forces_loop_parallel", "reactions_loop_parallel", "solve_loop_parallel", "sample_forces",
        "sample_forces_loaded", "sample_f10", "sample_f10_loaded", "lambda10_sample",
    )),
)  # fmt: skip


@pytest.fixture
def engine_calls(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The names of the engine entries called while the fixture is active."""
    calls: list[str] = []
    for module_name, name in _ENGINE_ENTRIES:
        module = importlib.import_module(module_name)
        original = getattr(module, name)

        def spy(*args: Any, __name: str = name, __original: Any = original, **kwargs: Any) -> Any:
            calls.append(__name)
            return __original(*args, **kwargs)

        monkeypatch.setattr(module, name, spy)
    return calls


def test_the_engine_spies_see_the_engines(engine_calls: list[str]) -> None:
    # the spies are where the entries call: a good call reaches them (else the test
    # below would pass for a function that skips validation)
    zeros = np.zeros((4, 3))
    prp3.paper_forces(ROBOT, zeros, zeros, zeros, engine="numba")
    prp3.paper_forces(ROBOT, zeros, zeros, zeros, engine="numpy")
    prp3.sample_forces(_compiled(), ZERO, ZERO, ZERO, engine="numpy")
    prp3.sample_forces(_compiled(), ZERO, ZERO, ZERO, engine="numba")
    assert engine_calls == ["forces_loop", "run_numpy", "_sample_floats", "sample_forces"]


@pytest.mark.parametrize(("name", "argument", "label"), list(_spoilt()))
def test_no_engine_sees_a_bad_argument(
    name: str, argument: str, label: str, engine_calls: list[str]
) -> None:
    # A public function validates all its arguments before any engine runs on samples:
    # a function that skipped validation (and let a result check catch the damage, or
    # not) fails here.  Functions that run the kernel on validated samples of their own
    # before they read a later argument would also show; none does.
    case = CASES[name]
    arguments = case.good()
    good = arguments[argument]
    base, _ = _kind(case.kinds[argument])
    bad = dict(SPOILERS[base](np.asarray(good) if base in ("array", "times") else good))
    if label not in bad:
        pytest.skip(f"{label} does not apply to {argument}")
    engine_calls.clear()  # the good arguments may have run an engine (a kinematics, ...)
    arguments[argument] = bad[label]
    with pytest.raises(Prp3Error):
        case.call(**arguments)
    assert engine_calls == [], f"{name}({argument}={label}) ran {engine_calls} before refusing"


def test_one_acceleration_bound_for_every_forward_dynamics() -> None:
    """``prp3.MAX_ACCELERATION`` is the bound the 3-PRP, family and spatial runs refuse beyond."""
    from prp3.family import forward as family
    from prp3.spatial import forward as spatial

    assert prp3.MAX_ACCELERATION == family.MAX_ACCELERATION == spatial.MAX_ACCELERATION == 1e6
    robot = prp3.FamilyRobot.from_mapping({"architecture": "3-RRR", "load": {"force": [2e12, 0]}})
    words = r"load.force = \[2000000000000.0, 0.0\] alone .* beyond the bound 1e\+06"
    with pytest.raises(prp3.ParameterError, match=words):
        prp3.family_forward_dynamics(robot, [0.0, 1.0], np.zeros((2, 3)), [0.0, 0.5],
                                     robot.home_poses[0], np.zeros(3))  # fmt: skip
