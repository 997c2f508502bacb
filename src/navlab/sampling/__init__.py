"""Sampling-based planning: samplers, RRT, RRT*, Informed RRT*, growth-ratio RRT."""

from .planners import PLANNERS, GrowthRatioRRT, InformedRRTStar, RRT, RRTStar, TreePlanner, make_planner
from .samplers import SAMPLERS, Sampler, make_sampler

__all__ = ["GrowthRatioRRT", "InformedRRTStar", "PLANNERS", "RRT", "RRTStar", "SAMPLERS",
           "Sampler", "TreePlanner", "make_planner", "make_sampler"]
