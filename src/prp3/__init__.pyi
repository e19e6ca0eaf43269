"""Type stub of :mod:`prp3`: every public name and the module it is loaded from (lazily, by
:func:`lazy_loader.attach_stub`: ``import prp3`` loads a name on first use)."""

# ruff: noqa: I001  (re-exports as `name as name`, PEP 484; one block per module)

__version__: str

from .analysis.equations_of_motion import (
    open_loop_growth_rate as open_loop_growth_rate,
    bias_forces as bias_forces,
    gravity_forces as gravity_forces,
    mass_matrix as mass_matrix,
    platform_dynamics as platform_dynamics,
)
from .analysis.force_histories import (
    ActuatorForces as ActuatorForces,
)
from .analysis.forward import (
    MAX_ACCELERATION as MAX_ACCELERATION,
    MAX_EVALUATIONS as MAX_EVALUATIONS,
    MAX_SECONDS as MAX_SECONDS,
    ForwardDynamics as ForwardDynamics,
    forward_dynamics as forward_dynamics,
)
from .analysis.forward_kinematics import (
    forward_acceleration as forward_acceleration,
    forward_kinematics as forward_kinematics,
    forward_velocity as forward_velocity,
)
from .analysis.inverse_dynamics import (
    METHODS as METHODS,
    inverse_dynamics as inverse_dynamics,
    kernel_method as kernel_method,
)
from .analysis.reachability import (
    jacobian_condition as jacobian_condition,
    orientation_range as orientation_range,
    reachable as reachable,
    reachable_region as reachable_region,
)
from .analysis.workspace import (
    OrientationScan as OrientationScan,
    WorkspaceSlice as WorkspaceSlice,
    WorkspaceStatics as WorkspaceStatics,
    orientation_scan as orientation_scan,
    workspace_slice as workspace_slice,
    workspace_statics as workspace_statics,
)
from .apps.base_parameters import (
    BaseParameters as BaseParameters,
    base_parameters as base_parameters,
)
from .apps.cluster import (
    dask_client as dask_client,
)
from .apps.codegen import (
    RETURN_CODES as RETURN_CODES,
    CSource as CSource,
    c_inverse_dynamics as c_inverse_dynamics,
)
from .apps.control import (
    control_times as control_times,
    Tracking as Tracking,
    check_model as check_model,
    hermite_reference as hermite_reference,
    track as track,
)
from .apps.control_law import (
    CONTROLLERS as CONTROLLERS,
    AxisGains as AxisGains,
    Controller as Controller,
    Gains as Gains,
    control_force as control_force,
)
from .apps.design import (
    DesignEvaluator as DesignEvaluator,
    design_columns as design_columns,
    design_robot as design_robot,
)
from .apps.design_evaluation import (
    evaluate_designs as evaluate_designs,
)
from .apps.design_objective import (
    DesignObjective as DesignObjective,
    OptimizeSpec as OptimizeSpec,
    pareto_front as pareto_front,
)
from .apps.excitation import (
    ExcitingTrajectory as ExcitingTrajectory,
    FourierSeries as FourierSeries,
    exciting_trajectory as exciting_trajectory,
)
from .apps.identification import (
    Identification as Identification,
    IdentifiedRobot as IdentifiedRobot,
    identified_robot as identified_robot,
    identify as identify,
    robot_from_standard as robot_from_standard,
    weighted_least_squares as weighted_least_squares,
)
from .apps.mjcf import (
    MjcfWarning as MjcfWarning,
    mjcf_model as mjcf_model,
)
from .apps.spatial_mjcf import (
    read_spatial_mjcf as read_spatial_mjcf,
    spatial_mjcf_model as spatial_mjcf_model,
    spatial_mjcf_robot as spatial_mjcf_robot,
)
from .apps.spatial_urdf import (
    read_spatial_urdf as read_spatial_urdf,
    spatial_urdf_closures as spatial_urdf_closures,
    spatial_urdf_model as spatial_urdf_model,
    spatial_urdf_robot as spatial_urdf_robot,
)
from .apps.optimization import (
    OptimizeOutcome as OptimizeOutcome,
    optimize_design as optimize_design,
)
from .apps.plants import (
    PLANTS as PLANTS,
    Plant as Plant,
    check_plant as check_plant,
)
from .apps.family_regressor import (
    FAMILY_PARAMETERS as FAMILY_PARAMETERS,
    FAMILY_PARAMETER_SYMBOLS as FAMILY_PARAMETER_SYMBOLS,
    FAMILY_PARAMETER_UNITS as FAMILY_PARAMETER_UNITS,
    FamilyRegressor as FamilyRegressor,
    family_known_forces as family_known_forces,
    family_random_motion as family_random_motion,
    family_regressor as family_regressor,
    family_standard_parameters as family_standard_parameters,
)
from .apps.regressor import (
    STANDARD_PARAMETERS as STANDARD_PARAMETERS,
    Regressor as Regressor,
    known_forces as known_forces,
    regressor as regressor,
    standard_parameters as standard_parameters,
)
from .apps.runs import (
    RunSummary as RunSummary,
    check_memory as check_memory,
    simulate_table as simulate_table,
    summarize as summarize,
)
from .apps.sweep import (
    SweepRun as SweepRun,
    read_designs as read_designs,
    run_sweep as run_sweep,
)
from .apps.sweep_spec import (
    design_values as design_values,
    Parameter as Parameter,
    SweepSpec as SweepSpec,
    read_sweep_spec as read_sweep_spec,
    sweep_spec as sweep_spec,
)
from .engines.compiled_robot import (
    CompiledRobot as CompiledRobot,
    compile_robot as compile_robot,
)
from .engines.entries import (
    FastForces as FastForces,
    actuator_forces as actuator_forces,
    paper_forces as paper_forces,
    solve_batch as solve_batch,
)
from .engines.sample_entries import (
    SampleForces as SampleForces,
    sample_actuator_forces as sample_actuator_forces,
    sample_forces as sample_forces,
)
from .engines.select import (
    ENGINES as ENGINES,
    EngineWarning as EngineWarning,
    default_engine as default_engine,
    resolve_engine as resolve_engine,
)
from .errors import (
    InputFileError as InputFileError,
    OutputFileError as OutputFileError,
    ParameterError as ParameterError,
    Prp3Error as Prp3Error,
    SingularPoseError as SingularPoseError,
    TrajectoryError as TrajectoryError,
    UnreachablePoseError as UnreachablePoseError,
)
from .explorer.html_file import (
    write_run_html as write_run_html,
)
from .explorer.run_folder import (
    Run as Run,
    read_run as read_run,
)
from .explorer.server import (
    serve as serve,
)
from .family.chain import (
    leg_chain as leg_chain,
    leg_jacobian as leg_jacobian,
    leg_measure as leg_measure,
    parallel_measure as parallel_measure,
    transmitted_wrench as transmitted_wrench,
)
from .family.codegen import (
    python_sample as python_sample,
    FamilyCSource as FamilyCSource,
    family_c_inverse_dynamics as family_c_inverse_dynamics,
)
from .apps.spatial_codegen import (
    SpatialCSource as SpatialCSource,
    spatial_c_inverse_dynamics as spatial_c_inverse_dynamics,
)
from .apps.spatial_design import (
    SpatialSweepSpec as SpatialSweepSpec,
    optimize_spatial as optimize_spatial,
    read_spatial_sweep_spec as read_spatial_sweep_spec,
    spatial_sweep_spec as spatial_sweep_spec,
)
from .family.design import (
    FamilySweepSpec as FamilySweepSpec,
    evaluate_family_designs as evaluate_family_designs,
    family_design_robot as family_design_robot,
    family_sweep_spec as family_sweep_spec,
    optimize_family as optimize_family,
    read_family_sweep_spec as read_family_sweep_spec,
    run_family_sweep as run_family_sweep,
)
from .family.forward import (
    FamilyEffortModel as FamilyEffortModel,
    FamilyForward as FamilyForward,
    family_energy as family_energy,
    family_forward_dynamics as family_forward_dynamics,
    singularity_margin as singularity_margin,
)
from .family.mechanics import (
    MAX_TURN as MAX_TURN,
    MAX_MOVE as MAX_MOVE,
    FamilyKinematics as FamilyKinematics,
    FamilySolution as FamilySolution,
    family_kinematics as family_kinematics,
)
from .family.mjcf import (
    joint_names as joint_names,
    family_mjcf_model as family_mjcf_model,
)
from .family.model import (
    ARCHITECTURES as ARCHITECTURES,
    Body as Body,
    FamilyRobot as FamilyRobot,
    LegDesign as LegDesign,
    PlatformBody as PlatformBody,
    family_template as family_template,
    read_robot_file as read_robot_file,
    robot_file_form as robot_file_form,
)
from .family.newton_euler import (
    newton_euler_dynamics as newton_euler_dynamics,
)
from .family.outputs import (
    FAMILY_COLUMNS as FAMILY_COLUMNS,
    FAMILY_ENGINES as FAMILY_ENGINES,
    FAMILY_METHODS as FAMILY_METHODS,
    family_inverse_dynamics as family_inverse_dynamics,
    family_results_table as family_results_table,
)
from .family.workspace import (
    FamilyOrientationScan as FamilyOrientationScan,
    FamilyStatics as FamilyStatics,
    FamilyWorkspace as FamilyWorkspace,
    family_orientation_scan as family_orientation_scan,
    family_workspace_slice as family_workspace_slice,
    family_workspace_statics as family_workspace_statics,
)
from .io.forces import (
    ForceInput as ForceInput,
    read_forces as read_forces,
)
from .io.measurements import (
    Measurements as Measurements,
    read_measurements as read_measurements,
)
from .io.results import (
    OUTPUT_QUANTITIES as OUTPUT_QUANTITIES,
    RESULT_COLUMNS as RESULT_COLUMNS,
    result_columns as result_columns,
    results_table as results_table,
)
from .io.spatial_robot import (
    SPATIAL_ARCHITECTURES as SPATIAL_ARCHITECTURES,
    SpatialRobotFile as SpatialRobotFile,
    read_spatial_robot as read_spatial_robot,
    spatial_robot_from_mapping as spatial_robot_from_mapping,
)
from .io.spatial_trajectory import (
    SpatialTrajectory as SpatialTrajectory,
    read_spatial_trajectory as read_spatial_trajectory,
)
from .io.tables import (
    read_table as read_table,
    read_table_csv as read_table_csv,
    write_table_csv as write_table_csv,
    write_table_parquet as write_table_parquet,
)
from .io.trajectory import (
    TRAJECTORY_COLUMNS as TRAJECTORY_COLUMNS,
    Trajectory as Trajectory,
    read_trajectory as read_trajectory,
    trajectory_table as trajectory_table,
)
from .mechanics.forces import (
    InverseDynamics as InverseDynamics,
)
from .mechanics.geometry import (
    ForwardGeometry as ForwardGeometry,
    InverseGeometry as InverseGeometry,
    forward_geometry as forward_geometry,
    inverse_geometry as inverse_geometry,
    platform_vertices as platform_vertices,
)
from .mechanics.kernel import (
    KernelSolution as KernelSolution,
    symbolic_solution as symbolic_solution,
)
from .mechanics.kinematics import (
    Kinematics as Kinematics,
    inverse_kinematics as inverse_kinematics,
    jacobian as jacobian,
)
from .mechanics.ops import (
    Ops as Ops,
    sympy_ops as sympy_ops,
)
from .model.body_elements import (
    GravityElement as GravityElement,
    LoadElement as LoadElement,
    PayloadElement as PayloadElement,
    WrenchElement as WrenchElement,
)
from .model.element_base import (
    Element as Element,
)
from .model.elements import (
    ELEMENTS as ELEMENTS,
)
from .model.joint_elements import (
    SMOOTHING_FLOOR as SMOOTHING_FLOOR,
    FrictionElement as FrictionElement,
    SpringElement as SpringElement,
    spring_element as spring_element,
    spring_force as spring_force,
)
from .model.motion import (
    PAPER_DURATION as PAPER_DURATION,
    PAPER_MOTIONS as PAPER_MOTIONS,
    Motion as Motion,
    differentiate_positions as differentiate_positions,
    law_at as law_at,
    law_motion as law_motion,
    paper_motion as paper_motion,
)
from .model.parameters import (
    Friction as Friction,
    JointFriction as JointFriction,
    Limits as Limits,
    LinkParameters as LinkParameters,
    Load as Load,
    Payload as Payload,
    PistonParameters as PistonParameters,
    PlatformParameters as PlatformParameters,
    Spring as Spring,
    SpringParameters as SpringParameters,
)
from .model.robot import (
    Robot as Robot,
    robot_template as robot_template,
)
from .path_validation import (
    check_path as check_path,
)
from .pose_validation import (
    check_poses as check_poses,
    singularity_measure as singularity_measure,
)
from .references.newton_euler import (
    newton_euler as newton_euler,
)
from .references.paper import (
    RecursiveMatrixResult as RecursiveMatrixResult,
    paper_method as paper_method,
    recursive_matrix_method as recursive_matrix_method,
)
from .staged_files import (
    StagedOutput as StagedOutput,
    read_manifest as read_manifest,
    staged_output as staged_output,
)
from .validation import (
    LEGS as LEGS,
    check_robot as check_robot,
)
from .family.paper import (
    paper_steps as paper_steps,
)
from .spatial.model import (
    three_rps as three_rps,
    hexapod as hexapod,
    delta as delta,
    SpatialRobot as SpatialRobot,
    Leg as Leg,
    Joint as Joint,
    JOINT_KINDS as JOINT_KINDS,
)
from .spatial.motion import (
    SPATIAL_MOTIONS as SPATIAL_MOTIONS,
    spatial_motion as spatial_motion,
    rpy_motion as rpy_motion,
    quaternion_motion as quaternion_motion,
    PlatformMotion as PlatformMotion,
)
from .spatial.kinematics import (
    complete_motion as complete_motion,
    spatial_kinematics as spatial_kinematics,
    SpatialKinematics as SpatialKinematics,
)
from .spatial.forward import (
    spatial_forward_dynamics as spatial_forward_dynamics,
    spatial_platform_dynamics as spatial_platform_dynamics,
    hold_efforts as hold_efforts,
    state_from_joints as state_from_joints,
    SpatialForward as SpatialForward,
    SpatialPlatformDynamics as SpatialPlatformDynamics,
)
from .io.spatial_efforts import (
    read_spatial_efforts as read_spatial_efforts,
    SpatialEfforts as SpatialEfforts,
)
from .spatial.workspace import (
    spatial_workspace as spatial_workspace,
    spatial_planes as spatial_planes,
    spatial_workspace_table as spatial_workspace_table,
    spatial_statics_table as spatial_statics_table,
    SpatialWorkspace as SpatialWorkspace,
    SPATIAL_PLANES as SPATIAL_PLANES,
    WORKSPACE_REASONS as WORKSPACE_REASONS,
)
from .spatial.outputs import (
    spatial_results_table as spatial_results_table,
    spatial_inverse_dynamics as spatial_inverse_dynamics,
    SpatialSolution as SpatialSolution,
    SPATIAL_METHODS as SPATIAL_METHODS,
)
from .spatial.newton_euler import (
    recursive_newton_euler as recursive_newton_euler,
    JointWrenches as JointWrenches,
)
from .spatial.compiled import (
    compile_spatial as compile_spatial,
    CompiledSpatial as CompiledSpatial,
    SpatialSample as SpatialSample,
    SpatialSamples as SpatialSamples,
    SPATIAL_STATUS as SPATIAL_STATUS,
)
from .apps.spatial_identification import (
    BODY_PARAMETERS as BODY_PARAMETERS,
    SpatialExcitation as SpatialExcitation,
    SpatialRegressor as SpatialRegressor,
    spatial_base_parameters as spatial_base_parameters,
    spatial_exciting_trajectory as spatial_exciting_trajectory,
    spatial_identified_robot as spatial_identified_robot,
    spatial_identify as spatial_identify,
    spatial_parameter_names as spatial_parameter_names,
    spatial_random_motion as spatial_random_motion,
    spatial_regressor as spatial_regressor,
    spatial_standard_parameters as spatial_standard_parameters,
)
from .io.spatial_trajectory import (
    SpatialMeasurements as SpatialMeasurements,
    read_spatial_measurements as read_spatial_measurements,
)
from .apps.spatial_control import (
    SpatialTracking as SpatialTracking,
    spatial_pose_error as spatial_pose_error,
    spatial_track as spatial_track,
)
