"""The explorer: the robot and every joint force in the browser (``prp3 explore``).

* :mod:`prp3.explorer.scene`: what is drawn, as plain columns (no Bokeh): the
  robot at a pose, its joint forces as arrows from prp3's own engines, a run
  of ``prp3 simulate``, the statics map of the workspace.
* :mod:`prp3.explorer.run_folder`: a folder of ``prp3 simulate`` results read
  and checked against the robot, and the run's platform motion.
* :mod:`prp3.explorer.app`: the Bokeh document of the server's 3-PRP page;
  :mod:`prp3.explorer.page`, what both pages draw alike (the robot's figure,
  the key, the arrows, the table, the sliders); :mod:`prp3.explorer.live`, the
  update loop of a live page and its one message per update;
  :mod:`prp3.explorer.scrubber`, a run's time plots and scrubber; :mod:`prp3.explorer.server`,
  the server of ``prp3 explore``; :mod:`prp3.explorer.html_file`, the
  self-contained HTML file of a run (``prp3 simulate --html``, ``prp3 explore
  --export``).  Bokeh is imported lazily, inside their functions.
* :mod:`prp3.explorer.family_scene` and :mod:`prp3.explorer.family_app`: the
  same for a family robot (docs/family.md): its own legs (R joints as circles,
  P joints as slides), the joint forces of :mod:`prp3.family` at the joint
  origins, and its singularity measures ``μ_leg``, ``μ_par``.
* :mod:`prp3.explorer.spatial_page` and :mod:`prp3.explorer.spatial_run`: the 3-D page of a
  spatial robot's run (plotly, docs/spatial.md §22): :func:`spatial_page_figure` (the figure as a
  dict), :func:`spatial_run_html` / :func:`write_spatial_run_html` (the offline page) and
  :func:`read_spatial_run` (a ``prp3 simulate`` folder of a spatial robot, checked).

>>> import subprocess, sys
>>> code = "import sys, prp3.explorer; print('bokeh' in sys.modules)"
>>> subprocess.run([sys.executable, "-c", code], capture_output=True, text=True).stdout.split()
['False']
"""

from __future__ import annotations

from prp3.explorer.family_scene import family_pose_table, family_view
from prp3.explorer.run_folder import Run, read_run, run_motion
from prp3.explorer.scene import (
    PRP3_SCENE,
    Scene,
    State,
    View,
    design_robot,
    pose_table,
    scene_view,
    workspace_overlay,
)
from prp3.explorer.spatial_page import spatial_page_figure, spatial_run_html, write_spatial_run_html
from prp3.explorer.spatial_run import read_spatial_run

__all__ = [
    "PRP3_SCENE",
    "Run",
    "Scene",
    "State",
    "View",
    "design_robot",
    "family_pose_table",
    "family_view",
    "pose_table",
    "read_run",
    "read_spatial_run",
    "run_motion",
    "scene_view",
    "spatial_page_figure",
    "spatial_run_html",
    "workspace_overlay",
    "write_spatial_run_html",
]
