"""A catalog's measuring geometries: in-plane light/view pairs, the reference and the multi-angle set.

Multi-angle geometries are named ``<light>as<aspecular>`` (ASTM E2194 / E2539); the reference one
``<light>:<view>``. Used by the spec parser, the records and the finish specification.
"""
from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Geometry", "DEFAULT_ASPECULAR_DEG", "geometry_name"]

#: Default multi-angle set: illumination 45°, aspecular -15°, 15°, 25°, 45°, 75°, 110° (ASTM E2194 / E2539).
DEFAULT_ASPECULAR_DEG = (-15.0, 15.0, 25.0, 45.0, 75.0, 110.0)


@dataclass(frozen=True)
class Geometry:
    """One in-plane light/view geometry.

    ``view_deg`` is the view's polar angle from the normal; ``view_side`` is ``"opposite"`` (the
    usual side, across the normal from the light) or ``"light"`` (the same side as the light).
    """

    name: str
    light_deg: float
    view_deg: float
    view_side: str = "opposite"
    aspecular_deg: float | None = None

    @property
    def view_azimuth_deg(self) -> float | None:
        """For swatch.physics.geometry: None = opposite side (azimuth + 180), 0 = the light's side."""
        return None if self.view_side == "opposite" else 0.0

    @property
    def theta_d_deg(self) -> float:
        """Incidence angle on the half-vector facet (in plane): half the angle between l and v."""
        if self.view_side == "opposite":
            return 0.5 * (self.light_deg + self.view_deg)
        return 0.5 * abs(self.light_deg - self.view_deg)

    def to_json(self) -> dict:
        out = {"name": self.name, "light_deg": self.light_deg, "view_deg": self.view_deg,
               "view_side": self.view_side}
        if self.aspecular_deg is not None:
            out["aspecular_deg"] = self.aspecular_deg
        out["theta_d_deg"] = self.theta_d_deg
        return out



def geometry_name(light: float, aspecular: float) -> str:
    return f"{light:g}as{aspecular:g}"
