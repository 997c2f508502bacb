"""The BARN protocol against hand computation and the challenge's published log."""

import math
from pathlib import Path

import numpy as np
import pytest

from navlab.bench import barn
from navlab.bench.experiment import ExperimentError

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "barn"
needs_data = pytest.mark.skipif(not DATA.is_dir(), reason="../shared/data/barn is not beside the checkout")


def hand_optimal_time(path_file):
    """run.py's computation, written out: cells to metres, start and goal added, summed at 2 m/s."""
    points = [(-2.0, 3.0)]
    for x, y in np.load(path_file).tolist():
        points.append((x * 0.15 - 0.075 - 4.5, y * 0.15 + 0.075 + 5))
    points.append((-2.0, 13.0))
    length = sum(math.dist(a, b) for a, b in zip(points, points[1:]))
    return length / 2


@needs_data
def test_optimal_time_of_every_shipped_path_file_equals_the_hand_computation():
    files = sorted((DATA / "path_files").glob("path_*.npy"))
    assert len(files) == 8
    for f in files:
        ot = barn.optimal_time(f)
        assert ot == pytest.approx(hand_optimal_time(f), rel=1e-12)
        assert 5.0 <= ot < 20.0  # at least the straight 10 m at 2 m/s


def test_score_clips_the_time_between_two_and_eight_optimal_times():
    assert barn.score(True, 1.0, 5.0) == pytest.approx(0.5)      # faster than 2·OT counts as 2·OT
    assert barn.score(True, 20.0, 5.0) == pytest.approx(0.25)
    assert barn.score(True, 99.0, 5.0) == pytest.approx(1 / 8)   # slower than 8·OT counts as 8·OT
    assert barn.score(False, 10.0, 5.0) == 0.0


@needs_data
def test_the_published_move_base_dwa_figures_on_the_shipped_worlds():
    runs = barn.read_runs(DATA / "dwa_out.txt")
    assert len(runs) == 500 and len({r.world for r in runs}) == 50
    means = barn.challenge_means(runs)
    # the recomputation over all 50 worlds (report_test.py's averaging)
    assert means["success"] == pytest.approx(0.85)
    assert means["collision"] == pytest.approx(0.056)
    assert means["timeout"] == pytest.approx(0.094)
    assert means["time"] == pytest.approx(34.09, abs=0.005)
    shipped = {int(f.stem.split("_")[1]): barn.optimal_time(f) for f in (DATA / "path_files").glob("*.npy")}
    some = [r for r in runs if r.world in shipped]
    scored = barn.challenge_means(some, shipped)
    by_hand = np.mean([np.mean([(r.succeeded * shipped[w] / min(max(r.time_s, 2 * shipped[w]), 8 * shipped[w]))
                                for r in some if r.world == w]) for w in shipped])
    assert scored["score"] == pytest.approx(by_hand) and 0 < scored["score"] <= 0.5
    with pytest.raises(ExperimentError, match="no optimal time .* 6"):
        barn.challenge_means(runs, shipped)


def test_challenge_means_average_worlds_first():
    runs = [barn.BarnRun(0, "succeeded", 10.0), barn.BarnRun(0, "collided", 3.0),
            barn.BarnRun(6, "succeeded", 20.0), barn.BarnRun(6, "succeeded", 30.0), barn.BarnRun(6, "timeout", 100.0)]
    m = barn.challenge_means(runs, {0: 5.0, 6: 5.0})
    assert m["success"] == pytest.approx((1 / 2 + 2 / 3) / 2)
    assert m["collision"] == pytest.approx((1 / 2 + 0) / 2)
    assert m["timeout"] == pytest.approx((0 + 1 / 3) / 2)
    assert m["time"] == pytest.approx((10.0 + 25.0) / 2)
    assert m["score"] == pytest.approx(((0.5 + 0) / 2 + (0.25 + 5 / 30 + 0) / 3) / 2)


def straight_run(speed=1.0, dt=0.05, until=200.0):
    t = np.arange(0.0, until, dt)
    y = np.minimum(3.0 + speed * t, 13.0)
    return t, np.column_stack([np.full_like(t, -2.0), y])


def test_judge_starts_the_clock_at_the_first_tenth_of_a_metre():
    t, xy = straight_run(speed=1.0)
    run = barn.judge(t, xy)
    # moved 0.1 m at t = 0.1 s, within 1 m of the goal (y = 12) at t = 9 s
    assert run.status == "succeeded" and run.time_s == pytest.approx(8.9, abs=1e-9)


def test_judge_collided_before_the_goal_and_timeouts():
    t, xy = straight_run(speed=1.0)
    assert barn.judge(t, xy, collided_at=4.0).status == "collided"
    assert barn.judge(t, xy, collided_at=9.5).status == "succeeded"   # touched after it had arrived
    t, xy = straight_run(speed=0.05, until=150.0)                      # 9 m at 5 cm/s takes 180 s
    slow = barn.judge(t, xy)
    assert slow.status == "timeout" and slow.time_s == pytest.approx(100.0)
    still = barn.judge(t, np.tile([-2.0, 3.0], (len(t), 1)))
    assert still.status == "timeout" and still.time_s == 0.0


@needs_data
def test_find_worlds_pairs_each_world_with_its_path_file(tmp_path):
    found = barn.find_worlds(DATA)
    assert sorted(found) == [0, 36, 72, 108, 144, 180, 216, 252]
    assert all(p is not None and p.name == f"path_{i}.npy" for i, (_, p) in found.items())
    (tmp_path / "world_3.world").write_text((DATA / "world_0.world").read_text())
    assert barn.find_worlds(tmp_path) == {3: (tmp_path / "world_3.world", None)}
    with pytest.raises(ExperimentError, match="no world_N.world"):
        barn.find_worlds(DATA / "params")


@pytest.mark.parametrize("text,expected", [(None, [0, 6, 12]), ("6", [6]), ("0,12", [0, 12]), ("0-6:6", [0, 6])])
def test_select_worlds(text, expected):
    assert barn.select_worlds(text, [0, 6, 12]) == expected


def test_select_worlds_names_the_missing_ones_as_ranges():
    with pytest.raises(ExperimentError, match="1-5, 7-11"):
        barn.select_worlds("0-12", [0, 6, 12])
    assert barn.select_worlds("test", list(range(300))) == list(range(0, 300, 6))


def test_select_worlds_says_which_worlds_the_folder_has():
    """(newcomer run: `--worlds test` on the eight worlds of ../shared listed 42 missing numbers and no more)"""
    with pytest.raises(ExperimentError, match=r"no world file for 6, 12, .*, \.\.\. \(42 in all\) in the data "
                                              r"folder; it has 0, 36, 72, 108, 144, 180, 216, 252$"):
        barn.select_worlds("test", [0, 36, 72, 108, 144, 180, 216, 252])


@pytest.mark.parametrize("text", ["0-" + "9" * 400, "0-2000000", "3000000", "0-10:" + "7" * 30, "1" * 5000])
def test_select_worlds_refuses_numbers_past_a_million_without_listing_them(text):
    """(10**400 was an OverflowError, an internal error, from the range it listed)"""
    with pytest.raises(ExperimentError, match="its numbers go up to 1000000"):
        barn.select_worlds(text, list(range(300)))
    assert barn.select_worlds("0006,000-0012:0006", list(range(300))) == [0, 6, 12]  # leading zeros are no more


@pytest.mark.parametrize("text", ["a", "5-2", "1-3:0", "-1"])
def test_select_worlds_refuses_what_is_not_a_selection(text):
    with pytest.raises(ExperimentError, match="--worlds"):
        barn.select_worlds(text, list(range(300)))
