"""Grid planning: occupancy grids, map files, mazes, A*/Dijkstra/JPS/Theta*."""

from .mapio import MapFormatError, load_map, load_movingai_map, load_ros_map, save_map
from .maze import make_maze, maze_cell_center
from .occupancy import MAX_CELLS, OccupancyGrid
from .planner import GRID_ALGORITHMS, HEURISTICS, line_of_sight, path_cost, plan, plan_world
from .scen import Scenario, read_scen

__all__ = ["GRID_ALGORITHMS", "HEURISTICS", "MAX_CELLS", "MapFormatError", "OccupancyGrid", "Scenario", "line_of_sight",
           "load_map", "load_movingai_map", "load_ros_map", "make_maze", "maze_cell_center", "path_cost",
           "plan", "plan_world", "read_scen", "save_map"]
