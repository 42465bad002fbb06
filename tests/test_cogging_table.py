"""The cogging table's size against the map's harmonics (``fricgen.codegen.cogging_table``):
a map too fine for the largest table is emitted with a warning that states its error."""
import numpy as np
import pytest

from fricgen.codegen.cogging_table import TABLE_TOLERANCE, CoggingTable
from fricgen.effects.cogging_map import MAX_TABLE, CoggingMap


def _map(harmonic):
    return CoggingMap(period=2 * np.pi, harmonics=(7, harmonic), sine=(0.002, 0.004),
                      cosine=(0.0, 0.001), sine_se=(0.0, 0.0), cosine_se=(0.0, 0.0))


def test_a_map_the_largest_table_cannot_hold_within_tolerance_is_named_with_its_error():
    table = CoggingTable.of(_map(1000))
    assert table.points == MAX_TABLE and table.float_bound > TABLE_TOLERANCE * table.map.rms
    line = table.shortfall("cg", "Nm")
    assert "harmonic 1000" in line and "CG_COGGING_ERROR_BOUND" in line
    assert f"{table.float_bound / table.map.rms:.1%}" in line


@pytest.mark.parametrize("harmonic", [24, 144])
def test_a_map_within_tolerance_gets_no_warning(harmonic):
    table = CoggingTable.of(_map(harmonic))
    assert table.float_bound <= TABLE_TOLERANCE * table.map.rms and table.shortfall("cg", "Nm") == ""
