"""Measuring geometries: in-plane light/view pairs, the reference and the multi-angle set.

Multi-angle geometries are named ``<light>as<aspecular>`` (ASTM E2194 / E2539); the reference one
``<light>:<view>``. Used by the catalog's spec parser and records, the finish specification and QC.

References
----------
.. [1] :cite:`ASTME2194`: the aspecular angles and the ``as`` naming.
.. [2] :cite:`ASTME2539`: multi-angle measurement of interference colours.
.. [3] :cite:`Fujii2019`: eq. 5, the incidence angle θ_d on the half-vector facet.
"""
from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Geometry", "DEFAULT_ASPECULAR_DEG", "geometry_name"]

#: Default multi-angle set: illumination 45°, aspecular -15°, 15°, 25°, 45°, 75°, 110° (ASTM E2194 / E2539).
DEFAULT_ASPECULAR_DEG = (-15.0, 15.0, 25.0, 45.0, 75.0, 110.0)


@dataclass(frozen=True)
class Geometry:
    """One in-plane light/view geometry of a catalog.

    Attributes
    ----------
    name : str
        ``45:0`` (the reference) or ``45as15`` (multi-angle).
    light_deg : float
        The light's polar angle from the normal, degrees.
    view_deg : float
        The view's polar angle from the normal, degrees.
    view_side : str
        ``"opposite"`` (across the normal from the light, the usual side) or ``"light"`` (the light's side).
    aspecular_deg : float or None
        The aspecular angle (ASTM E2194), degrees, for a multi-angle geometry.

    Examples
    --------
    >>> g = Geometry("45as110", 45.0, 65.0, "light", 110.0)
    >>> g.theta_d_deg, g.view_azimuth_deg
    (10.0, 0.0)
    """

    name: str
    light_deg: float
    view_deg: float
    view_side: str = "opposite"
    aspecular_deg: float | None = None

    @property
    def view_azimuth_deg(self) -> float | None:
        """The view's azimuth for :mod:`swatch.physics.geometry`: None (opposite side, light + 180°) or 0 (the light's side).

        Returns
        -------
        float or None
            None (the view opposite the light, azimuth light + 180°) or 0.0 (the light's side), degrees.
        """
        return None if self.view_side == "opposite" else 0.0

    @property
    def theta_d_deg(self) -> float:
        """Incidence angle on the half-vector facet (in plane): half the angle between l and v (Fujii et al. eq. 5).

        Returns
        -------
        float
            Degrees.
        """
        if self.view_side == "opposite":
            return 0.5 * (self.light_deg + self.view_deg)
        return 0.5 * abs(self.light_deg - self.view_deg)

    def to_json(self) -> dict:
        """The geometry as ``catalog.json`` writes it (with ``theta_d_deg``).

        Returns
        -------
        dict
            ``name``, ``light_deg``, ``view_deg``, ``view_side``, ``aspecular_deg`` (multi-angle) and ``theta_d_deg`` (degrees).
        """
        out = {"name": self.name, "light_deg": self.light_deg, "view_deg": self.view_deg,
               "view_side": self.view_side}
        if self.aspecular_deg is not None:
            out["aspecular_deg"] = self.aspecular_deg
        out["theta_d_deg"] = self.theta_d_deg
        return out



def geometry_name(light: float, aspecular: float) -> str:
    """The name of a multi-angle geometry: ``<light>as<aspecular>``.

    Parameters
    ----------
    light : float
        Degrees.
    aspecular : float
        Degrees.

    Returns
    -------
    str
        ``45as15`` for a multi-angle geometry, ``45:0`` for a light/view pair (degrees, ``g`` format).

    Examples
    --------
    >>> geometry_name(45.0, -15.0)
    '45as-15'
    """
    return f"{light:g}as{aspecular:g}"
