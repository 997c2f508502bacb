"""floor_div gives the cell Python's ``x // res`` gives, at cell edges too."""

import math

import numpy as np
import pytest

from navlab.grid.floor_cells import floor_div


@pytest.mark.parametrize("res", [0.05, 0.1, 0.3, 1.0, 1 / 3, 0.025])
def test_floor_div_is_pythons_floor_division(res):
    rng = np.random.default_rng(7)
    edges = np.arange(-2000, 2000) * res  # products that round just above or below a cell edge
    xs = np.concatenate([edges, np.nextafter(edges, np.inf), np.nextafter(edges, -np.inf),
                         rng.uniform(-300.0, 300.0, 2000), [0.0, -0.0, res, -res]])
    got = np.array([floor_div(float(x), res) for x in xs])
    want = np.array([float(x) // res for x in xs])
    assert np.array_equal(got, want)
    if res != 1.0 and res != 0.025:  # a quotient that is merely floored gets some of these wrong
        assert any(math.floor(float(x) / res) != float(x) // res for x in edges)
