"""Type stub of :mod:`prp3.plotting`: every public figure function and the module it is loaded
from (lazily, by :func:`lazy_loader.attach_stub`: matplotlib is imported only when drawing)."""

# ruff: noqa: I001  (re-exports as `name as name`, PEP 484; one block per module)

from .animation import (
    MechanismFrame as MechanismFrame,
    draw_frame as draw_frame,
    frame_indices as frame_indices,
    frame_schedule as frame_schedule,
    mechanism_figure as mechanism_figure,
    mechanism_frame as mechanism_frame,
    save_animation as save_animation,
)
from .control import (
    tracking_figure as tracking_figure,
)
from .design import (
    pareto_figure as pareto_figure,
    sensitivity_figure as sensitivity_figure,
)
from .family import (
    designs_figure as designs_figure,
    family_figure_names as family_figure_names,
    family_figures as family_figures,
    joint_forces_figure as joint_forces_figure,
)
from .family_animation import (
    FamilyFrame as FamilyFrame,
    family_frame as family_frame,
    save_family_animation as save_family_animation,
)
from .family_design import (
    comparison_figure as comparison_figure,
    family_designs_figure as family_designs_figure,
)
from .family_workspace import (
    family_statics_figure as family_statics_figure,
    family_workspace_figure as family_workspace_figure,
    save_family_statics_map as save_family_statics_map,
    save_family_workspace_map as save_family_workspace_map,
)
from .figures import (
    figure_names as figure_names,
    friction_figure as friction_figure,
    leg_figure as leg_figure,
    results_figures as results_figures,
    save_figure as save_figure,
    save_figures as save_figures,
)
from .identification import (
    identification_figure as identification_figure,
)
from .spatial import (
    joint_reactions_figure as joint_reactions_figure,
    platform_motion_figure as platform_motion_figure,
    spatial_efforts_figure as spatial_efforts_figure,
    spatial_figure_names as spatial_figure_names,
    spatial_figures as spatial_figures,
)
from .spatial_animation import (
    SpatialFrame as SpatialFrame,
    force_scale as force_scale,
    robot_size as robot_size,
    save_spatial_animation as save_spatial_animation,
    spatial_frame as spatial_frame,
    spatial_pose_figure as spatial_pose_figure,
    spatial_robot_figure as spatial_robot_figure,
    spatial_samples as spatial_samples,
)
from .spatial_workspace import (
    save_spatial_statics_map as save_spatial_statics_map,
    save_spatial_workspace_map as save_spatial_workspace_map,
    spatial_statics_figure as spatial_statics_figure,
    spatial_workspace_figure as spatial_workspace_figure,
)
from .workspace import (
    save_statics_map as save_statics_map,
    save_workspace_map as save_workspace_map,
    statics_figure as statics_figure,
    workspace_figure as workspace_figure,
)
