"""Write the example inputs in examples/ that the README's and the guide's commands name.

    python scripts/make_examples.py            # from the repository root; about a minute (tmm is scalar code)
    python scripts/make_examples.py --outputs  # only what is made from the shipped inputs (seconds, plus pictures)

``--outputs`` remakes every shipped output from the shipped inputs: ``examples/line.toml`` (``swatch
calibrate examples/coupons.csv``), the lines the guides quote from a command's output (a ``text`` block
after ``<!-- docs-test: output -->``: each quoted line is replaced by the line the command prints today
that starts with the same word, the page's commands run in order in a scratch copy of the repository),
and the pictures of docs/ whose fingerprint is stale (scripts/docs_pictures.py). tests/test_docs_commands.py
and tests/test_examples_current.py fail when any of them is stale.

Every measurement is made by an independent route, not by swatch's own optics or colorimetry: spectra by
Byrnes' ``tmm.coh_tmm`` on the half-vector facet (tests/synthetic.py), averaged over the film's thickness
spread by Gauss–Legendre quadrature where the line has one, and CIELAB by ``colour.sd_to_XYZ`` (ASTM E308).

* ``part.glb`` — a knob (a fluted cylinder with a domed cap on a round base), for ``swatch render --mesh``.
* ``coupons.csv`` — 30 coupons of a simulated anodising line at 8–100 V, CIELAB at 45:0, D65, 10°
  (the file ``scripts/simulate_coupons.py`` writes: TiO2-Franta on Ti-Palm, a knee at 45 V, 3.5 % spread,
  0.3 noise, one mislabelled coupon), for ``swatch calibrate``.
* ``line.toml`` — that line's process profile as ``swatch calibrate examples/coupons.csv`` writes it.
* ``parts.cxf`` — five parts anodised on that line, aimed at 51.2 nm (the spec for ``#2579b8`` on
  ``line.toml``) and landing at +0, +0.5, −0.6 and +3 nm, and a fifth at 51.4 nm under a warm, absorbing
  deposit (a contaminated rinse: its reflectance × 0.55–1.0 rising from blue to red), whose colour no
  thickness gives, measured by a multi-angle instrument (light 45°, aspecular −15°, 15°, 25°, 45°, 75°,
  110°; spectra 380–730 nm at 10 nm; D65, 10°): CxF3, XSD-valid.
* ``parts-i1.txt`` — the same five parts at 45/0 only, in X-Rite i1Profiler's CGATS.17 export layout
  (CIELAB and spectra, D65, 10°).
* ``sky.hdr`` — a small equirectangular sky (Radiance HDR, 128 × 64, y up): a blue gradient over a grey
  ground with a sun 35° up, for ``--environment FILE``.
* ``sample.cxf`` — one multi-angle measurement of the paper's blue plate (50.8 nm of TiO2-Siefke on
  Ti-Johnson), for ``swatch match --measurement``.
"""
from __future__ import annotations

import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import colour
import numpy as np
import trimesh

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
from tests.synthetic import tmm_half_vector_reflectance, write_multi_angle_cxf  # noqa: E402

OUT = ROOT / "examples"
WL = np.arange(380.0, 731.0, 10.0)
ASPECULAR = (-15.0, 15.0, 25.0, 45.0, 75.0, 110.0)
LINE = {"film": "TiO2-Franta", "substrate": "Ti-Palm", "spread": 0.035}  # scripts/simulate_coupons.py
PARTS_NM = {"P1": 51.2, "P2": 51.7, "P3": 50.6, "P4": 54.2, "P5": 51.4}
#: P5's deposit: a factor on its reflectance, 0.55 in the blue to 1.0 in the red (no film thickness gives it).
TINT = {"P5": 0.55 + 0.45 * (WL - WL[0]) / (WL[-1] - WL[0])}
SAMPLE_NM = 50.8


def knob() -> trimesh.Trimesh:
    """A knob, y up: a round base, a fluted grip and a domed cap (about 2 000 triangles)."""
    base = trimesh.creation.cylinder(radius=1.0, height=0.25, sections=64)
    base.apply_translation([0, 0, 0.125])
    grip = trimesh.creation.cylinder(radius=0.62, height=0.9, sections=48)
    grip.apply_translation([0, 0, 0.7])
    v = grip.vertices
    angle = np.arctan2(v[:, 1], v[:, 0])
    v[:, :2] *= (1.0 + 0.06 * np.cos(12.0 * angle))[:, None]  # twelve flutes
    grip.vertices = v
    cap = trimesh.creation.icosphere(subdivisions=3, radius=0.62)
    cap.vertices[:, 2] = 1.15 + 0.45 * np.maximum(cap.vertices[:, 2], 0.0)
    knob = trimesh.util.concatenate([base, grip, cap])
    knob.apply_transform(trimesh.transformations.rotation_matrix(-np.pi / 2, [1, 0, 0]))  # z up -> y up
    return knob


