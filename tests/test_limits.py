"""limits.check_count: one rule for every count a user gives (iterations, expansions, samples)."""

import math

import numpy as np
import pytest

import navlab
from navlab.errors import ParameterError
from navlab.grid import OccupancyGrid
from navlab.limits import check_count
from navlab.world.shapes import Circle


@pytest.mark.parametrize("value, expected", [(1, 1), (np.int64(7), 7), (1e3, 1000), (np.float64(5.0), 5),
                                             (2 ** 62, 2 ** 62)])
def test_whole_numbers_are_counts_whatever_their_type(value, expected):
    out = check_count("n", value)
    assert out == expected and type(out) is int


# the compiled loops' bound is named only to a number past it (newcomer, session 29)
@pytest.mark.parametrize("value, said", [
    (1.5, "of at least 1, got 1.5"), (math.nan, "of at least 1, got nan"), (math.inf, "of at least 1, got inf"),
    (True, "of at least 1, got True"), ("10", "of at least 1, got '10'"), (None, "of at least 1, got None"),
    (0, "of at least 1, got 0"), (-3, "of at least 1, got -3"),
    (2 ** 62 + 1, "from 1 to 4.61e+18, got 4611686018427387905"),
    (10 ** 400, "from 1 to 4.61e+18, got a number of 401 digits")])
def test_anything_else_is_one_line_naming_the_field_and_the_range(value, said):
    with pytest.raises(ValueError) as info:
        check_count("max_iter", value)
    assert str(info.value) == f"max_iter must be a whole number {said}"


def test_bounds_are_the_callers():
    assert check_count("k", 3.0, 2, 3) == 3 and check_count("k", 10 ** 30, 1, None) == 10 ** 30
    with pytest.raises(ValueError, match="k must be a whole number from 2 to 3, got 4"):
        check_count("k", 4, 2, 3)
    with pytest.raises(ValueError, match="k must be a whole number of at least 1, got 0"):
        check_count("k", 0, 1, None)


@pytest.mark.parametrize("scene, extra", [("clutter", {}), ("trap_car", {"motion": "reeds_shepp"})])
def test_max_iter_written_as_a_float_plans_as_the_whole_number(scene, extra):
    """1e3 from a command line or a YAML file plans as 1000 iterations, for 2D and SE(2) trees alike."""
    a = navlab.plan(scene, planner="rrt", max_iter=1e3, seed=1, **extra)
    b = navlab.plan(scene, planner="rrt", max_iter=1000, seed=1, **extra)
    assert a.params["max_iter"] == 1000 and type(a.params["max_iter"]) is int
    assert a.status == b.status and a.cost == b.cost
    with pytest.raises(ValueError, match="max_iter must be a whole number"):
        navlab.plan(scene, planner="rrt", max_iter=2.5, **extra)


@pytest.mark.parametrize("value, text", [
    (10 ** 400, "an integer of 401 digits"), ([30, 150, 10 ** 400], "[30, 150, an integer of 401 digits]"),
    ((1,), "(1,)"), ("abc", "'abc'"), (0.5, "0.5"),
    (list(range(100)), "[0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21..."),
    (np.zeros((2, 1)), "array([[0.], [0.]])")])
def test_shown_is_one_line_of_at_most_80_characters(value, text):
    from navlab.limits import shown

    assert shown(value) == text and len(shown("x" * 500)) == 80


def test_shown_survives_a_list_nested_thousands_deep():
    from navlab.limits import shown

    deep = inner = []
    for _ in range(100_000):
        inner.append([])
        inner = inner[0]
    assert shown(deep) == "[a list nested too deeply to show]"


def test_a_number_too_long_to_write_out_is_shown_by_its_digits():
    """(review, session 20: str() refuses integers past 4 300 digits, so a message about a 5 000-digit --param value
    was an internal ValueError)"""
    import random

    from navlab.limits import digit_count, shown

    rng = random.Random(3)
    for n in [0, 1, 9, 10, 99, 100, 10**20 - 1, 10**20, -(10**30)] + [rng.randrange(1, 10 ** rng.randint(1, 400))
                                                                     for _ in range(500)]:
        assert digit_count(n) == len(str(abs(n)))
    assert (digit_count(10**5000 - 1), digit_count(10**5000)) == (5000, 5001)
    assert shown(10**5000) == "an integer of 5001 digits"
    from click.testing import CliRunner

    from navlab.cli import main

    res = CliRunner().invoke(main, ["plan", "trap", "--planner", "rrt", "--param", "max_iter=" + "9" * 4100])
    assert res.exit_code == 2 and "max_iter must be a whole number from 1 to 4.61e+18, got a number of 4100 digits" \
        in res.stderr


def test_a_short_name_keeps_its_limit_with_control_characters_escaped():
    """(review, session 21: escaped after the cut, 301 control characters came out as 930)"""
    from navlab.limits import short_name

    assert short_name("a\nb") == "a\\nb"
    for name in ("\x01" * 301, "\n" * 300, "é" * 10_000):
        text = short_name(name)
        assert len(text) <= 300 + 3 + len(f" (a name of {len(name)} characters)") and "\n" not in text
        assert text.endswith(f" (a name of {len(name)} characters)")


def test_text_that_reads_as_infinity_is_refused_as_not_finite():
    """(--param expand_dis=inf: YAML keeps the text 'inf', and "must be a number" read as if infinity were not
    one: newcomer, session 31)"""
    from navlab.limits import finite_number

    for text in ("inf", "-Infinity", "nan"):
        with pytest.raises(ParameterError, match=f"x must be finite, got '{text}'"):
            finite_number("x", text)
    with pytest.raises(ParameterError, match="x must be a number, got 'abc'"):
        finite_number("x", "abc")


@pytest.mark.parametrize("call, said", [
    (lambda: OccupancyGrid(np.zeros((4, 4), bool)).world_to_cell([10 ** 400, 1]), "world points: expected"),
    (lambda: Circle([10 ** 400, 1], 1.0), "must be two finite numbers"),
])
def test_a_whole_number_past_a_float_is_refused_naming_the_field(call, said):
    # (numpy's OverflowError "int too large to convert to float" went up as an internal error: review, s32)
    with pytest.raises(ParameterError, match=said):
        call()
