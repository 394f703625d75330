"""Clear layers over the oxide (a lacquer or sol-gel topcoat): ``--overcoat INDEX:NM|TABLE:NM``.

The stack ambient / overcoats / oxide / metal is reflected by the coherent transfer-matrix product
(:func:`swatch.physics.multilayer.stack_reflectance`); the oxide's thickness varies, the overcoats are
fixed, and the half-vector model (:class:`swatch.physics.model.HalfVector`) applies as for a bare film.

References
----------
.. [1] :cite:`Born1999`: §1.6.5, stratified media, the characteristic matrix.
.. [2] :cite:`Byrnes2016`: the formulation of the ``tmm`` package, the independent reference the tests compare with.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_THICKNESS_NM
from swatch.physics import optics
from swatch.physics.materials import list_materials, load_material
from swatch.physics.model import Coating, HalfVector, averaged_over_spread, check_no_amplitudes, check_thickness_nm
from swatch.physics.multilayer import stack_reflectance
from swatch.physics.spread import ThicknessSpread

__all__ = ["Overcoat", "OvercoatedCoating", "overcoat", "overcoat_json", "overcoat_text"]


@dataclass(frozen=True)
class Overcoat:
    """A clear layer over the oxide (e.g. a thin lacquer or sol-gel topcoat), treated coherently.

    Attributes
    ----------
    label : str
        A table name, or ``n=1.5`` for a constant index.
    n : numpy.ndarray
        Complex index on the coating's wavelength grid, shape (W,).
    thickness_nm : float
        The layer's thickness, nm.
    """

    label: str  # a table name, or "n=1.5" for a constant index
    n: np.ndarray  # complex index on the coating's wavelength grid
    thickness_nm: float


@dataclass(frozen=True)
class OvercoatedCoating(HalfVector):
    """Ambient / overcoats / oxide film / substrate: the oxide's thickness varies, the overcoats are
    fixed. Reflectance by the transfer-matrix product (:func:`swatch.physics.multilayer.stack_reflectance`).

    Attributes
    ----------
    base : swatch.physics.model.Coating
        The oxide on its metal (grid, indices, thickness spread).
    overcoats : tuple of Overcoat
        The clear layers, listed from the air side.

    Examples
    --------
    >>> from swatch.physics.model import get_coating
    >>> c = get_coating()
    >>> oc = OvercoatedCoating(c, (overcoat("1.5:200", c.wavelength_nm),))
    >>> oc.reflectance(50.8, 0.0).R.shape, overcoat_text(oc)
    ((81,), ' under n=1.5 200 nm')
    """

    base: Coating
    overcoats: tuple[Overcoat, ...]

    @property
    def film(self) -> str:
        """The oxide's table name.

        Returns
        -------
        str
            The base coating's film (oxide) material name, as ``swatch.physics.materials.load_material`` takes it.
        """
        return self.base.film

    @property
    def substrate(self) -> str:
        """The metal's table name.

        Returns
        -------
        str
            The base coating's substrate (metal) material name, as ``swatch.physics.materials.load_material`` takes it.
        """
        return self.base.substrate

    @property
    def wavelength_nm(self) -> np.ndarray:
        """The grid, nm, shape (W,).

        Returns
        -------
        numpy.ndarray
            The base coating's wavelength grid, nm, shape (W,).
        """
        return self.base.wavelength_nm

    @property
    def spread(self) -> ThicknessSpread:
        """The oxide's thickness spread.

        Returns
        -------
        swatch.physics.spread.ThicknessSpread
            The base coating's oxide thickness spread (σ in nm and as a fraction); the overcoats' own are uniform.
        """
        return self.base.spread

    def _stack(self, thickness_nm, incidence_deg) -> optics.Reflectance:
        return stack_reflectance(
            [o.thickness_nm for o in self.overcoats] + [thickness_nm],
            [o.n for o in self.overcoats] + [self.base.n_film],
            self.base.n_substrate, incidence_deg, self.base.wavelength_nm,
        )

    def reflectance(self, thickness_nm, incidence_deg, amplitudes: bool = False) -> optics.Reflectance:
        """Reflectance at incidence angles (degrees) on the facet, through the overcoats.

        Parameters
        ----------
        thickness_nm : array_like
            The oxide's thickness, nm (0 to ``MAX_THICKNESS_NM``).
        incidence_deg : array_like
            Incidence angle in air on the facet, degrees, broadcast with ``thickness_nm`` to S.
        amplitudes : bool, optional
            Refused with a thickness spread (the transfer matrix gives reflectances only here).

        Returns
        -------
        swatch.physics.optics.Reflectance
            Shapes S + (W,).

        Raises
        ------
        SwatchError
            For a thickness out of range, or amplitudes of a spread film.
        """
        d = check_thickness_nm(thickness_nm)
        if self.base.spread.is_zero:
            return self._stack(d, incidence_deg)
        check_no_amplitudes(amplitudes)

        def reflect(t):
            r = self._stack(t, incidence_deg)
            return r.R_s, r.R_p

        return averaged_over_spread(reflect, d, self.base)

    def reflectance_cos(self, thickness_nm, cos_incidence, amplitudes: bool = False) -> optics.Reflectance:
        """Reflectance at incidence cosines on the facet (:meth:`reflectance` at their angles).

        Parameters
        ----------
        thickness_nm : array_like
            The oxide's thickness, nm.
        cos_incidence : array_like
            Cosine of the incidence angle in air, clipped to [0, 1].
        amplitudes : bool, optional
            As :meth:`reflectance`.

        Returns
        -------
        swatch.physics.optics.Reflectance
            Shapes S + (W,).
        """
        theta = np.degrees(np.arccos(np.clip(np.asarray(cos_incidence, dtype=np.float64), 0.0, 1.0)))
        return self.reflectance(thickness_nm, theta, amplitudes)


def overcoat(spec: str, wavelength_nm) -> Overcoat:
    """Parse ``N_OR_TABLE:THICKNESS_NM`` (``1.5:200`` or ``TiO2-Siefke:20``) into an :class:`Overcoat`.

    Parameters
    ----------
    spec : str
        A constant real index from 1 to 5, or a film table's name, then ``:`` and the layer's
        thickness in nm (more than 0, at most ``MAX_THICKNESS_NM``).
    wavelength_nm : array_like, shape (W,)
        The coating's wavelength grid, nm (the layer's index is evaluated on it).

    Returns
    -------
    Overcoat
        The layer (label, complex index (W,), thickness_nm), treated coherently by the transfer matrix.

    Examples
    --------
    >>> overcoat("1.5:200", [500.0, 600.0]).label
    'n=1.5'
    """
    text = str(spec).strip()
    what, sep, thick = text.rpartition(":")
    if not sep or not what:
        raise SwatchError(f"overcoat {text!r} must be INDEX:THICKNESS_NM or TABLE:THICKNESS_NM, e.g. 1.5:200")
    try:
        d = float(thick)
    except ValueError:
        raise SwatchError(f"overcoat thickness {thick!r} is not a number of nm") from None
    if not (math.isfinite(d) and 0 < d <= MAX_THICKNESS_NM):
        raise SwatchError(f"overcoat thickness must be more than 0 and at most {MAX_THICKNESS_NM:g} nm "
                          "(a thicker layer is not coherent: its fringes are finer than the wavelength grid)")
    wl = np.asarray(wavelength_nm, dtype=np.float64)
    n_real: float | None
    try:
        n_real = float(what)
    except ValueError:
        n_real = None
    if n_real is None:
        mat = load_material(what)
        if mat.role != "film":  # a metal is not a clear layer (it would be opaque at these thicknesses)
            choices = ", ".join(m.name for m in list_materials("film"))
            raise SwatchError(f"overcoat {mat.name} is a {mat.role} table, not a clear film; use an index "
                              f"from 1 to 5 or one of {choices}")
        return Overcoat(mat.name, mat.nk(wl), d)
    if not (math.isfinite(n_real) and 1.0 <= n_real <= 5.0):
        raise SwatchError(f"overcoat index must be from 1 to 5 (got {what})")
    return Overcoat(f"n={n_real:g}", np.full(wl.shape, n_real, dtype=np.complex128), d)


def overcoat_json(coating) -> dict:
    """The overcoats of a coating as JSON metadata.

    Parameters
    ----------
    coating : Coating or OvercoatedCoating
        A coating; a plain :class:`~swatch.physics.model.Coating` has no overcoats.

    Returns
    -------
    dict
        ``{"overcoat": [{"layer", "thickness_nm"}, ...]}`` (from the air side), or ``{}`` without overcoats.
    """
    overcoats = getattr(coating, "overcoats", ())
    if not overcoats:
        return {}
    return {"overcoat": [{"layer": o.label, "thickness_nm": o.thickness_nm} for o in overcoats]}


def overcoat_text(coating) -> str:
    """The overcoats of a coating as a phrase for titles and reports.

    Parameters
    ----------
    coating : Coating or OvercoatedCoating
        A coating; a plain :class:`~swatch.physics.model.Coating` has no overcoats.

    Returns
    -------
    str
        ``" under n=1.5 200 nm / ..."`` (from the air side), or ``""`` without overcoats.
    """
    layers = [f"{o.label} {o.thickness_nm:g} nm" for o in getattr(coating, "overcoats", ())]
    return f" under {' / '.join(layers)}" if layers else ""
