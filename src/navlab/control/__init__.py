"""Controllers: potential field (holonomic), the hybrid navigator (global plan +
field), goto_waypoint and pure pursuit (with optional replanning), rear-wheel feedback
(paths of poses with reverse stretches), DWA, MPPI and Regulated Pure Pursuit."""

from .base import CONTROLLERS, REACHED, RUNNING, STALLED, Command, Controller, StallDetector, make_controller
from .dwa import DWA, DWABarn
from .followers import GotoWaypoint, PurePursuit
from .mppi import MPPI
from .path_tracking import RearWheelFeedback
from .rpp import RegulatedPurePursuit
from .hybrid import Hybrid
from .potential_field import PotentialField, attractive, repulsive

__all__ = ["CONTROLLERS", "Command", "Controller", "DWA", "DWABarn", "GotoWaypoint", "Hybrid", "MPPI", "PotentialField", "PurePursuit", "RearWheelFeedback", "RegulatedPurePursuit", "REACHED",
           "RUNNING", "STALLED", "StallDetector", "attractive", "make_controller", "repulsive"]
