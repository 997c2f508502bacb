"""The simulator (a Gazebo stand-in) and the seeds' experiments."""

from .scene import Scene, load_scene_world
from .simulation import SimResult, SimStatus, Simulation

__all__ = ["Scene", "SimResult", "SimStatus", "Simulation", "load_scene_world"]
