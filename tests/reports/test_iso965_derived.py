"""ISO 965-1 limits of M24x1.5 derived by hand from the standard's tabled values, against
``cutsim.reports.iso965.limits`` (6g, 6H, 4h6h: the bolt's and the nut's commonest classes and a
fine bolt class whose two grades differ).

The tabled values (micrometres) for P = 1.5 and the diameter range 22.4 < d <= 45 mm, as ISO
965-1:1998 lists them (Table 2 fundamental deviations, Table 3 T_D1, Table 4 T_d, Table 5 T_D2,
Table 6 T_d2) and as the M24x1.5 rows of ISO 965-2's limits of sizes reproduce them
(6g: d 23.732 to 23.968, d2 22.844 to 22.994; 6H: D2 23.026 to 23.226, D1 22.376 to 22.676):

    es(g) = -32, es(h) = EI(H) = 0; T_d(4) = 150, T_d(6) = 236; T_d2(4) = 95, T_d2(6) = 150;
    T_D2(6) = 200; T_D1(6) = 300.

Basic sizes (ISO 724): d2 = D2 = d - 0.649519 P, d1 = D1 = d - 1.082532 P. A bolt's class gives
d from es - T_d to es over d, d2 from es - T_d2 to es over d2, d1 at most d1 + es; a nut's D at
least D + EI, D2 and D1 from EI to EI + T (docs/checks.md). The tabled values themselves follow
from ISO 965-1's formulas rounded to the R40 series (ISO 3; printed in whole µm below 100), checked
here with the test's own rounding.
"""
import math

import pytest

from cutsim.reports.iso965 import limits

D, P = 24.0, 1.5
D2_BASIC = D - 0.649519 * P
D1_BASIC = D - 1.082532 * P
TABLE = {"es_g": -32.0, "Td4": 150.0, "Td6": 236.0, "Td2_4": 95.0, "Td2_6": 150.0, "TD2_6": 200.0, "TD1_6": 300.0}
R40 = [10, 10.6, 11.2, 11.8, 12.5, 13.2, 14, 15, 16, 17, 18, 19, 20, 21.2, 22.4, 23.6, 25, 26.5, 28, 30,
       31.5, 33.5, 35.5, 37.5, 40, 42.5, 45, 47.5, 50, 53, 56, 60, 63, 67, 71, 75, 80, 85, 90, 95]  # ISO 3


def r40(x: float) -> float:
    """Nearest R40 preferred number on a logarithmic scale, printed in whole micrometres below
    100 (31.5 as 32)."""
    series = [v * 10 ** k for k in range(0, 3) for v in R40]
    v = min(series, key=lambda s: abs(math.log(s / x)))
    return float(round(v)) if v < 100 else float(v)


def test_the_tabled_values_follow_from_the_formulas():
    dm = math.sqrt(22.4 * 45.0)  # the range's geometric mean
    td2_6 = 90.0 * P ** 0.4 * dm ** 0.1
    td_6 = 180.0 * P ** (2.0 / 3.0) - 3.15 / math.sqrt(P)
    assert r40(15.0 + 11.0 * P) == -TABLE["es_g"]
    assert r40(td2_6) == TABLE["Td2_6"] and r40(0.63 * td2_6) == TABLE["Td2_4"]
    assert r40(td_6) == TABLE["Td6"] and r40(0.63 * td_6) == TABLE["Td4"]
    assert r40(1.32 * TABLE["Td2_6"]) == TABLE["TD2_6"]
    assert r40(230.0 * P ** 0.7) == TABLE["TD1_6"]


def _um(x: float) -> float:
    return x / 1000.0


EXPECTED = {
    "M24x1.5-6g": {
        "major_diameter": (D + _um(TABLE["es_g"] - TABLE["Td6"]), D + _um(TABLE["es_g"])),
        "pitch_diameter": (D2_BASIC + _um(TABLE["es_g"] - TABLE["Td2_6"]), D2_BASIC + _um(TABLE["es_g"])),
        "minor_diameter": (None, D1_BASIC + _um(TABLE["es_g"])),
    },
    "M24x1.5-6H": {
        "major_diameter": (D, None),
        "pitch_diameter": (D2_BASIC, D2_BASIC + _um(TABLE["TD2_6"])),
        "minor_diameter": (D1_BASIC, D1_BASIC + _um(TABLE["TD1_6"])),
    },
    "M24x1.5-4h6h": {  # pitch diameter grade 4, crest (major) grade 6, es(h) = 0
        "major_diameter": (D - _um(TABLE["Td6"]), D),
        "pitch_diameter": (D2_BASIC - _um(TABLE["Td2_4"]), D2_BASIC),
        "minor_diameter": (None, D1_BASIC),
    },
}


@pytest.mark.parametrize("designation", sorted(EXPECTED))
def test_m24x1_5_limits_derived_from_the_tables(designation):
    got = limits(designation)
    for quantity, want in EXPECTED[designation].items():
        for g, w in zip(got[quantity], want):
            assert (g is None) == (w is None), (designation, quantity, got[quantity])
            if w is not None:
                assert abs(g - w) <= 1e-6, (designation, quantity, got[quantity], want)


def test_m24x1_5_6g_as_printed():
    """ISO 965-2's printed row (to 0.001 mm): d 23.732-23.968, d2 22.844-22.994."""
    got = limits("M24x1.5-6g")
    assert [round(x, 3) for x in got["major_diameter"]] == [23.732, 23.968]
    assert [round(x, 3) for x in got["pitch_diameter"]] == [22.844, 22.994]
