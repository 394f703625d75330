"""swatch: physics-based colour swatches for anodised titanium.

Thin-film interference of an anodic oxide on a metal, evaluated with the
half-vector model of Fujii et al. (IEICE Trans. Inf. & Syst. J102-D, 2019),
turned into spectra, CIELAB values, renders and catalog sheets.

The public API is listed in :data:`__all__` and loaded on first use (PEP 562), so that
``import swatch`` and ``swatch --help`` stay fast::

    >>> import swatch
    >>> coating = swatch.get_coating()                      # TiO2 on Ti, 380-780 nm
    >>> cm = swatch.get_colorimeter(coating.wavelength_nm)  # D65, CIE 1964 10° for XYZ and Lab
    >>> cm.observer, cm.display_colorimeter.observer       # display sRGB: CIE 1931 2°, always
    ('10', '2')
    >>> float(swatch.voltage_to_thickness_nm(25.0))         # the paper's growth law (nm)
    50.8

The layers below (docs/DEVNOTES.md): ``core`` → ``physics`` → ``colorimetry`` → ``io`` →
``render`` / ``fit`` / ``presets`` → ``report`` → ``catalog`` → ``commands``.
"""
from __future__ import annotations

import importlib
import warnings as _warnings

from swatch.core.version import __version__

# colour-science announces, on first use of some functions, that its plotting API needs
# Matplotlib. swatch never plots through colour-science; keep the CLI's output clean.
_warnings.filterwarnings("ignore", message='"Matplotlib" related API features are not available')

#: public name -> the module that defines it (imported when the name is first used)
_API = {
    # errors
    "SwatchError": "swatch.core.errors",
    # physics: materials, the thin-film coating on the half-vector facet, process profiles
    "Material": "swatch.physics.materials",
    "list_materials": "swatch.physics.materials",
    "load_material": "swatch.physics.materials",
    "wavelength_grid": "swatch.physics.materials",
    "Coating": "swatch.physics.model",
    "get_coating": "swatch.physics.model",
    "overcoat": "swatch.physics.overcoat",
    "voltage_to_thickness_nm": "swatch.physics.growth",
    "thickness_to_voltage_V": "swatch.physics.growth",
    "film_reflectance": "swatch.physics.optics",
    "Process": "swatch.physics.process",
    "load_process": "swatch.physics.process",
    "list_processes": "swatch.physics.process",
    # colorimetry
    "Colorimeter": "swatch.colorimetry.colorimeter",
    "get_colorimeter": "swatch.colorimetry.colorimeter",
    "delta_E_ab": "swatch.colorimetry.colorimeter",
    "delta_E_00": "swatch.colorimetry.colorimeter",
    "Lab_to_LCh": "swatch.colorimetry.colorimeter",
    "srgb_hex": "swatch.colorimetry.colorimeter",
    "hex_to_Lab_2deg": "swatch.colorimetry.colorimeter",
    "thickness_colours": "swatch.colorimetry.appearance",
    "Tolerance": "swatch.colorimetry.tolerance",
    "get_tolerance": "swatch.colorimetry.tolerance",
    # measurement files
    "read_measurement": "swatch.io.measurement_csv",
    "read_coupons": "swatch.io.coupons",
    # renders
    "render_swatch": "swatch.render.dispatch",
    "render_request": "swatch.render.request",
    "RenderRequest": "swatch.render.request",
    "SwatchImage": "swatch.render.image",
    "angular_map": "swatch.render.angular",
    "AngularMap": "swatch.render.angular",
    "get_environment": "swatch.render.environment",
    "load_mesh": "swatch.render.mesh",
    # fits
    "fit_measurement": "swatch.fit.spectral_fit",
    "fit_lab": "swatch.fit.lab_fit",
    "match_colour": "swatch.fit.matching",
    "calibrate": "swatch.fit.calibration.procedure",
    # catalogs
    "build_catalog": "swatch.catalog.build",
    "load_spec": "swatch.catalog.spec.document",
}

__all__ = ["__version__"]
__all__ += list(_API)


def __getattr__(name: str):
    """Load a public name of :data:`__all__` from its module on first use (PEP 562)."""
    module = _API.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *__all__])
