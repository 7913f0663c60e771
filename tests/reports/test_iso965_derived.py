"""ISO 965-1 limits of M24x1.5 derived by hand from the standard's tabled values, against
``cutsim.reports.iso965.limits`` (6g, 6H, 4h6h: the bolt's and the nut's commonest classes and a
fine bolt class whose two grades differ; 5H and 8H: nut grades other than 6, whose tabled
tolerances follow from the ROUNDED grade 6 value).

The tabled values (micrometres) for P = 1.5 and the diameter range 22.4 < d <= 45 mm, as ISO
965-1:1998 lists them (Table 2 fundamental deviations, Table 3 T_D1, Table 4 T_d, Table 5 T_D2,
Table 6 T_d2) and as the M24x1.5 rows of ISO 965-2's limits of sizes reproduce them
(6g: d 23.732 to 23.968, d2 22.844 to 22.994; 6H: D2 23.026 to 23.226, D1 22.376 to 22.676):

    es(g) = -32, es(h) = EI(H) = 0; T_d(4) = 150, T_d(6) = 236; T_d2(4) = 95, T_d2(6) = 150;
    T_D2(6) = 200; T_D1(6) = 300; T_D2(5) = 160, T_D2(8) = 315; T_D1(5) = 236, T_D1(8) = 475.

Basic sizes (ISO 724): d2 = D2 = d - 0.649519 P, d1 = D1 = d - 1.082532 P. A bolt's class gives
d from es - T_d to es over d, d2 from es - T_d2 to es over d2, d1 at most d1 + es; a nut's D at
least D + EI, D2 and D1 from EI to EI + T (docs/checks.md). The tabled values themselves follow
from ISO 965-1's formulas rounded to the R40 series (ISO 3; printed in whole µm below 100), checked
here with the test's own rounding; a grade other than 6 is the grade factor (0.5, 0.63, 0.8, 1.25,
1.6, 2 for grades 3, 4, 5, 7, 8, 9) times the ROUNDED grade 6 value, rounded again: T_D1(5) =
r40(0.8 x 300 = 240) = 236, not r40(0.8 x 305.5 = 244.4) = 250.
"""
import math

import pytest

from cutsim.reports.iso965 import limits

D, P = 24.0, 1.5
D2_BASIC = D - 0.649519 * P
D1_BASIC = D - 1.082532 * P
TABLE = {"es_g": -32.0, "Td4": 150.0, "Td6": 236.0, "Td2_4": 95.0, "Td2_6": 150.0, "TD2_6": 200.0, "TD1_6": 300.0,
         "TD2_5": 160.0, "TD2_8": 315.0, "TD1_5": 236.0, "TD1_8": 475.0}
R40 = [10, 10.6, 11.2, 11.8, 12.5, 13.2, 14, 15, 16, 17, 18, 19, 20, 21.2, 22.4, 23.6, 25, 26.5, 28, 30,
       31.5, 33.5, 35.5, 37.5, 40, 42.5, 45, 47.5, 50, 53, 56, 60, 63, 67, 71, 75, 80, 85, 90, 95]  # ISO 3


