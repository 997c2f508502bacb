"""``astar_pathplanner`` (seed 002): the ``pathplanner`` node under its
first name (the default algorithm is A*; every parameter of ``pathplanner``
works here too, ``algorithm:=rrt_star`` included)."""

from __future__ import annotations

from .base import node_main
from .pathplanner import PathPlanner


class AStarPathPlanner(PathPlanner):
    NODE_NAME = "astar_pathplanner"


main = node_main(AStarPathPlanner)

if __name__ == "__main__":
    main()
