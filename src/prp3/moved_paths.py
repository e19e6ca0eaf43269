"""The module paths of prp3 0.1 and where their names live now (deprecated, removed in 0.3).

prp3 0.2 gathered its public names at ``prp3.<name>`` and moved the modules behind
them into packages (``prp3.model``, ``prp3.mechanics``, ``prp3.engines``, …).  Code
written against 0.1 keeps working for this release: importing ``prp3.fast``,
``prp3.kernel``, … gives a stand-in module, and every name taken from it (or from a
0.1 module that is now a package, such as ``prp3.model``) is the object of today,
with a :class:`DeprecationWarning` naming where to take it from instead.

>>> import warnings
>>> import prp3
>>> with warnings.catch_warnings(record=True) as caught:
...     warnings.simplefilter("always")
...     from prp3.fast import paper_forces
>>> paper_forces is prp3.paper_forces
True
>>> print(caught[0].message)
prp3.fast.paper_forces is deprecated since prp3 0.2.0 and goes in 0.3.0: use prp3.paper_forces
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import types
import warnings

__all__ = ["MOVED", "REMOVED_IN", "install", "moved_attribute", "new_location"]

#: The release that removes the 0.1 paths.
REMOVED_IN = "0.3.0"

#: 0.1 module -> {module holding the names now: the names}; ``"prp3"`` is the public
#: namespace (``prp3.<name>``), any other module is internal.
MOVED: dict[str, dict[str, str]] = {
    "prp3._trace": {
        "prp3.engines.trace": "TRACE Traced array_function broadcast_function trace",
    },
    "prp3.codegen": {
        "prp3": "CSource c_inverse_dynamics",
        "prp3.apps.codegen": "C_NOT_FINITE C_OK C_OUTSIDE_STROKE C_SINGULAR HEADER_NAME SOURCE_NAME",
    },
    "prp3.control": {
        "prp3": "AxisGains CONTROLLERS Controller Gains PLANTS Plant Tracking check_model check_plant control_force hermite_reference law_at track",
        "prp3.apps.control": "DEFAULT_RATE LOAD_REFUSAL MAX_STEPS control_times",
        "prp3.apps.control_law": "DEFAULT_KD DEFAULT_KP",
        "prp3.apps.plants": "PLANT_ATOL PLANT_RTOL",
    },
    "prp3.design": {
        "prp3": "DesignEvaluator DesignObjective OptimizeSpec Parameter SweepSpec design_columns design_robot evaluate_designs pareto_front read_sweep_spec sweep_spec",
        "prp3.apps.design": "AGGREGATES design_mapping nominal_value",
        "prp3.apps.design_evaluation": "STATUSES",
        "prp3.apps.design_objective": "INFEASIBLE penalized_objective quantity",
        "prp3.apps.sweep_spec": "CHUNK_DESIGNS MAX_DESIGNS SAMPLINGS design_values",
    },
    "prp3.dynamics": {
        "prp3": "InverseDynamics METHODS inverse_dynamics kernel_method newton_euler",
    },
    "prp3.elements": {
        "prp3": "ELEMENTS Element FrictionElement GravityElement LoadElement PayloadElement SpringElement WrenchElement",
        "prp3.model.element_base": "State is_zero number_text rate_sign",
        "prp3.model.elements": "FRICTIONS GRAVITY LOAD PAYLOAD SPRING WRENCH effect_fields",
    },
    "prp3.engines": {
        "prp3": "ENGINES EngineWarning default_engine resolve_engine",
        "prp3.engines.select": "CHUNK numba_module run_numpy runs_on",
    },
    "prp3.explorer.app": {
        "prp3": "serve write_run_html",
        "prp3.explorer.html_file": "run_html",
        "prp3.explorer.scrubber": "MAX_HTML_FRAMES",
        "prp3.explorer.server": "DEFAULT_HOST DEFAULT_PORT",
    },
    "prp3.explorer.page": {
        "prp3.explorer.scrubber": "MAX_CURVE_POINTS MAX_HTML_FRAMES",
    },
    "prp3.explorer.scene": {
        "prp3": "Run read_run",
        "prp3.explorer.run_folder": "run_motion",
    },
    "prp3.fast": {
        "prp3": "CompiledRobot ENGINES FastForces SampleForces actuator_forces compile_robot paper_forces sample_actuator_forces sample_forces solve_batch",
        "prp3.engines.entries": "DEFAULT_CHUNK FRICTION_OUTPUTS KERNEL_OUTPUTS MAX_CHUNK",
        "prp3.engines.sample_entries": "sample_forces_unchecked",
    },
    "prp3.files": {
        "prp3": "StagedOutput read_manifest staged_output",
        "prp3.staged_files": "LIBRARY_COMMAND MANIFEST_NAME file_digest read_manifest_commands",
    },
    "prp3.forces": {
        "prp3": "InverseDynamics",
        "prp3.mechanics.forces": "FORCE_NAMES FRICTION_NAMES checked",
    },
    "prp3.forward": {
        "prp3": "ActuatorForces ForwardDynamics ForwardGeometry bias_forces forward_acceleration forward_dynamics forward_geometry forward_kinematics forward_velocity gravity_forces mass_matrix platform_dynamics",
        "prp3.analysis.equations_of_motion": "PlatformDynamics SPACES check_forward_friction open_loop_growth_rate",
        "prp3.analysis.forward": "MIN_RTOL SINGULARITY_STOP",
        "prp3.mechanics.geometry": "DEGENERATE_ASSEMBLY orientation_from_sum sum_from_orientation",
    },
    "prp3.geometry": {
        "prp3": "ForwardGeometry InverseGeometry LEGS check_poses forward_geometry inverse_geometry platform_vertices singularity_measure",
        "prp3.mechanics.geometry": "ALPHA DEGENERATE_ASSEMBLY LEG_AXIS LEG_NORMAL base_vertices check_stroke cross2 dot2 orientation_from_sum perp sum_from_orientation",
        "prp3.pose_validation": "SINGULARITY_THRESHOLD",
    },
    "prp3.identification": {
        "prp3": "BaseParameters ExcitingTrajectory FourierSeries Identification IdentifiedRobot Regressor STANDARD_PARAMETERS base_parameters exciting_trajectory identified_robot identify known_forces regressor robot_from_standard standard_parameters weighted_least_squares",
        "prp3.apps.identification": "FRICTION_MODELS MIN_SAMPLES_PER_PARAMETER",
        "prp3.apps.regressor": "ELEMENT_PARAMETERS FORCES FRICTION_PARAMETERS PARAMETERS PARAMETER_SYMBOLS PARAMETER_UNITS",
    },
    "prp3.io": {
        "prp3": "ForceInput Measurements StagedOutput TRAJECTORY_COLUMNS Trajectory differentiate_positions read_forces read_manifest read_measurements read_table_csv read_trajectory staged_output trajectory_table write_table_csv write_table_parquet",
        "prp3.files": "atomic_path atomic_writer check_inputs_kept check_output_directory",
        "prp3.io.forces": "FORCE_COLUMNS",
        "prp3.io.measurements": "MEASURED_FORCE_COLUMNS",
        "prp3.io.tables": "format_float format_floats parquet_available",
        "prp3.io.trajectory": "DERIVATIVE_COLUMNS LOAD_COLUMNS POSITION_COLUMNS",
        "prp3.staged_files": "MANIFEST_NAME",
    },
    "prp3.kernel": {
        "prp3": "KernelSolution Ops symbolic_solution sympy_ops",
        "prp3.mechanics.implicit_friction": "MU_STEPS NEAR_LOCK_MU solve_mu",
        "prp3.mechanics.joint_motion": "KernelGeometry KernelKinematics PI_3 kernel_geometry kernel_kinematics",
        "prp3.mechanics.kernel": "STATE_SYMBOLS dynamics solve",
        "prp3.mechanics.ops": "MATH NUMPY",
        "prp3.mechanics.parameters": "EFFECT_FIELDS INERTIAL_FIELDS KernelParameters kernel_parameters symbolic_parameters",
        "prp3.mechanics.virtual_work": "joint_forces",
        "prp3.mechanics.wrenches": "BodyWrenches KernelFriction body_wrenches friction_forces",
    },
    "prp3.kinematics": {
        "prp3": "Kinematics inverse_kinematics jacobian",
    },
    "prp3.mjcf": {
        "prp3": "MjcfWarning mjcf_model",
        "prp3.apps.mjcf": "INERTIA_FLOOR MIN_L0 MUJOCO_MIN_VALUE TIMESTEP WELD_SOLIMP WELD_SOLREF unrepresented",
    },
    "prp3.model": {
        "prp3": "Friction JointFriction Limits LinkParameters Load Payload PistonParameters PlatformParameters Robot Spring SpringParameters check_robot robot_template",
    },
    "prp3.motion": {
        "prp3": "Motion PAPER_MOTIONS differentiate_positions law_at law_motion paper_motion",
        "prp3.model.motion": "MAX_SAMPLES PAPER_DURATION",
    },
    "prp3.newton_euler_solver": {
        "prp3": "newton_euler",
        "prp3.references.newton_euler": "NEWTON_EULER_CHUNK",
    },
    "prp3.numba_engine": {
        "prp3": "sample_forces",
        "prp3.engines.numba": "f10_loop forces_loop lambda10_sample reactions_loop sample_f10 sample_f10_loaded sample_forces_loaded solve_loop",
    },
    "prp3.paper": {
        "prp3": "RecursiveMatrixResult paper_method recursive_matrix_method",
        "prp3.references.paper": "FORCE_SETS MAX_RECORDED_SAMPLES PAPER_CHUNK paper_inverse_dynamics",
    },
    "prp3.paper_kinematics": {
        "prp3.references.paper_kinematics": "A10 A30_CIRCLE A32 FixedFrameKinematics PaperAccelerations PaperGeometry PaperVelocities R00 THETA_1 THETA_2 U1 U2 U3 U3_TILDE VIRTUAL_SETS VirtualVelocities fixed_frame_kinematics orientation_condition paper_accelerations paper_geometry paper_velocities platform_centre rot skew theta_alpha vee virtual_velocities",
    },
    "prp3.paper_wrenches": {
        "prp3.references.paper_wrenches": "body_constants chain_wrenches inertia_wrenches other_reactions virtual_work weight_wrenches",
    },
    "prp3.results": {
        "prp3": "OUTPUT_QUANTITIES RESULT_COLUMNS result_columns results_table",
        "prp3.io.results": "FRICTION_COLUMNS LOAD_RESULT_COLUMNS OutputQuantity PER_LEG_COLUMNS output_quantity",
    },
    "prp3.runs": {
        "prp3": "RunSummary check_memory simulate_table summarize",
        "prp3.apps.runs": "CHUNK_SAMPLES available_memory summary_text",
    },
    "prp3.sweep": {
        "prp3": "OptimizeOutcome SweepRun dask_client optimize_design read_designs run_sweep",
        "prp3.apps.cluster": "CONNECT_TIMEOUT ClientOrFactory",
        "prp3.apps.optimization": "DaskMap",
        "prp3.apps.sweep": "DESIGNS_FILE DesignTable check_sweep_folder staging_folder stale_staging_folders sweep_of",
    },
    "prp3.validation": {
        "prp3": "check_path check_poses singularity_measure",
        "prp3.path_validation": "RATE_TOLERANCE STEP_TOLERANCE rest_joint_rates rest_rates",
        "prp3.pose_validation": "MAX_ORIENTATION POSE_BOUND SINGULARITY_THRESHOLD check_pose_array check_pose_sample check_sample check_state_sample",
    },
    "prp3.workspace": {
        "prp3": "OrientationScan WorkspaceSlice WorkspaceStatics jacobian_condition orientation_range orientation_scan reachable reachable_region workspace_slice workspace_statics",
        "prp3.analysis.reachability": "SINGULAR_ORIENTATIONS",
    },
}

_HOMES: dict[str, dict[str, str]] = {
    old: {name: home for home, names in homes.items() for name in names.split()}
    for old, homes in MOVED.items()
}


def new_location(old_module: str, name: str) -> str | None:
    """Where ``old_module.name`` of prp3 0.1 lives now (``"prp3.x"`` or a module path), or None.

    >>> new_location("prp3.kernel", "Ops"), new_location("prp3.kernel", "PI_3")
    ('prp3.Ops', 'prp3.mechanics.joint_motion.PI_3')
    """
    home = _HOMES.get(old_module, {}).get(name)
    return None if home is None else f"{home}.{name}"


def moved_attribute(old_module: str, name: str) -> object:
    """The object ``old_module.name`` of prp3 0.1 is now, with a DeprecationWarning naming it.

    A module of today that had other names in 0.1 forwards its ``__getattr__`` here.

    Raises
    ------
    AttributeError
        When ``name`` was not a name of ``old_module`` in 0.1 either.
    """
    home = _HOMES.get(old_module, {}).get(name)
    if home is None:
        raise AttributeError(f"module {old_module!r} has no attribute {name!r}")
    where = f"{home}.{name}"
    advice = (
        f"use {where}"
        if home == "prp3"
        else f"it is internal now, at {where} (not part of the public API)"
    )
    warnings.warn(
        f"{old_module}.{name} is deprecated since prp3 0.2.0 and goes in {REMOVED_IN}: {advice}",
        DeprecationWarning,
        stacklevel=3,
    )
    return getattr(importlib.import_module(home), name)


class _MovedModules(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds and makes the stand-in of each 0.1 module that no longer exists."""

    def find_spec(
        self, fullname: str, path: object = None, target: object = None
    ) -> importlib.machinery.ModuleSpec | None:
        # after the path finders on sys.meta_path: asked only for a module that does not exist
        if fullname not in MOVED:
            return None
        return importlib.machinery.ModuleSpec(fullname, self)

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> types.ModuleType:
        module = types.ModuleType(spec.name, f"Deprecated 0.1 path of prp3 ({spec.name}).")

        def forward(name: str) -> object:
            return moved_attribute(spec.name, name)

        module.__getattr__ = forward  # type: ignore[method-assign]
        module.__all__ = sorted(_HOMES[spec.name])  # type: ignore[attr-defined]
        return module

    def exec_module(self, module: types.ModuleType) -> None:
        return None


_FINDER = _MovedModules()


def install() -> None:
    """Put the finder of the 0.1 paths on :data:`sys.meta_path` (once; ``import prp3`` does)."""
    if _FINDER not in sys.meta_path:
        sys.meta_path.append(_FINDER)