def reflectance(d_nm: float, light_deg: float, view_deg: float, film=None, substrate=None, spread=0.0):
    """tmm's half-vector reflectance (W,) at one in-plane geometry (view < 0: the light's side), averaged
    over a normal thickness distribution of 1σ = spread × d by 12-point Gauss–Legendre over ±4σ."""
    kw = {} if film is None else {"film": film, "substrate": substrate}
    azimuth = None if view_deg >= 0 else 0.0
    if spread == 0.0:
        return tmm_half_vector_reflectance(d_nm, [light_deg], [abs(view_deg)], WL, view_azimuth_deg=azimuth, **kw)[0]
    x, w = np.polynomial.legendre.leggauss(12)
    ts = d_nm + 4.0 * spread * d_nm * x
    ww = w * np.exp(-0.5 * (4.0 * x) ** 2)
    rows = [tmm_half_vector_reflectance(t, [light_deg], [abs(view_deg)], WL, view_azimuth_deg=azimuth, **kw)[0]
            for t in ts]
    return np.tensordot(ww / ww.sum(), np.stack(rows), axes=1)


def lab_d65_10(R) -> np.ndarray:
    cmfs = colour.MSDS_CMFS["CIE 1964 10 Degree Standard Observer"]
    ill = colour.SDS_ILLUMINANTS["D65"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # colour-science notes that 10 nm data is interpolated (ASTM E308)
        XYZ = colour.sd_to_XYZ(colour.SpectralDistribution(R, WL), cmfs, ill) / 100.0
    return colour.XYZ_to_Lab(XYZ, colour.CCS_ILLUMINANTS["CIE 1964 10 Degree Standard Observer"]["D65"])


def multi_angle_cxf(path: Path, parts: dict[str, float], creator: str, **line) -> None:
    """A multi-angle CxF3 document (spectra per BRDF angle, D65 / 10°), validated against the CxF3 XSD."""
    spectra = {name: np.stack([reflectance(d, 45.0, 45.0 - a, **line) * TINT.get(name, 1.0) for a in ASPECULAR])
               for name, d in parts.items()}
    write_multi_angle_cxf(path, spectra, ASPECULAR, WL, creator)


def i1profiler_parts(path: Path) -> None:
    """The parts at 45/0 in i1Profiler's CGATS.17 layout: CIELAB and spectra (fractions), D65 / 10°."""
    R = np.stack([reflectance(d, 45.0, 0.0, **LINE) * TINT.get(name, 1.0) for name, d in PARTS_NM.items()])
    lines = ["CGATS.17", 'ORIGINATOR "X-Rite i1Profiler"', 'DESCRIPTOR "Anodised parts, order 2026-12"',
             'CREATED "December 1, 2026"', 'INSTRUMENTATION "i1Pro 3"', 'INSTRUMENT_SERIAL_NUMBER "000000"',
             'MEASUREMENT_SOURCE "Illumination=D65\tObserverAngle=10\tWhiteBase=Abs\tFilter=No"',
             'MEASUREMENT_GEOMETRY "45/0"', "", f"NUMBER_OF_FIELDS {5 + WL.size}", "BEGIN_DATA_FORMAT",
             "SampleID SAMPLE_NAME LAB_L LAB_A LAB_B " + " ".join(f"nm{round(w)}" for w in WL),
             "END_DATA_FORMAT", "", f"NUMBER_OF_SETS {len(PARTS_NM)}", "BEGIN_DATA"]
    for k, (name, r) in enumerate(zip(PARTS_NM, R, strict=True)):
        lines.append(f"{k + 1} {name} " + " ".join(f"{x:.4f}" for x in lab_d65_10(r)) + " "
                     + " ".join(f"{x:.6f}" for x in r))
    lines += ["END_DATA", ""]
    path.write_text("\n".join(lines), encoding="utf-8")


def sky_hdr(path: Path) -> None:
    """A 128 × 64 equirectangular sky (rows from the zenith down): gradient, ground, a sun 35° up."""
    import OpenImageIO as oiio

    h, w = 64, 128
    elevation = np.radians(90.0 - (np.arange(h) + 0.5) * 180.0 / h)[:, None]
    azimuth = np.radians((np.arange(w) + 0.5) * 360.0 / w - 180.0)[None, :]
    up = np.clip(np.sin(elevation), 0.0, 1.0)
    sky = np.stack([0.35 + 0.25 * (1 - up), 0.55 + 0.2 * (1 - up), 0.95 + 0.0 * up], -1) * np.ones((1, w, 1))
    ground = np.full((h, w, 3), 0.18)
    img = np.where((elevation > 0)[..., None], sky, ground)
    sun = np.array([np.cos(np.radians(35.0)) * np.sin(np.radians(40.0)), np.sin(np.radians(35.0)),
                    np.cos(np.radians(35.0)) * np.cos(np.radians(40.0))])
    d = np.stack(np.broadcast_arrays(np.cos(elevation) * np.sin(azimuth), np.sin(elevation),
                                     np.cos(elevation) * np.cos(azimuth)), -1)
    img = img + 200.0 * (d @ sun > np.cos(np.radians(4.0)))[..., None]
    out = oiio.ImageOutput.create(str(path))
    out.open(str(path), oiio.ImageSpec(w, h, 3, "float"))
    out.write_image(img.astype(np.float32))
    out.close()


def line_profile() -> None:
    """``examples/line.toml``: the profile ``swatch calibrate examples/coupons.csv`` writes today."""
    (OUT / "line.toml").unlink(missing_ok=True)
    subprocess.run([sys.executable, "-m", "swatch.cli", "calibrate", "examples/coupons.csv", "--out",
                    "examples/line.toml"], check=True, cwd=ROOT, stdout=subprocess.DEVNULL)


def quoted_outputs() -> None:
    """Rewrite the lines the guides quote from a command's output with what the command prints today."""
    import tempfile

    from tests.cli_helpers import run_swatch
    from tests.test_docs_commands import PAGES, page_commands

    for page in PAGES:
        commands = [c for c in page_commands(page) if c.run]
        if not any(c.quoted for c in commands):
            continue
        lines = page.read_text(encoding="utf-8").split("\n")
        with tempfile.TemporaryDirectory() as tmp:
            shutil.copytree(OUT, Path(tmp) / "examples")
            shutil.copytree(ROOT / "catalog", Path(tmp) / "catalog")
            for c in commands:
                printed = run_swatch(*c.argv, cwd=tmp).stdout.splitlines()
                for q in c.quoted:
                    key = q.split()[0]
                    now = next((ln.rstrip() for ln in printed if ln.split()[:1] == [key]), None)
                    if now is None:
                        raise SystemExit(f"{page.name}: `{c.text}` prints no line starting {key!r} any more")
                    lines = [now if ln.rstrip() == q else ln for ln in lines]
        page.write_text("\n".join(lines), encoding="utf-8")
        print(f"{page.relative_to(ROOT)}: quoted outputs refreshed")


def stale_pictures() -> None:
    """Remake the pictures of docs/ whose fingerprint no longer matches (scripts/docs_pictures.py)."""
    import json

    sys.path.insert(0, str(ROOT / "scripts"))
    import docs_pictures

    record = json.loads(docs_pictures.RECORD.read_text(encoding="utf-8"))
    stale = [n for n in docs_pictures.PICTURES if record.get(n, {}).get("fingerprint") != docs_pictures.fingerprint(n)]
    if stale:
        docs_pictures.main(stale)


def outputs() -> None:
    """Every shipped output made from the shipped inputs (see the module docstring)."""
    line_profile()
    quoted_outputs()
    stale_pictures()


def main() -> None:
    if sys.argv[1:] == ["--outputs"]:
        outputs()
        return
    knob().export(OUT / "part.glb")
    shutil.copyfile(ROOT / "tests" / "data" / "simulated-line-coupons.csv", OUT / "coupons.csv")
    line_profile()
    multi_angle_cxf(OUT / "parts.cxf", PARTS_NM, "a multi-angle spectrophotometer (simulated: tmm)", **LINE)
    i1profiler_parts(OUT / "parts-i1.txt")
    sky_hdr(OUT / "sky.hdr")
    multi_angle_cxf(OUT / "sample.cxf", {"blue-plate": SAMPLE_NM}, "a multi-angle spectrophotometer (simulated: tmm)")
    print("written: " + ", ".join(sorted(p.name for p in OUT.iterdir())))
    quoted_outputs()
    stale_pictures()


if __name__ == "__main__":
    main()
