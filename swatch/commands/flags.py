"""The library speaks parameters, the CLI speaks flags (issue 17).

Library errors (:class:`swatch.core.errors.SwatchError`) name a parameter in backquotes, as Python
code: ```size_px``` or ```environment='point'```. :func:`speak_flags` rewrites them as the command
line's options before the CLI prints the one-line error: ```size_px``` → ``--size``,
```environment='point'``` → ``--environment point``, ```fit_scale=False``` → ``--fixed-scale``.
"""
from __future__ import annotations

import re

__all__ = ["PARAMETER_FLAGS", "speak_flags"]

#: Python parameter (or ``parameter=value``) -> command-line option.
PARAMETER_FLAGS = {
    "jobs": "--jobs",
    "scheduler": "--scheduler",
    "base_url": "--base-url",
    "angles": "--angles",
    "rank": "--rank",
    "top": "--top",
    "report_dir": "--report",
    "out_path": "--out",
    "out_dir": "--out",
    "ra_nm": "--ra",
    "nm_per_V": "--nm-per-volt",
    "process": "--process",
    "film": "--film",
    "substrate": "--substrate",
    "size_px": "--size",
    "roughness_alpha": "--roughness",
    "environment": "--environment",
    "model": "--model",
    "distribution": "--distribution",
    "background": "--background",
    "wavelength_nm": "--wavelengths",
    "exclude_mirror_deg": "--exclude-mirror",
    "fit_scale=False": "--fixed-scale",
    "force": "--force",
    "spread": "--spread",
    "engine": "--engine",
    "scheme": "--scheme",
    "spp": "--spp",
    "seed": "--seed",
    "denoise": "--denoise",
    "denoise=False": "--no-denoise",
    "device": "--device",
    "finish": "--finish",
    "timezone_h": "--sun-timezone",
    "illuminant": "--illuminant",
    "observer": "--observer",
    "thickness_nm": "--thickness",
    "voltage_V": "--voltage",
    "light_deg": "--light",
    "view_deg": "--view",
    "light_azimuth_deg": "--light-azimuth",
    "view_azimuth_deg": "--view-azimuth",
}

_QUOTED = re.compile(r"`([A-Za-z_][A-Za-z0-9_]*)(?:=([^`]*))?`")


def speak_flags(message: str) -> str:
    """``message`` with every backquoted parameter of :data:`PARAMETER_FLAGS` written as its option.

    Parameters
    ----------
    message : str
        A library error's one line.

    Returns
    -------
    str
        The same line with each backquoted name (or ``name=value``) of :data:`PARAMETER_FLAGS` replaced by its
        command-line option; other backquoted text kept.

    Examples
    --------
    >>> speak_flags("`thickness_nm` must be a number from 0 to 1000 nm (got 1200)")
    '--thickness must be a number from 0 to 1000 nm (got 1200)'
    >>> speak_flags("use a smaller `size_px`, or `environment='point'`")
    'use a smaller --size, or --environment point'
    """

    def flag(m: re.Match) -> str:
        name, value = m.group(1), m.group(2)
        if value is not None and f"{name}={value}" in PARAMETER_FLAGS:
            return PARAMETER_FLAGS[f"{name}={value}"]
        if name not in PARAMETER_FLAGS:
            return m.group(0)
        if value is None:
            return PARAMETER_FLAGS[name]
        return f"{PARAMETER_FLAGS[name]} {value.strip(chr(39) + chr(34)).replace('None', 'none')}"

    return _QUOTED.sub(flag, message)
