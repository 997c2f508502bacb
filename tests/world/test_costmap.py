"""Costmaps: Nav2's inflation cell for cell against brute force, footprint costs, layers, scaling, bad input."""

import math

import numpy as np
import pytest

from navlab.grid.occupancy import OccupancyGrid
from navlab.world import Bounds, Circle, Rectangle, World
from navlab.world.costmap import (INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION, Costmap,
                                  CostmapError, LayeredCostmap, build_costmap)
from navlab.world.footprint import Footprint

JACKAL = Footprint.polygon([[-0.21, -0.165], [-0.21, 0.165], [0.21, 0.165], [0.21, -0.165]])


def _brute_inflation(lethal, res, inscribed, radius, factor):
    ys, xs = np.nonzero(lethal)
    out = np.zeros(lethal.shape, np.uint8)
    for y in range(lethal.shape[0]):
        for x in range(lethal.shape[1]):
            d = math.sqrt(min((x - a) ** 2 + (y - b) ** 2 for a, b in zip(xs, ys))) * res
            if d == 0:
                out[y, x] = 254
            elif d <= inscribed:
                out[y, x] = 253
            elif d <= radius:
                out[y, x] = int(252 * math.exp(-factor * (d - inscribed)))
    return out


def test_inflation_equals_brute_force_cell_for_cell():
    rng = np.random.default_rng(0)
    blocked = rng.random((50, 60)) < 0.004
    grid = OccupancyGrid(blocked, resolution=0.05, origin=(1.0, -2.0, 0.0))
    costmap = build_costmap(grid, JACKAL, inflation_radius=0.5, cost_scaling_factor=10.0)
    expected = _brute_inflation(blocked, 0.05, 0.165, 0.5, 10.0)
    np.testing.assert_array_equal(costmap.costs, expected)
    assert (costmap.costs == INSCRIBED_INFLATED_OBSTACLE).any() and (costmap.costs == 0).any()
    assert 0 < ((costmap.costs > 0) & (costmap.costs < 253)).sum()


def test_world_static_layer_marks_the_cells_an_obstacle_reaches():
    world = World("w", Bounds(0, 2, 0, 1), (0.1, 0.1), (1.9, 0.9), (Circle((1.0, 0.5), 0.075),
                                                                     Rectangle((0.2, 0.2), (0.3, 0.3))))
    costmap = build_costmap(world, Footprint.disc(0.1), inflation_radius=0.1, resolution=0.05)
    lethal = costmap.costs == LETHAL_OBSTACLE
    centres = costmap.cell_to_world(np.argwhere(np.ones(costmap.shape, bool))[:, ::-1]).reshape(*costmap.shape, 2)
    # a cell is lethal iff its square meets the disc: centre-to-square distance, by hand
    dx = np.maximum(np.abs(centres[..., 0] - 1.0) - 0.025, 0)
    dy = np.maximum(np.abs(centres[..., 1] - 0.5) - 0.025, 0)
    near_disc = np.hypot(dx, dy) <= 0.075
    in_rect = (np.abs(centres[..., 0] - 0.25) <= 0.075) & (np.abs(centres[..., 1] - 0.25) <= 0.075)
    np.testing.assert_array_equal(lethal, near_disc | in_rect)
    assert costmap.cost_at([(1.0, 0.5), (0.6, 0.7), (-5, 0)]).tolist() == [254, 0, NO_INFORMATION]


def test_footprint_cost_is_the_worst_cell_under_the_outline():
    costs = np.zeros((40, 40), np.uint8)
    costs[20, 30] = 200  # outside the rectangle's outline at the test pose
    costs[15, 14] = 100  # inside the rectangle, not under its outline: Nav2 does not count it
    costs[10, 12] = 77  # on the bottom edge's row
    cm = Costmap(costs, 0.1, (0.0, 0.0))
    # body 0.42 × 0.33 centred at (1.5, 1.5): vertices' cells x 12..17, y 13..16
    fp = Footprint.polygon([[-0.3, -0.2], [-0.3, 0.2], [0.3, 0.2], [0.3, -0.2]])
    pose = (1.5, 1.5, 0.0)  # x 1.2..1.8 → cells 12..18, y 1.3..1.7 → cells 13..17
    outline = np.zeros_like(costs, bool)
    outline[13, 12:19] = outline[17, 12:19] = outline[13:18, 12] = outline[13:18, 18] = True
    assert cm.footprint_cost([pose], fp)[0] == costs[outline].max() == 0
    costs2 = costs.copy()
    costs2[17, 15] = 120
    assert Costmap(costs2, 0.1).footprint_cost([pose], fp)[0] == 120
    # off the map: lethal
    assert cm.footprint_cost([(0.1, 0.1, 0.0)], fp)[0] == LETHAL_OBSTACLE
    # many poses at once agree with one at a time
    poses = np.column_stack((np.linspace(0.5, 3.5, 7), np.full(7, 1.5), np.linspace(0, 3, 7)))
    batch = cm.footprint_cost(poses, JACKAL)
    assert batch.tolist() == [int(cm.footprint_cost([p], JACKAL)[0]) for p in poses]


