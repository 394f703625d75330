"""What every render and angular map says about itself: its file stem, the reference colour and
the metadata common to both (materials, illuminant, observer, model, roughness, software)."""
from __future__ import annotations

import numpy as np

from swatch.colorimetry.colorimeter import get_colorimeter
from swatch.core.errors import SwatchError
from swatch.core.version import __version__
from swatch.physics.model import get_coating

__all__ = ["REFERENCE_GEOMETRY", "file_stem", "reference_Lab", "common_metadata", "coating_and_colorimeter",
           "with_voltage", "voltage_note", "file_stems"]

REFERENCE_GEOMETRY = (45.0, 0.0)  # light 45°, view along the normal


def coating_and_colorimeter(coating, colorimeter):
    """The given coating and colorimeter, the defaults for None; they must share a wavelength grid.

    Parameters
    ----------
    coating : swatch.physics.model.Coating or None
        None: the default film on the default substrate (:func:`swatch.physics.model.get_coating`).
    colorimeter : swatch.colorimetry.colorimeter.Colorimeter or None
        None: D65 and the CIE 1964 10° observer on the coating's grid
        (:func:`swatch.colorimetry.colorimeter.get_colorimeter`).

    Returns
    -------
    (swatch.physics.model.Coating, swatch.colorimetry.colorimeter.Colorimeter)
        The coating and the colorimeter, on the same wavelength grid (nm).

    Raises
    ------
    swatch.core.errors.SwatchError
        The two have different wavelength grids.
    """
    if coating is None:

        coating = get_coating()
    if colorimeter is None:

        colorimeter = get_colorimeter(coating.wavelength_nm)
    if not np.array_equal(np.asarray(colorimeter.wavelength_nm), np.asarray(coating.wavelength_nm)):
        raise SwatchError("the colorimeter and the coating must use the same wavelength grid")
    return coating, colorimeter


def file_stem(kind: str, thickness_nm: float) -> str:
    """The file stem of a render: the kind and the thickness to 0.1 nm, zero-padded to sort.

    Parameters
    ----------
    kind : str
        The shape or ``angular``.
    thickness_nm : float
        Film thickness, nm.

    Returns
    -------
    str
        ``<kind>_<d>nm`` with the thickness zero-padded to sort (``flat_050.8nm``).

    Examples
    --------
    >>> file_stem("cylinder", 50.8)
    'cylinder_050.8nm'
    """
    return f"{kind}_{float(thickness_nm):05.1f}nm"


def file_stems(kind: str, thickness_nm) -> list[str]:
    """:func:`file_stem` of each thickness; two thicknesses with one stem are refused.

    Parameters
    ----------
    kind : str
        The file's kind (a shape name, ``angular``, ``mesh``).
    thickness_nm : array_like
        nm.

    Returns
    -------
    list of str
        One stem per thickness, distinct.

    Raises
    ------
    swatch.core.errors.SwatchError
        Two thicknesses round to the same 0.1 nm name.
    """
    stems = [file_stem(kind, x) for x in np.atleast_1d(thickness_nm)]
    if len(set(stems)) != len(stems):
        raise SwatchError("two thicknesses round to the same 0.1 nm file name; give distinct thicknesses")
    return stems


def reference_Lab(thickness_nm: float, coating, colorimeter) -> np.ndarray:
    """CIELAB at the reference geometry 45°:0° (the half-vector reflectance, the paper's model).

    Parameters
    ----------
    thickness_nm : float
        Film thickness, nm.
    coating : swatch.physics.model.Coating
        The film on its substrate.
    colorimeter : swatch.colorimetry.colorimeter.Colorimeter
        Illuminant and observer of the result.

    Returns
    -------
    numpy.ndarray, shape (3,)
        CIELAB at the reference geometry 45:0 under the colorimeter's illuminant and observer.
    """
    refl, _ = coating.half_vector(float(thickness_nm), *REFERENCE_GEOMETRY)
    return colorimeter.Lab(colorimeter.XYZ(refl.R))


def common_metadata(d: float, coating, colorimeter, model: str, distribution: str, roughness_alpha: float) -> dict:
    """Metadata shared by renders and angular maps (materials, colorimetry, model, reference CIELAB, software).

    No voltage: only the caller knows the process (its growth law, or none) and writes the voltage
    once, with :func:`with_voltage` (issue 17).

    Parameters
    ----------
    d : float
        Oxide thickness, nm.
    coating : swatch.physics.model.Coating
        The film on its substrate (names, index scale, spread).
    colorimeter : swatch.colorimetry.colorimeter.Colorimeter
        Illuminant and observer of the reference Lab.
    model, distribution : str
        The shading model and microfacet distribution.
    roughness_alpha : float
        Microfacet α (recorded as ``roughness``).

    Returns
    -------
    dict
        The metadata every render carries: thickness, film, substrate, illuminant, observers, model, distribution,
        roughness, the reference geometry's CIELAB, software.
    """

    return {
        "thickness_nm": round(d, 6),
        "film": coating.film,
        "substrate": coating.substrate,
        "illuminant": colorimeter.illuminant,
        "observer": f"CIE {'1964 10' if colorimeter.observer == '10' else '1931 2'} deg",
        "rgb_observer": "CIE 1931 2 deg (display RGB is defined on it; Lab uses the observer above)",
        "model": model,
        "distribution": distribution if model == "microfacet" else "none (facet probability constant)",
        "roughness": roughness_alpha,
        "reference_geometry": "45:0 (light 45 deg, view along the normal), paper model",
        "Lab_reference": [round(float(x), 4) for x in reference_Lab(d, coating, colorimeter)],
        "software": f"swatch {__version__}",
    }


def voltage_note(proc, given: bool, known: bool) -> str:
    """How an image's voltage was obtained, by the process profile's growth law.

    Parameters
    ----------
    proc : swatch.physics.process.Process
        The process profile (its growth law).
    given : bool
        The user gave the voltage (the thickness came from it).
    known : bool
        The profile has a growth rate.

    Returns
    -------
    str
        How the voltage in the metadata was obtained (given, from the growth law, or unknown).
    """
    law = (f"{proc.nm_per_V:g} nm/V + {proc.offset_nm:g} nm (process {proc.label})" if proc.has_growth_law
           else f"process {proc.label}")
    if given:
        return f"given; thickness from it at {law}"
    return f"estimated from the thickness at {law}" if known else f"no growth rate in {law}"


def with_voltage(meta: dict, voltage_V: float, note: str, proc) -> dict:
    """A copy of ``meta`` with the voltage right after the thickness, how it was obtained and the profile's metadata.

    Parameters
    ----------
    meta : dict
        :func:`common_metadata`.
    voltage_V : float
        V; NaN when unknown (written as None).
    note : str
        :func:`voltage_note`.
    proc : swatch.physics.process.Process
        The process profile (recorded in the metadata).

    Returns
    -------
    dict
        ``meta`` with ``voltage_V`` (V, or None), its note and the process.
    """
    volts = {"voltage_V": round(float(voltage_V), 6) if np.isfinite(voltage_V) else None, "voltage_note": note}
    out: dict = {}
    for key, value in meta.items():
        out[key] = value
        if key == "thickness_nm":  # the voltage right after the thickness, where readers find it
            out.update(volts)
    meta = out | volts
    meta.update({k: (round(v, 9) if isinstance(v, float) else v) for k, v in proc.metadata().items()})
    return meta
