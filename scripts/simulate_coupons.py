"""Write tests/data/simulated-line-coupons.csv: the coupons of a simulated anodising line (issue 19).

The line: TiO2-Franta on Ti-Palm (not the default substrate), a two-slope growth law (4 nm +
2.2 nm/V up to a knee at 45 V, 2.9 nm/V above), a thickness spread of 3.5 % (1σ of the local
thickness), 30 coupons at 8–100 V, measured at 45°:0° (half-vector facet 22.5°), D65, CIE 1964 10°.
Each coupon's spectrum is Byrnes' ``tmm.coh_tmm`` (s and p averaged) integrated over the thickness
distribution by 24-point Gauss–Legendre quadrature over ±5σ (an independent route: swatch uses
Gauss–Hermite), its colour by ``colour.sd_to_XYZ`` and ``colour.XYZ_to_Lab``; then Gaussian noise of
0.3 per CIELAB coordinate, and coupon c20 is mislabelled (anodised at 30 V, labelled 71.4 V).

    python scripts/simulate_coupons.py            # about a minute (tmm is a per-wavelength scalar code)
"""
from __future__ import annotations

import sys
import warnings
from pathlib import Path

import colour
import numpy as np
import tmm

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from swatch.physics.materials import load_material

WL = np.arange(380.0, 781.0, 5.0)
FILM, SUBSTRATE = "TiO2-Franta", "Ti-Palm"
OFFSET_NM, RATE, KNEE_V, RATE_ABOVE, SPREAD = 4.0, 2.2, 45.0, 2.9, 0.035
VOLTS = np.linspace(8.0, 100.0, 30)
MISLABELLED, GROWN_AT_V = 20, 30.0
NOISE = 0.3
OUT = Path(__file__).resolve().parents[1] / "tests" / "data" / "simulated-line-coupons.csv"


def thickness_nm(v):
    return OFFSET_NM + RATE * np.minimum(v, KNEE_V) + RATE_ABOVE * np.maximum(v - KNEE_V, 0.0)


def main() -> None:
    nf, ns = load_material(FILM).nk(WL), load_material(SUBSTRATE).nk(WL)
    th = np.radians(22.5)

    def R(d):
        return np.array([0.5 * sum(tmm.coh_tmm(p, [1.0, nf[i], ns[i]], [np.inf, d, np.inf], th, w)["R"] for p in "sp")
                         for i, w in enumerate(WL)])

    x, w = np.polynomial.legendre.leggauss(24)

    def R_spread(d):
        sigma = SPREAD * d
        ts = d + 5.0 * sigma * x
        ww = w * np.exp(-0.5 * ((ts - d) / sigma) ** 2)
        return sum(wi * R(t) for wi, t in zip(ww / ww.sum(), ts, strict=True))

    cmfs = colour.MSDS_CMFS["CIE 1964 10 Degree Standard Observer"]
    d65 = colour.SDS_ILLUMINANTS["D65"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        white = colour.sd_to_XYZ(colour.SpectralDistribution(np.ones_like(WL), WL), cmfs, d65)

        def Lab(r):
            XYZ = colour.sd_to_XYZ(colour.SpectralDistribution(r, WL), cmfs, d65)
            return colour.XYZ_to_Lab(XYZ / 100.0, colour.XYZ_to_xy(white / 100.0))

        rng = np.random.default_rng(19)
        rows = [f"# simulated line (scripts/simulate_coupons.py): {FILM} on {SUBSTRATE}, {OFFSET_NM:g} nm + "
                f"{RATE:g} nm/V to {KNEE_V:g} V then {RATE_ABOVE:g} nm/V, spread {SPREAD:g}; 45:0, D65, 10 deg; "
                f"noise {NOISE:g} per Lab coordinate; c{MISLABELLED} grown at {GROWN_AT_V:g} V",
                "coupon,voltage_V,L,a,b"]
        for i, v in enumerate(VOLTS):
            L, a, b = Lab(R_spread(thickness_nm(GROWN_AT_V if i == MISLABELLED else v))) + rng.normal(0.0, NOISE, 3)
            rows.append(f"c{i:02d},{v:.4f},{L:.3f},{a:.3f},{b:.3f}")
    OUT.write_text("\n".join(rows) + "\n", encoding="utf-8")
    print(f"{OUT}: {VOLTS.size} coupons")


if __name__ == "__main__":
    main()