def test_nav2_occupancy_scaling():
    cm = Costmap(np.array([[0, 1, 128, 252, 253, 254, 255]], np.uint8), 0.05)
    assert cm.to_occupancy_values().tolist() == [[0, 1, 1 + 97 * 127 // 251, 98, 99, 100, -1]]


def test_obstacle_layer_marks_and_clears():
    world = World("empty", Bounds(0, 5, 0, 5), (0.5, 0.5), (4.5, 4.5))
    layers = LayeredCostmap(world, Footprint.disc(0.1), inflation_radius=0.2, cost_scaling_factor=3.0,
                            resolution=0.1, static=False)
    cm = layers.update((1.0, 1.0), np.array([[3.0, 1.05], [1.05, 4.5]]))  # the second is beyond 2.5 m
    assert cm.cost_at([(3.0, 1.05)])[0] == LETHAL_OBSTACLE
    assert cm.cost_at([(1.05, 4.5)])[0] == 0
    # the obstacle moved away: a beam through its cell clears it
    cm = layers.update((1.0, 1.0), np.array([[3.45, 1.05]]))
    assert cm.cost_at([(3.0, 1.05)])[0] < 253 and cm.cost_at([(3.45, 1.05)])[0] == LETHAL_OBSTACLE
    window = layers.update(None, None, window=(1.0, 1.0), center=(3.45, 1.05))
    assert window.shape == (10, 10) and window.cost_at([(3.45, 1.05)])[0] == LETHAL_OBSTACLE


@pytest.mark.parametrize("kwargs, words", [
    ({"inflation_radius": 0.1}, "inflation_radius = 0.1 m is below the footprint's inscribed radius"),
    ({"inflation_radius": float("nan")}, "inflation_radius"),
    ({"cost_scaling_factor": -1}, "cost_scaling_factor"),
    ({"resolution": 0}, "resolution"),
])
def test_bad_settings_name_the_field(kwargs, words):
    world = World("empty", Bounds(0, 5, 0, 5), (0.5, 0.5), (4.5, 4.5))
    settings = {"inflation_radius": 0.5, **kwargs}
    with pytest.raises(CostmapError, match=words):
        LayeredCostmap(world, JACKAL, **settings)


def test_a_steep_cost_scaling_factor_raises_no_numpy_warning_and_keeps_the_costs():
    """cost_scaling_factor=5000 overflowed exp inside the inscribed radius: a RuntimeWarning on stderr
    (newcomer check, session 16). Those cells are INSCRIBED whatever the exponential says."""
    import warnings

    from navlab.world.costmap import inflation_costs

    lethal = np.zeros((40, 40), bool)
    lethal[20, 20] = True
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        steep = inflation_costs(lethal, 0.05, 0.3, 0.6, 5000.0)
    d = np.hypot(*np.meshgrid(np.arange(40) - 20, np.arange(40) - 20)) * 0.05
    assert (steep[(d <= 0.3) & ~lethal] == INSCRIBED_INFLATED_OBSTACLE).all()
    assert (steep[(d > 0.31) & (d <= 0.6)] == 0).all()  # exp(-5000 · 0.01 m or more) is 0


@pytest.mark.parametrize("setting, value", [("resolution", 2e7), ("resolution", 1e-10), ("inflation_radius", 2e7)])
def test_costmap_lengths_keep_navlabs_range(setting, value):
    """resolution=2e7 built a 1 x 1 costmap and inflation_radius=2e7 was taken, where every other length
    is refused beyond ±1e7 m (newcomer check, session 16)."""
    import navlab

    with pytest.raises(ValueError, match=f"^{setting} = "):
        navlab.plan("trap", planner="astar", costmap=True, **{setting: value})
