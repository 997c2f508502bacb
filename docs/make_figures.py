"""Regenerate the pictures in docs/img (python docs/make_figures.py [SCENE ...])."""

import sys
from pathlib import Path

import navlab
from navlab.viz import plot_plan
from navlab.world import SCENES

OUT = Path(__file__).parent / "img"


def main() -> None:
    OUT.mkdir(exist_ok=True)
    for name in sys.argv[1:] or SCENES:
        world = navlab.load_world(name)
        if world.footprint is not None:  # a scene that needs heading
            planner = "hybrid_astar"
            result = navlab.plan(world, planner=planner)
        else:
            planner = "growth_ratio_rrt" if name == "growth_ratio" else "rrt_star"
            result = navlab.plan(world, planner=planner, sampler="uniform", seed=0, keep_tree=True, max_iter=1500)
        fig = plot_plan(world, result, str(OUT / f"scene_{name}.png"),
                        title=f"scene '{name}': {planner}, seed 0, cost {result.cost:.2f} m")
        del fig


if __name__ == "__main__":
    main()
