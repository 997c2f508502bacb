"""navlab: 2D mobile-robot path planning and navigation."""

from .planning import plan, planner_names
from .result import Result, Status
from .sampling import make_planner, make_sampler
from .world import World, load_world
from .world.sources import load_source

__version__ = "0.1.0"

__all__ = ["Result", "Status", "World", "load_source", "load_world", "make_planner", "make_sampler", "plan",
           "planner_names", "__version__"]
