"""Moving AI scenario files (navlab.grid.scen.read_scen)."""

import pytest

from navlab.grid.mapio import MapFormatError
from navlab.grid.scen import read_scen

ROW = "0\troom.map\t12\t8\t{sx}\t{sy}\t{gx}\t{gy}\t3.00000000\n"


def write(tmp_path, first_line, **cells):
    where = {"sx": 1, "sy": 1, "gx": 4, "gy": 1, **cells}
    path = tmp_path / "room.map.scen"
    path.write_text(f"{first_line}\n" + ROW.format(**where))
    return path


@pytest.mark.parametrize("version", ["version 1", "version 1.0", "version  1"])
def test_version_1_is_read(tmp_path, version):
    (row,) = read_scen(write(tmp_path, version))
    assert (row.width, row.height, row.start, row.goal, row.optimal) == (12, 8, (1, 1), (4, 1), 3.0)


@pytest.mark.parametrize("version", ["version 9", "version", "version 0.5", "version one",
                                     "version 1.00000000000000000001"])
def test_another_version_is_one_error_naming_it(tmp_path, version):
    with pytest.raises(MapFormatError, match=r"room\.map\.scen: line 1: scenario format version .* is not one"):
        read_scen(write(tmp_path, version))


def test_cells_outside_the_rows_map_are_read_and_left_to_the_run(tmp_path):
    """`navlab grid scen` counts such a row as INVALID_START / INVALID_GOAL and runs the rest
    (tests/grid/test_grid_cli.py); a bench map experiment refuses it before any trial."""
    (row,) = read_scen(write(tmp_path, "version 1", gx=12))
    assert row.goal == (12, 1)


def test_a_long_version_is_shown_whole(tmp_path):
    """(cut to 20 characters it read '1.000000000000000000', as if 1.0 were refused: newcomer run)"""
    path = write(tmp_path, "version 1.00000000000000000001")
    with pytest.raises(MapFormatError, match=r"version '1\.00000000000000000001' is not one"):
        read_scen(path)
