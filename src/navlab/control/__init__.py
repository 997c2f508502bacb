"""Controllers: potential field (holonomic), the hybrid navigator (global plan +
field), goto_waypoint and pure pursuit (with optional replanning)."""

from .base import CONTROLLERS, REACHED, RUNNING, STALLED, Command, Controller, StallDetector, make_controller
from .dwa import DWA, DWABarn
from .followers import GotoWaypoint, PurePursuit
from .mppi import MPPI
from .rpp import RegulatedPurePursuit
from .hybrid import Hybrid
from .potential_field import PotentialField, attractive, repulsive

__all__ = ["CONTROLLERS", "Command", "Controller", "DWA", "DWABarn", "GotoWaypoint", "Hybrid", "MPPI", "PotentialField", "PurePursuit", "RegulatedPurePursuit", "REACHED",
           "RUNNING", "STALLED", "StallDetector", "attractive", "make_controller", "repulsive"]
