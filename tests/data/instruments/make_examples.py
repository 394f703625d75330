"""Regenerate the CGATS examples of this folder (run from the repository root:
``.venv/bin/python tests/data/instruments/make_examples.py``).

The spectra are made by an independent route, not by swatch's optics or colorimetry: Byrnes'
``tmm.coh_tmm`` on the half-vector facet (tests/synthetic.py) for TiO2-Siefke on Ti-Johnson, and
CIELAB by ``colour.sd_to_XYZ`` (ASTM E308) under the illuminant/observer each file's header states.
The layouts follow files those programs write (see README.md here): ArgyllCMS chartread's ``.ti3``
and X-Rite i1Profiler's CGATS.17 export.
"""
from __future__ import annotations

import sys
from pathlib import Path

import colour
import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[2]))  # the repository root (tests.synthetic)
from tests.synthetic import tmm_half_vector_reflectance  # noqa: E402


def lab(R, wl, illuminant, observer):
    cmfs = colour.MSDS_CMFS[observer]
    ill = colour.SDS_ILLUMINANTS[illuminant]
    out = []
    for r in R:
        sd = colour.SpectralDistribution(dict(zip(wl, r, strict=True)))
        XYZ = colour.sd_to_XYZ(sd, cmfs, ill) / 100.0
        white = colour.CCS_ILLUMINANTS[observer][illuminant]
        out.append(colour.XYZ_to_Lab(XYZ, white))
    return np.array(out)


def argyll_ti3():
    """A part at 120 nm in ArgyllCMS .ti3 layout: spectra in percent, 380–730 nm in 36 bands."""
    wl = np.linspace(380.0, 730.0, 36)
    parts = {"P1": 118.0, "P2": 120.0, "P3": 123.0}
    lines = ["CTI3   ", "", 'DESCRIPTOR "Argyll Calibration Target chart information 3"',
             'ORIGINATOR "Argyll chartread"', 'CREATED "Tue Dec  1 20:00:00 2026"', 'DEVICE_CLASS "OUTPUT"',
             'COLOR_REP "iRGB_XYZ"', 'TARGET_INSTRUMENT "X-Rite i1 Pro 2"', 'DEVCALSTD "XRGA"',
             f'SPECTRAL_BANDS "{wl.size}"', 'SPECTRAL_START_NM "380.000000"', 'SPECTRAL_END_NM "730.000000"', "",
             f"NUMBER_OF_FIELDS {5 + wl.size}", "BEGIN_DATA_FORMAT",
             "SAMPLE_ID SAMPLE_LOC XYZ_X XYZ_Y XYZ_Z " + " ".join(f"SPEC_{round(w)}" for w in wl) + " ",
             "END_DATA_FORMAT", "", f"NUMBER_OF_SETS {len(parts)}", "BEGIN_DATA"]
    for k, (name, d) in enumerate(parts.items(), start=1):
        R = tmm_half_vector_reflectance(d, [45.0], [0.0], wl)[0]
        sd = colour.SpectralDistribution(dict(zip(wl, R, strict=True)))
        XYZ = colour.sd_to_XYZ(sd, colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"], colour.SDS_ILLUMINANTS["D50"])
        lines.append(f'{k} "{name}" ' + " ".join(f"{v:.5f}" for v in XYZ) + " "
                     + " ".join(f"{100 * v:.5f}" for v in R) + " ")
    lines += ["END_DATA", ""]
    (HERE / "argyll_parts.ti3").write_text("\n".join(lines), encoding="utf-8")


def i1profiler_cgats():
    """Coupons at known voltages in i1Profiler's CGATS.17 layout (D50, 2°; Lab and nm380… spectra)."""
    wl = np.arange(380.0, 731.0, 10.0)
    volts = [10.0, 20.0, 30.0, 40.0, 50.0, 60.0]
    d = [2.032 * v for v in volts]  # the default profile's growth law (titanium-fujii2019)
    R = np.stack([tmm_half_vector_reflectance(x, [45.0], [0.0], wl)[0] for x in d])
    L = lab(R, wl, "D50", "CIE 1931 2 Degree Standard Observer")
    lines = ["CGATS.17", 'ORIGINATOR "X-Rite i1Profiler"', 'DESCRIPTOR "Anodised coupons"',
             'CREATED "December 1, 2026"', 'INSTRUMENTATION "i1Pro 2"', 'INSTRUMENT_SERIAL_NUMBER "000000"',
             'MEASUREMENT_SOURCE "Illumination=D50\tObserverAngle=2\tWhiteBase=Abs\tFilter=No"',
             'MEASUREMENT_GEOMETRY "45/0"', 'KEYWORD "VOLTAGE_V"', 'LGOROWLENGTH 6', "",
             f"NUMBER_OF_FIELDS {6 + wl.size}", "BEGIN_DATA_FORMAT",
             "SampleID SAMPLE_NAME VOLTAGE_V LAB_L LAB_A LAB_B " + " ".join(f"nm{round(w)}" for w in wl),
             "END_DATA_FORMAT", "", f"NUMBER_OF_SETS {len(volts)}", "BEGIN_DATA"]
    for k, v in enumerate(volts):
        lines.append(f"{k + 1} A{k + 1} {v:g} " + " ".join(f"{x:.4f}" for x in L[k]) + " "
                     + " ".join(f"{x:.6f}" for x in R[k]))
    lines += ["END_DATA", ""]
    (HERE / "i1profiler_coupons.txt").write_text("\n".join(lines), encoding="utf-8")


if __name__ == "__main__":
    argyll_ti3()
    i1profiler_cgats()
