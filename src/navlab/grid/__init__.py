"""Grid planning: occupancy grids, map files, mazes, A*/Dijkstra/JPS/Theta*.

The public names below are imported on first use (PEP 562), as in
:mod:`navlab`: importing one submodule (``navlab.grid.occupancy``, which
every source check needs) then loads neither the search kernels nor the map
readers.
"""

from .. import lazy_attributes

#: public name -> the submodule (relative to navlab.grid) that defines it
_LAZY = {
    "MapFormatError": "mapio", "load_map": "mapio", "load_movingai_map": "mapio", "load_ros_map": "mapio",
    "save_map": "mapio", "make_maze": "maze", "maze_cell_center": "maze", "MAX_CELLS": "occupancy",
    "OccupancyGrid": "occupancy", "GRID_ALGORITHMS": "planner", "HEURISTICS": "planner", "line_of_sight": "planner",
    "path_cost": "planner", "plan": "planner", "plan_world": "planner", "Scenario": "scen", "read_scen": "scen",
}

__all__ = ["GRID_ALGORITHMS", "HEURISTICS", "MAX_CELLS", "MapFormatError", "OccupancyGrid", "Scenario", "line_of_sight",
           "load_map", "load_movingai_map", "load_ros_map", "make_maze", "maze_cell_center", "path_cost",
           "plan", "plan_world", "read_scen", "save_map"]

__getattr__, __dir__ = lazy_attributes(__name__, _LAZY)
