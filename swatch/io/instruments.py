"""Measurements as instruments export them: the common part of the CGATS, CxF3 and CSV readers.

An instrument file holds one or many *samples* (parts, coupons, patches), each with CIELAB or a reflectance spectrum
at one or several geometries, and may state the illuminant, observer and geometry it was measured or computed under.
What the file states is used; an explicit command-line value must agree with it (:func:`check_agrees`), or the file
is refused in one line. CIELAB needs a white point: the file's illuminant and observer, else the explicit options.

Every value is checked before use (finite, CIELAB within range, reflectance within the limits of
:mod:`swatch.core.limits`); sizes and counts are capped before memory is spent.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np

from swatch.colorimetry.colorimeter import illuminant_names
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_LAB_AB, MAX_REFLECTANCE, MIN_PEAK_REFLECTANCE, MIN_REFLECTANCE
from swatch.io.measurements import PERCENT_THRESHOLD, LabMeasurement, SpectralMeasurement, check_spectral_axis
from swatch.physics import geometry

__all__ = ["Request", "Sample", "InstrumentFile", "parse_geometry_text", "parse_observer", "parse_illuminant",
           "lab_sample", "spectral_sample", "check_agrees", "check_lab", "geometry_name"]

_DIFFUSE = re.compile(r"^\s*(d|di|de|8)\s*[:/]\s*(d|di|de|8)\s*$", re.IGNORECASE)
_DIRECTIONAL = re.compile(r"^\s*(\d+(?:\.\d+)?)\s*°?\s*[acx]?\s*[:/]\s*(\d+(?:\.\d+)?)\s*°?\s*[acx]?\s*$",
                          re.IGNORECASE)


@dataclass(frozen=True)
class Request:
    """What the command line says about a measurement file, and which of it was given explicitly.

    Attributes
    ----------
    light_deg, view_deg : float
        The geometry for files that state none, polar angles from the normal, degrees.
    light_azimuth_deg : float
        The light's azimuth, degrees.
    view_azimuth_deg : float or None
        The view's azimuth, degrees (None: the opposite side).
    illuminant, observer : str
        Colorimetry for files that state none (CIE illuminant name; ``"2"`` or ``"10"``).
    percent : bool or None
        Reflectance in percent (True), as a fraction (False) or detected (None).
    given : frozenset of str
        Which of ``"geometry"``, ``"illuminant"``, ``"observer"`` were explicit (a file contradicting one is refused).
    """

    light_deg: float = 45.0
    view_deg: float = 0.0
    light_azimuth_deg: float = 0.0
    view_azimuth_deg: float | None = None
    illuminant: str = "D65"
    observer: str = "10"
    percent: bool | None = None
    given: frozenset[str] = frozenset()


@dataclass(frozen=True)
class Sample:
    """One measured part.

    Attributes
    ----------
    id : str
        The sample's name in the file.
    measurement : swatch.io.measurements.SpectralMeasurement or swatch.io.measurements.LabMeasurement
        One or several geometries.
    voltage_V : float or None
        The anodising voltage, V, when the file gives it (coupons).
    thickness_nm : float or None
        The oxide thickness, nm, when the file gives it.
    """

    id: str
    measurement: SpectralMeasurement | LabMeasurement
    voltage_V: float | None = None
    thickness_nm: float | None = None


@dataclass(frozen=True)
class InstrumentFile:
    """The samples of one file with the colorimetry they are to be read under.

    Attributes
    ----------
    source : str
        The file's name (for messages).
    format : str
        ``"csv"``, ``"cgats"`` or ``"cxf3"``.
    samples : tuple of Sample
        Measured alike (:func:`same_geometries`).
    illuminant, observer : str
        The file's where it states them, else the command line's.
    stated : dict
        What the file itself states (``illuminant``, ``observer``, ``geometry``), for reports.
    """

    source: str
    format: str  # "csv", "cgats", "cxf3"
    samples: tuple[Sample, ...]
    illuminant: str
    observer: str
    stated: dict = field(default_factory=dict)

    @property
    def kind(self) -> str:
        """``"colour"`` (CIELAB samples) or ``"spectrum"``.

        Returns
        -------
        str
            Which kind of measurement every sample holds.
        """
        return "colour" if isinstance(self.samples[0].measurement, LabMeasurement) else "spectrum"


def geometry_name(light_deg: float, view_deg: float, same_side: bool = False) -> str:
    """The name of an in-plane geometry: ``45:0`` (view across the normal) or ``45:-15`` (the light's side).

    Parameters
    ----------
    light_deg, view_deg : float
        Polar angles from the normal, degrees.
    same_side : bool
        The view is on the light's side.

    Returns
    -------
    str
        ``light:view`` in degrees, the view negative on the light's side.

    Examples
    --------
    >>> geometry_name(45, 0), geometry_name(45, 15, same_side=True)
    ('45:0', '45:-15')
    """
    return f"{light_deg:g}:{-view_deg if same_side and view_deg else view_deg:g}"


def parse_geometry_text(text: str, source: str) -> tuple[float, float]:
    """(light_deg, view_deg) of a directional geometry as files write it: ``45/0``, ``0:45``, ``45°a:0°`` (annular).

    Parameters
    ----------
    text : str
        The file's geometry statement.
    source : str
        Names the file in messages.

    Returns
    -------
    (float, float)
        Illumination and viewing polar angles from the normal, degrees.

    Raises
    ------
    swatch.core.errors.SwatchError
        A diffuse geometry (``d/8``: the model is directional), an unreadable text, or an angle ≥ 90°.

    Examples
    --------
    >>> parse_geometry_text("45°a:0°", "x.txt")
    (45.0, 0.0)
    """
    t = str(text).strip().split("(")[0].strip()
    if _DIFFUSE.match(t) or t.lower().startswith(("d/", "d:", "di", "de")):
        raise SwatchError(f"{source}: geometry {text!r} is a diffuse (sphere) geometry; swatch models directional "
                          "geometries such as 45/0 (measure with a 45/0 or multi-angle instrument)")
    m = _DIRECTIONAL.match(t)
    if not m:
        raise SwatchError(f"{source}: geometry {text!r} is not understood; write it as LIGHT/VIEW in degrees "
                          "from the normal, e.g. 45/0")
    light, view = float(m.group(1)), float(m.group(2))
    for what, a in (("illumination", light), ("viewing", view)):
        if not a < 90:
            raise SwatchError(f"{source}: geometry {text!r}: the {what} angle must be below 90°")
    return light, view


def parse_observer(text: str, source: str) -> str:
    """``"2"`` or ``"10"`` from ``2``, ``2°``, ``2_Degree``, ``CIE 1931 2 degree``, ``10 deg`` …

    Parameters
    ----------
    text : str
        The file's observer statement.
    source : str
        Names the file in messages.

    Returns
    -------
    str
        The observer's field of view, degrees: ``"2"`` (CIE 1931) or ``"10"`` (CIE 1964).

    Raises
    ------
    swatch.core.errors.SwatchError
        Neither observer is recognised.

    Examples
    --------
    >>> parse_observer("CIE 1964 10 degree", "x"), parse_observer("2_Degree", "x")
    ('10', '2')
    """
    t = str(text).lower()
    if "1964" in t or re.search(r"(^|[^0-9])10([^0-9]|$)", t):
        return "10"
    if "1931" in t or re.search(r"(^|[^0-9])2([^0-9]|$)", t):
        return "2"
    raise SwatchError(f"{source}: observer {text!r} is not understood; the CIE observers are 2° (1931) and 10° (1964)")


def parse_illuminant(text: str, source: str) -> str:
    """A CIE illuminant name as colour-science spells it, from how files write it (``Illuminant D65``, ``F11`` → ``FL11``).

    Parameters
    ----------
    text : str
        The file's illuminant statement.
    source : str
        Names the file in messages.

    Returns
    -------
    str
        The name as :func:`swatch.colorimetry.colorimeter.illuminant_names` spells it (``D65``, ``FL11`` …).

    Raises
    ------
    swatch.core.errors.SwatchError
        Not a CIE illuminant colour-science knows.

    Examples
    --------
    >>> parse_illuminant("Illuminant d50", "x"), parse_illuminant("F11", "x")
    ('D50', 'FL11')
    """
    t = str(text).strip().upper().replace("ILLUMINANT", "").replace("CIE", "").strip(" ,_")
    m = re.fullmatch(r"F(\d+)", t)
    if m:
        t = f"FL{m.group(1)}"
    names = {n.upper(): n for n in illuminant_names()}
    if t not in names:
        raise SwatchError(f"{source}: illuminant {text!r} is not a CIE illuminant swatch knows "
                          "(D50, D65, A, FL2, FL11, ...)")
    return names[t]


def check_agrees(source: str, what: str, stated, where: str, request: Request, given_key: str, cli_value,
                 option: str) -> None:
    """Refuse a file whose stated condition contradicts an explicit command-line option.

    Parameters
    ----------
    source : str
        Names the file.
    what : str
        The condition, for the message (``geometry``, ``illuminant``, ``observer``).
    stated : tuple of float, str or None
        What the file states ((light_deg, view_deg) for a geometry); None: nothing, nothing to check.
    where : str
        Where the file states it, for the message.
    request : Request
        The command line.
    given_key : str
        The key of ``request.given`` that says whether the option was explicit.
    cli_value : tuple of float or str
        The option's value.
    option : str
        The parameter's name in backquotes (```illuminant```, ```light_deg```/```view_deg```), for the
        message: the CLI speaks it as its flag (:mod:`swatch.commands.flags`).

    Returns
    -------
    None

    Raises
    ------
    swatch.core.errors.SwatchError
        The explicit option and the file disagree (angles to 1e-6°, names case-insensitively).
    """
    if stated is None or given_key not in request.given:
        return
    same = (abs(stated[0] - cli_value[0]) < 1e-6 and abs(stated[1] - cli_value[1]) < 1e-6
            if isinstance(stated, tuple) else str(stated).upper() == str(cli_value).upper())
    if not same:
        shown = geometry_name(*stated) if isinstance(stated, tuple) else stated
        cli = geometry_name(*cli_value) if isinstance(cli_value, tuple) else cli_value
        raise SwatchError(f"{source}: the file states {what} {shown} ({where}) but {option} {cli} was given; leave it "
                          f"out to use the file's, or measure under {cli}")


def _finite(values: np.ndarray, source: str, sample_id: str, what: str) -> None:
    bad = np.flatnonzero(~np.isfinite(values.reshape(values.shape[0], -1)).all(axis=1))
    if bad.size:
        raise SwatchError(f"{source}: sample {sample_id!r}: {what} is not a finite number (NaN or infinite); "
                          "every value must be a number")


def _geometry_arrays(geometries):
    """(light, |view|, light_az, view_az) from (light_deg, signed view_deg) pairs (negative: light's side)."""
    g = np.asarray(geometries, dtype=np.float64).reshape(-1, 2)
    light, view = g[:, 0], g[:, 1]
    return light, np.abs(view), np.zeros_like(light), np.where(view < 0, 0.0, 180.0)


def check_lab(source: str, sample_id: str, Lab) -> np.ndarray:
    """CIELAB values checked: finite, L* in [0, 100], |a*|, |b*| ≤ :data:`swatch.core.limits.MAX_LAB_AB`.

    Parameters
    ----------
    source, sample_id : str
        The file and the sample, for messages.
    Lab : array_like, shape (..., 3)
        CIELAB values.

    Returns
    -------
    numpy.ndarray, shape (G, 3)
        The values as float64 rows (a value not finite or out of range: SwatchError).
    """
    Lab = np.asarray(Lab, dtype=np.float64).reshape(-1, 3)
    _finite(Lab, source, sample_id, "a CIELAB value")
    if np.any((Lab[:, 0] < 0) | (Lab[:, 0] > 100)):
        raise SwatchError(f"{source}: sample {sample_id!r}: L* {Lab[:, 0].max():g} is outside [0, 100]")
    if np.any(np.abs(Lab[:, 1:]) > MAX_LAB_AB):
        raise SwatchError(f"{source}: sample {sample_id!r}: a* and b* must lie within ±{MAX_LAB_AB:g}")
    return Lab


def lab_sample(source: str, sample_id: str, geometries, Lab, voltage_V=None, thickness_nm=None) -> Sample:
    """A CIELAB sample at in-plane geometries, validated.

    Parameters
    ----------
    source, sample_id : str
        The file and the sample, for messages.
    geometries : sequence of (float, float)
        (light_deg, signed view_deg) per geometry (negative view: the light's side), degrees.
    Lab : array_like, shape (G, 3)
        CIELAB: L* in [0, 100], |a*|, |b*| ≤ :data:`swatch.core.limits.MAX_LAB_AB`.
    voltage_V, thickness_nm : float or None
        Labels of a coupon, V and nm.

    Returns
    -------
    Sample
        Its measurement (one geometry per row) and the coupon labels.

    Raises
    ------
    swatch.core.errors.SwatchError
        A value not finite or out of range, a repeated geometry, or an angle outside [0, 90).
    """
    Lab = check_lab(source, sample_id, Lab)
    light, view, la, va = _geometry_arrays(geometries)
    _check_unique(source, sample_id, light, view, va)
    m = LabMeasurement(f"{source}#{sample_id}", light, view, la, va, Lab)
    return Sample(str(sample_id), m, voltage_V, thickness_nm)


def spectral_sample(source: str, sample_id: str, geometries, wavelength_nm, reflectance, percent: bool | None,
                    voltage_V=None, thickness_nm=None) -> Sample:
    """A spectral sample, validated (reflectance converted to a fraction).

    Parameters
    ----------
    source, sample_id : str
        The file and the sample, for messages.
    geometries : sequence of (float, float)
        (light_deg, signed view_deg) per geometry, degrees.
    wavelength_nm : array_like, shape (W,)
        The axis, nm, as :func:`swatch.io.measurements.check_spectral_axis` allows it (two or more, finite,
        strictly increasing, inside the measured range).
    reflectance : array_like, shape (G, W)
        Reflectance factors, as a fraction or in percent.
    percent : bool or None
        Percent (True), fraction (False), or detected (None: percent when a value exceeds 1.5).
    voltage_V, thickness_nm : float or None
        Labels of a coupon, V and nm.

    Returns
    -------
    Sample
        Its measurement (reflectance as a fraction) and the coupon labels.

    Raises
    ------
    swatch.core.errors.SwatchError
        Non-finite values, a wavelength axis :func:`swatch.io.measurements.check_spectral_axis` refuses,
        reflectance outside the caps of :mod:`swatch.core.limits` or implausibly dark, a repeated geometry, or an angle outside [0, 90).
    """
    wl = check_spectral_axis(wavelength_nm, source, what=f"sample {sample_id!r}: wavelengths")
    R = np.asarray(reflectance, dtype=np.float64).reshape(-1, wl.size)
    _finite(R, source, sample_id, "a reflectance value")
    detected = percent is None
    is_percent = bool(np.max(R) > PERCENT_THRESHOLD) if percent is None else bool(percent)
    if is_percent:
        R = R / 100.0
    if np.min(R) < MIN_REFLECTANCE or np.max(R) > MAX_REFLECTANCE:
        raise SwatchError(f"{source}: sample {sample_id!r}: reflectance outside [{MIN_REFLECTANCE:g}, "
                          f"{MAX_REFLECTANCE:g}] (as a fraction)")
    if not np.max(R) >= MIN_PEAK_REFLECTANCE:
        raise SwatchError(f"{source}: sample {sample_id!r}: the largest reflectance is {np.max(R):.3g}: implausibly "
                          f"dark for a measurement (at least {MIN_PEAK_REFLECTANCE:g} as a fraction)")
    light, view, la, va = _geometry_arrays(geometries)
    _check_unique(source, sample_id, light, view, va)
    m = SpectralMeasurement(f"{source}#{sample_id}", light, view, la, va, wl, R, percent=is_percent,
                            unit_detected=detected)
    return Sample(str(sample_id), m, voltage_V, thickness_nm)


def _check_unique(source, sample_id, light, view, va) -> None:
    key = {(round(float(a), 6), round(float(b), 6), float(c)) for a, b, c in zip(light, view, va, strict=True)}
    if len(key) != light.size:
        raise SwatchError(f"{source}: sample {sample_id!r} has one geometry twice; give each geometry once")
    bad = np.flatnonzero(~((light >= 0) & (light < 90) & (view < 90)))
    if bad.size:
        raise SwatchError(f"{source}: sample {sample_id!r}: geometry light {light[bad[0]]:g}° view {view[bad[0]]:g}° "
                          "is outside [0, 90) degrees from the normal")


def aspecular_geometry(light_deg: float, aspecular_deg: float, source: str) -> tuple[float, float]:
    """(light_deg, signed view_deg) of a multi-angle geometry (ASTM E2194: aspecular angle from the specular).

    Parameters
    ----------
    light_deg : float
        Illumination polar angle, degrees.
    aspecular_deg : float
        Aspecular angle, degrees (towards the light is positive).
    source : str
        Names the file in messages.

    Returns
    -------
    (float, float)
        Negative view: on the light's side.

    Raises
    ------
    swatch.core.errors.SwatchError
        The view falls outside (−90°, 90°) or the light outside [0°, 90°).

    Examples
    --------
    >>> aspecular_geometry(45.0, 15.0, "x"), aspecular_geometry(45.0, 110.0, "x")
    ((45.0, 30.0), (45.0, -65.0))
    """
    v = float(geometry.aspecular_view_deg(light_deg, aspecular_deg))
    if not (math.isfinite(v) and abs(v) < 90 and 0 <= light_deg < 90):
        raise SwatchError(f"{source}: multi-angle geometry light {light_deg:g}°, aspecular {aspecular_deg:g}° puts the "
                          "view outside (-90, 90) degrees")
    return float(light_deg), v


def same_geometries(samples: tuple[Sample, ...], source: str) -> None:
    """Refuse a file whose samples share a name or were not measured alike (geometries, quantities).

    Parameters
    ----------
    samples : tuple of Sample
        The file's samples.
    source : str
        Names the file.

    Returns
    -------
    None

    Raises
    ------
    swatch.core.errors.SwatchError
        Two samples share a name (one name, one part), differ in geometry (to 0.001°) or mix CIELAB and spectra.
    """
    ids = [s.id for s in samples]
    if len(set(ids)) != len(ids):
        twice = next(i for k, i in enumerate(ids) if i in ids[:k])
        raise SwatchError(f"{source}: sample {twice!r} appears twice; give each sample its own name (one sample, "
                          "all its geometries, per name)")
    def key(s: Sample):
        m = s.measurement
        return (type(m).__name__, tuple(np.round(m.light_deg, 3)), tuple(np.round(m.view_deg, 3)),
                tuple(m.view_azimuth_deg))
    first = key(samples[0])
    for s in samples[1:]:
        if key(s) != first:
            kind = "CIELAB and spectra" if key(s)[0] != first[0] else "different geometries"
            raise SwatchError(f"{source}: samples {samples[0].id!r} and {s.id!r} mix {kind}; a file holds samples "
                              "measured alike (one file per geometry set)")
