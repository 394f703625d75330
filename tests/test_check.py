"""``swatch check`` (issue 20): a synthetic line of parts at known thickness offsets, made by tmm +
colour-science (not our code), judged exactly as the tolerance says, voltage corrections within 0.2 V."""
from __future__ import annotations

import json

import colour
import numpy as np
from cli_helpers import assert_one_line_error, run_swatch
from synthetic import tmm_half_vector_reflectance

O10 = "CIE 1964 10 Degree Standard Observer"
OFFSETS_NM = (-3.0, -1.0, 0.0, 0.8, 2.0, 4.0)


def _lab(d, light, view):
    wl = np.arange(380.0, 781.0, 5.0)
    R = tmm_half_vector_reflectance(d, [light], [view], wl)[0]
    sd = colour.SpectralDistribution(dict(zip(wl, R, strict=True)))
    XYZ = colour.sd_to_XYZ(sd, colour.MSDS_CMFS[O10], colour.SDS_ILLUMINANTS["D65"]) / 100
    return colour.XYZ_to_Lab(XYZ, colour.CCS_ILLUMINANTS[O10]["D65"])


def test_synthetic_line_passes_and_fails_as_the_tolerance_says(tmp_path):
    assert run_swatch("spec", "--thickness", "120", "--tolerance", "dE00:2", "--out", tmp_path / "s").returncode == 0
    spec = json.loads((tmp_path / "s" / "spec.json").read_text(encoding="utf-8"))
    geoms = [spec["reference"], *spec["multi_angle"][:3]]
    lines = ["id,light_deg,view_deg,L,a,b"]
    truth = {}
    for k, off in enumerate(OFFSETS_NM):
        dE = []
        for g in geoms:
            signed = g["view_deg"] if g["view_side"] == "opposite" else -g["view_deg"]
            lab = _lab(120.0 + off, g["light_deg"], g["view_deg"])
            lines.append(f"P{k},{g['light_deg']:g},{signed:g},{lab[0]:.4f},{lab[1]:.4f},{lab[2]:.4f}")
            dE.append(colour.delta_E(lab, g["Lab"], method="CIE 2000"))
        truth[f"P{k}"] = (max(dE) <= 2.0, -off / 2.032)
    p = tmp_path / "parts.csv"
    p.write_text("\n".join(lines) + "\n", encoding="utf-8")
    proc = run_swatch("check", p, "--spec", tmp_path / "s" / "spec.json", "--json", "--report", tmp_path / "qc")
    out = json.loads(proc.stdout)
    assert {r["id"]: r["pass"] for r in out["measurements"]} == {k: v[0] for k, v in truth.items()}
    assert len({v[0] for v in truth.values()}) == 2  # the line has parts on both sides of the tolerance
    for r in out["measurements"]:
        assert abs(r["voltage_correction_V"] - truth[r["id"]][1]) <= 0.2
        assert set(r["delta_E"]) == {g["geometry"] for g in geoms}
    assert out["pass"] is False and proc.returncode == 1
    assert (tmp_path / "qc" / "check.png").stat().st_size > 0


def test_check_exit_status_zero_when_all_pass_and_two_for_bad_input(tmp_path):
    assert run_swatch("spec", "--thickness", "120", "--out", tmp_path / "s").returncode == 0
    lab = _lab(120.0, 45.0, 0.0)
    p = tmp_path / "one.csv"
    p.write_text(f"L;a;b\n{lab[0]:.4f};{lab[1]:.4f};{lab[2]:.4f}\n".replace(".", ","), encoding="utf-8")
    proc = run_swatch("check", p, "--spec", tmp_path / "s" / "spec.json")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    bad = tmp_path / "bad.json"
    bad.write_text("{}", encoding="utf-8")
    assert_one_line_error(run_swatch("check", p, "--spec", bad), "not a swatch spec.json")
