"""``swatch match --angles`` / ``--measurement`` (issue 20): thicknesses ranked by the worst or mean
ΔE2000 over several geometries, checked against tmm + colour-science (not our code)."""
from __future__ import annotations

import colour
import numpy as np
import pytest

from tests.cli_helpers import assert_one_line_error, run_json, run_swatch
from tests.synthetic import tmm_half_vector_reflectance

O10 = "CIE 1964 10 Degree Standard Observer"


def _lab(d, light, view):
    wl = np.arange(380.0, 781.0, 5.0)
    az = None if view >= 0 else 0.0
    R = tmm_half_vector_reflectance(d, [light], [abs(view)], wl, view_azimuth_deg=az)[0]
    sd = colour.SpectralDistribution(dict(zip(wl, R, strict=True)))
    XYZ = colour.sd_to_XYZ(sd, colour.MSDS_CMFS[O10], colour.SDS_ILLUMINANTS["D65"]) / 100
    return colour.XYZ_to_Lab(XYZ, colour.CCS_ILLUMINANTS[O10]["D65"])


def test_worst_case_match_is_a_minimax_over_the_angles():
    out = run_json("match", "--lab", "55,10,40", "--angles", "45:0,45:60", "--rank", "worst", "--top", "3")
    best = out["candidates"][0]
    d = best["thickness_nm"]

    def worst(x):
        return max(colour.delta_E(_lab(x, 45.0, v), [55, 10, 40], method="CIE 2000") for v in (0.0, 60.0))

    assert best["worst_delta_E_00"] == pytest.approx(worst(d), abs=0.02)
    assert worst(d - 0.5) > worst(d) and worst(d + 0.5) > worst(d)
    ranks = [c["worst_delta_E_00"] for c in out["candidates"]]
    assert ranks == sorted(ranks)


def test_multi_angle_measurement_as_target_recovers_its_thickness(tmp_path):
    geoms = [(45.0, 0.0), (45.0, 30.0), (45.0, -15.0), (45.0, 60.0)]
    rows = ["light_deg,view_deg,L,a,b"] + [f"{lt:g},{v:g}," + ",".join(f"{x:.4f}" for x in _lab(150.0, lt, v))
                                          for lt, v in geoms]
    p = tmp_path / "target.csv"
    p.write_text("\n".join(rows) + "\n", encoding="utf-8")
    out = run_json("match", "--measurement", p, "--rank", "mean")
    assert out["candidates"][0]["thickness_nm"] == pytest.approx(150.0, abs=0.1)
    assert set(out["candidates"][0]["geometries"]) == {"45:0", "45:30", "45:-15", "45:60"}
    assert out["candidates"][0]["within_tolerance"]


def test_bad_angles_are_refused():
    assert_one_line_error(run_swatch("match", "--hex", "b08d57", "--angles", "45/0"), "LIGHT:VIEW")
    assert_one_line_error(run_swatch("match", "--hex", "b08d57", "--angles", "45:0,45:0"), "repeats")
    assert_one_line_error(run_swatch("match", "--hex", "b08d57", "--angles", "45:95"), "within 90")
