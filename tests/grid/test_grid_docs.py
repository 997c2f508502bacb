"""docs/grid.md's example works on the README's own maze."""

from navlab import Status
from navlab.grid import make_maze, plan, plan_world


def test_the_docs_example_on_the_readme_maze():
    # navlab grid maze --cells 10 10 --seed 1 --out maze.yaml (CLI defaults)
    grid = make_maze(10, 10, seed=1).inflate(0.1)
    r = plan(grid, (5, 5), (96, 96), algorithm="jps")
    assert r.status == Status.EXACT
    assert plan(grid, (3, 3), (96, 96), algorithm="jps").status == Status.INVALID_START  # as the docs say
    r = plan_world(grid, (0.3, 0.3), (4.8, 4.8), smooth=True)
    assert r.status == Status.EXACT and r.cost == r.stats["cost_cells"] * 0.05
