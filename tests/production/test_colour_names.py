"""Colour names follow hue as published titanium anodising charts name it, in their order (issue 35).

The chart: Carlesso's titanium page (http://www.carlesso.net/en/materials/titanium/) gives the colours of
anodised titanium as the voltage rises from 0 to 140 V as "yellow – purple – blue – blue – silver – yellow
– pink – violet – cobalt – green – verdegiallo – pink", the order the common voltage charts print
(bronze/gold, purple, blue, light blue, yellow/gold, rose/magenta, purple/violet, teal/green …). The
colours walked up the scale are tmm's + colour-science's (not our optics), at 45:0 under D65 / 10°."""
from __future__ import annotations

import colour
import numpy as np

from swatch.colorimetry.names import colour_name
from tests.synthetic import tmm_half_vector_reflectance

O10 = "CIE 1964 10 Degree Standard Observer"
#: The chart's colours in voltage order, each with the names of ours that say it.
CHART = (
    ("yellow", {"straw", "gold", "bronze", "champagne"}),
    ("purple", {"plum", "magenta", "purple", "violet"}),
    ("blue", {"blue"}),
    ("blue (light)", {"blue", "silver blue"}),
    ("silver", {"silver", "silver blue"}),
    ("yellow", {"straw", "gold"}),
    ("pink", {"pink", "magenta"}),
    ("violet", {"magenta", "purple", "violet"}),
    ("cobalt", {"blue", "violet"}),
    ("green", {"teal", "green"}),
    ("verdegiallo (yellow-green)", {"lime", "straw"}),
    ("pink", {"champagne", "pink", "magenta"}),
)


def _LCh(thickness_nm):
    wl = np.arange(380.0, 781.0, 5.0)
    cmfs, ill = colour.MSDS_CMFS[O10], colour.SDS_ILLUMINANTS["D65"]
    out = []
    for d in thickness_nm:
        R = tmm_half_vector_reflectance(float(d), [45.0], [0.0], wl)[0]
        XYZ = colour.sd_to_XYZ(colour.SpectralDistribution(dict(zip(wl, R, strict=True))), cmfs, ill) / 100
        out.append(colour.Lab_to_LCHab(colour.XYZ_to_Lab(XYZ, colour.CCS_ILLUMINANTS[O10]["D65"])))
    return np.array(out)


def _follows(runs: list[str], chart) -> bool:
    """Whether the runs of names can be laid on the chart in order, every chart colour in turn (none skipped)."""
    reach = {0} if runs and runs[0] in chart[0][1] else set()
    for name in runs[1:]:
        reach = {j for i in reach for j in (i, i + 1) if j < len(chart) and name in chart[j][1]}
    return len(chart) - 1 in reach


def test_the_names_up_the_voltage_scale_follow_the_charts_order():
    volts = np.arange(5.0, 126.0, 1.0)  # up to the chart's last pink (the model's rate: 50.8 nm / 25 V)
    names = [colour_name(*lch) for lch in _LCh(volts * 50.8 / 25.0)]
    runs = [n for k, n in enumerate(names) if k == 0 or names[k - 1] != n]
    assert _follows(runs, CHART), runs
    # the check can fail: the chart's order reversed, or a colour the chart does not have there
    assert not _follows(runs[::-1], CHART) and not _follows(["blue", *runs], CHART)


def test_the_third_orders_mauve_is_not_blue():
    """Issue 35: 275 nm (#a28bb0, a pale greyish purple) was "blue"."""
    assert colour_name(*_LCh([275.0])[0]) == "mauve"
    white = colour.CCS_ILLUMINANTS[O10]["D65"]
    lab = colour.XYZ_to_Lab(colour.sRGB_to_XYZ(np.array([0xA2, 0x8B, 0xB0]) / 255.0), white)
    assert colour_name(*colour.Lab_to_LCHab(lab)) == "mauve"
    # and a clear blue, a blue-violet and a purple keep their names
    assert colour_name(49.0, 40.0, 265.0) == "blue" and colour_name(55.0, 45.0, 278.0) == "violet"
    assert colour_name(32.0, 48.0, 308.0) == "purple"
