"""What the colorimetry did to a measurement's spectra, in words: :func:`swatch.fit.result.colour_grid`
interpolates spectra that are not on an ASTM E308 grid onto one, and every command that does so says it
(``fit``'s header, ``check``'s and ``match --measurement``'s notes)."""
from __future__ import annotations

import numpy as np

from swatch.fit.result import colour_grid, resampled_words
from swatch.io.instruments import InstrumentFile
from swatch.io.measurements import SpectralMeasurement

__all__ = ["resampling_note", "resampling_notes"]


def resampling_note(source: str, wavelength_nm) -> str | None:
    r"""What :func:`swatch.fit.result.colour_grid` does to a measurement's spectra, in words, when it
    interpolates them.

    Parameters
    ----------
    source : str
        Names the measurement (a file, or ``file#sample``).
    wavelength_nm : array_like, shape (W,)
        The measured wavelengths, nm, increasing.

    Returns
    -------
    str or None
        The note (the measured range, why, and the grid used), or None when the spectra are used as measured.

    Raises
    ------
    swatch.core.errors.SwatchError
        As :func:`swatch.fit.result.colour_grid`.

    Examples
    --------
    >>> resampling_note("a.csv", np.arange(400.0, 701.0, 10.0)) is None
    True
    >>> print(resampling_note("b.csv", np.arange(401.0, 751.0, 7.0)).replace("; ", ";\n"))
    b.csv: 50 wavelengths 401–744 nm, not an even 1, 5, 10 or 20 nm grid inside 360–830 nm (ASTM E308);
    colour from the spectra interpolated linearly onto 405–740 nm at 5 nm
    """
    wl = np.asarray(wavelength_nm, dtype=np.float64)
    grid, interpolated = colour_grid(wl)
    if not interpolated:
        return None
    return (f"{source}: {wl.size} wavelengths {wl[0]:g}–{wl[-1]:g} nm, "
            + resampled_words([grid[0], grid[-1], grid[1] - grid[0]]))


def resampling_notes(instrument_file: InstrumentFile) -> list[str]:
    """:func:`resampling_note` of each wavelength axis of a file's spectral samples: named by the file when its
    samples share one axis, else by the first sample on each.

    Parameters
    ----------
    instrument_file : swatch.io.instruments.InstrumentFile
        The file's samples (CIELAB samples have no axis and no note).

    Returns
    -------
    list of str
        One note per axis the colorimetry interpolates (none when every spectrum is used as measured).
    """
    axes: dict[bytes, tuple[str, np.ndarray]] = {}
    for s in instrument_file.samples:
        m = s.measurement
        if isinstance(m, SpectralMeasurement):
            axes.setdefault(m.wavelength_nm.tobytes(), (s.id, m.wavelength_nm))
    source = instrument_file.source
    notes = [resampling_note(source if len(axes) == 1 else f"{source}#{sid}", wl) for sid, wl in axes.values()]
    return [n for n in notes if n is not None]
