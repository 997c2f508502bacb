"""Controllers: potential field (holonomic), goto_waypoint and pure pursuit."""

from .base import CONTROLLERS, REACHED, RUNNING, STALLED, Command, Controller, StallDetector, make_controller
from .followers import GotoWaypoint, PurePursuit
from .potential_field import PotentialField, attractive, repulsive

__all__ = ["CONTROLLERS", "Command", "Controller", "GotoWaypoint", "PotentialField", "PurePursuit", "REACHED",
           "RUNNING", "STALLED", "StallDetector", "attractive", "make_controller", "repulsive"]