def r40(x: float) -> float:
    """Nearest R40 preferred number on a logarithmic scale, printed in whole micrometres below
    100 (31.5 as 32). Nearest to the exact 10^(k/40) that the R40 value rounds (ISO 3): 136 lies
    below 10^(85.5/40) = 137.2 and gives 132 (Td2(5) of 11.2-22.4 mm at P 2.5, 0.8 x 170, is
    printed 132), though it is nearer 140 than 132 on the printed values."""
    k = min(range(40, 160), key=lambda i: abs(i / 40.0 - math.log10(x)))  # 10 um to 10 mm
    v = R40[k % 40] * 10 ** (k // 40 - 1)
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
    # the other grades from the rounded grade 6 value (the unrounded 305.5 would give 250 and 500)
    assert r40(0.8 * TABLE["TD1_6"]) == TABLE["TD1_5"] and r40(1.6 * TABLE["TD1_6"]) == TABLE["TD1_8"]
    assert r40(0.8 * 230.0 * P ** 0.7) == 250.0 and r40(1.6 * 230.0 * P ** 0.7) == 500.0
    assert r40(1.32 * 0.8 * TABLE["Td2_6"]) == TABLE["TD2_5"] and r40(1.32 * 1.6 * TABLE["Td2_6"]) == TABLE["TD2_8"]


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
    "M24x1.5-5H": {  # grade 5 for both D2 and D1
        "major_diameter": (D, None),
        "pitch_diameter": (D2_BASIC, D2_BASIC + _um(TABLE["TD2_5"])),
        "minor_diameter": (D1_BASIC, D1_BASIC + _um(TABLE["TD1_5"])),
    },
    "M24x1.5-8H": {
        "major_diameter": (D, None),
        "pitch_diameter": (D2_BASIC, D2_BASIC + _um(TABLE["TD2_8"])),
        "minor_diameter": (D1_BASIC, D1_BASIC + _um(TABLE["TD1_8"])),
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


def test_m24x1_5_5h_and_8h_by_hand():
    """5H: D1 22.376202 + 0.236 = 22.612202 (not + 0.250); 8H: + 0.475 = 22.851202 (not + 0.500);
    D2 23.025721 + 0.160 and + 0.315."""
    h5, h8 = limits("M24x1.5-5H"), limits("M24x1.5-8H")
    assert [round(x, 6) for x in h5["minor_diameter"]] == [22.376202, 22.612202]
    assert [round(x, 6) for x in h8["minor_diameter"]] == [22.376202, 22.851202]
    assert [round(x, 6) for x in h5["pitch_diameter"]] == [23.025721, 23.185721]
    assert [round(x, 6) for x in h8["pitch_diameter"]] == [23.025721, 23.340721]


# T_d2 (µm) of ISO 965-1 as ASME B1.13M-2005 Table 11 (Machinery's Handbook, "Pitch-diameter
# tolerances of external metric threads, Td2") reprints it: (over, up to, P, grades 3 to 9; None
# where not tabled). Every grade k is r40(factor_k x tabled grade 6 value).
TD2_TABLE = [
    (1.5, 2.8, 0.2, (25, 32, 40, 50, None, None, None)), (1.5, 2.8, 0.45, (36, 45, 56, 71, 90, None, None)),
    (2.8, 5.6, 0.35, (34, 42, 53, 67, 85, None, None)), (2.8, 5.6, 0.5, (38, 48, 60, 75, 95, None, None)),
    (2.8, 5.6, 0.6, (42, 53, 67, 85, 106, None, None)), (2.8, 5.6, 0.7, (45, 56, 71, 90, 112, None, None)),
    (2.8, 5.6, 0.75, (45, 56, 71, 90, 112, None, None)), (2.8, 5.6, 0.8, (48, 60, 75, 95, 118, 150, 190)),
    (5.6, 11.2, 0.75, (50, 63, 80, 100, 125, None, None)), (5.6, 11.2, 1.0, (56, 71, 90, 112, 140, 180, 224)),
    (5.6, 11.2, 1.25, (60, 75, 95, 118, 150, 190, 236)), (5.6, 11.2, 1.5, (67, 85, 106, 132, 170, 212, 265)),
    (11.2, 22.4, 1.0, (60, 75, 95, 118, 150, 190, 236)), (11.2, 22.4, 1.25, (67, 85, 106, 132, 170, 212, 265)),
    (11.2, 22.4, 1.5, (71, 90, 112, 140, 180, 224, 280)), (11.2, 22.4, 1.75, (75, 95, 118, 150, 190, 236, 300)),
    (11.2, 22.4, 2.0, (80, 100, 125, 160, 200, 250, 315)), (11.2, 22.4, 2.5, (85, 106, 132, 170, 212, 265, 335)),
    (22.4, 45.0, 1.0, (63, 80, 100, 125, 160, 200, 250)), (22.4, 45.0, 1.5, (75, 95, 118, 150, 190, 236, 300)),
    (22.4, 45.0, 2.0, (85, 106, 132, 170, 212, 265, 335)),
]


@pytest.mark.parametrize("lo,hi,p,row", TD2_TABLE)
def test_td2_of_every_grade_as_printed(lo, hi, p, row):
    from cutsim.reports.iso965 import tolerance
    for grade, want in zip(range(3, 10), row):
        if want is not None:
            assert tolerance("d2", grade, hi, p) == want, (lo, hi, p, grade)
            assert r40({3: 0.5, 4: 0.63, 5: 0.8, 6: 1.0, 7: 1.25, 8: 1.6, 9: 2.0}[grade] * row[3]) == want


def test_printed_grade6_values_carry_to_the_limits():
    """Two grade 6 values the tables print off the formula: T_d(6) at P 4 is 475 (formula 452 ->
    450; ISO 965-2's M36 6g row: d 35.465 to 35.940 = 36 - 0.060 - 0.475), T_d2(6) of 2.8-5.6 mm at
    P 0.75 is 90 (formula 92.05 -> 95): M4.5x0.75-6H's T_D2 = r40(1.32 x 90 = 118.8) = 118, as tap
    makers' charts list the 6H pitch-diameter tolerance of M4.5x0.75; D2 = 4.5 - 0.649519 x 0.75."""
    assert [round(x, 3) for x in limits("M36x4-6g")["major_diameter"]] == [35.465, 35.940]
    d2 = 4.5 - 0.649519 * 0.75
    got = limits("M4.5x0.75-6H")["pitch_diameter"]
    assert abs(got[0] - d2) < 1e-6 and abs(got[1] - (d2 + 0.118)) < 1e-6
    assert abs(limits("M36x4-4h")["major_diameter"][0] - (36.0 - 0.300)) < 1e-9  # r40(0.63 x 475)


def test_two_more_printed_values_at_small_pitches():
    """es_g at P 0.4 is printed -19 (15 + 4.4 = 19.4 would round to 20 on the logarithmic scale):
    M2x0.4-6g d 1.886 to 1.981, d2 1.654 to 1.721 (2 - 0.019 - 0.095, 1.7402 - 0.019 - 0.067), as
    metric thread charts list it; T_d(6) at P 0.2 is printed 56 (180 x 0.2^(2/3) - 3.15 / sqrt(0.2)
    = 54.5 would round to 53): M1.6x0.2-6g d 1.527 to 1.583."""
    g = limits("M2x0.4-6g")
    assert [round(x, 3) for x in g["major_diameter"]] == [1.886, 1.981]
    assert [round(x, 3) for x in g["pitch_diameter"]] == [1.654, 1.721]
    assert [round(x, 3) for x in limits("M1.6x0.2-6g")["major_diameter"]] == [1.527, 1.583]
    assert abs(limits("M2x0.4-6G")["pitch_diameter"][0] - (2.0 - 0.649519 * 0.4 + 0.019)) < 1e-6  # EI_G too
