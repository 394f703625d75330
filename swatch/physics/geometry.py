"""Light/view geometry and the half vector (the paper's eq. 5).

Angles are polar angles from the macroscopic surface normal (``*_deg``) and azimuths around it.
The default geometry is the paper's: light and view in one plane of incidence, on opposite sides
of the normal (``view_azimuth_deg = light_azimuth_deg + 180``), so ``light_deg == view_deg`` is
the mirror direction.

The half vector ``h = (l + v) / |l + v|`` is the normal of the microfacets that mirror the light
into the view. The incidence angle on those facets is ``theta_d = 1/2 arccos(l . v)``; in plane
it equals ``(theta_l + theta_v) / 2``.

References
----------
.. [1] :cite:`Fujii2019`: eq. 5, the incidence angle on the half-vector facet.
.. [2] :cite:`Walter2007`: the half vector.
"""
from __future__ import annotations

import numpy as np

from swatch.core.errors import SwatchError

__all__ = [
    "direction",
    "check_polar_deg",
    "check_azimuth_deg",
    "check_light_view_deg",
    "resolve_view_azimuth_deg",
    "cos_light_view",
    "cos_theta_d",
    "theta_d_deg",
    "cos_theta_h",
    "aspecular_view_deg",
]


def check_polar_deg(angle_deg, what: str) -> np.ndarray:
    """A polar angle checked: finite and in [0, 90) degrees from the normal.

    Parameters
    ----------
    angle_deg : array_like, degrees
        Polar angle(s), any shape.
    what : str
        The parameter's name (``light_deg``, ``view_deg``), for the error message (the CLI speaks it
        as its flag, :mod:`swatch.commands.flags`).

    Returns
    -------
    numpy.ndarray, float64, the shape of ``angle_deg``
        The angles as given, degrees from the normal, each in [0, 90).

    Raises
    ------
    SwatchError
        When an angle is not finite or outside [0, 90).
    """
    a = np.asarray(angle_deg, dtype=np.float64)
    if not np.all(np.isfinite(a)) or np.any(a < 0) or np.any(a >= 90):
        bad = a.reshape(-1)[~(np.isfinite(a) & (a >= 0) & (a < 90)).reshape(-1)][0]
        raise SwatchError(f"`{what}` must be in [0, 90) degrees from the normal (got {float(bad):g})")
    return a


def check_azimuth_deg(azimuth_deg, what: str) -> np.ndarray:
    """An azimuth checked: finite, any value, in degrees.

    Parameters
    ----------
    azimuth_deg : array_like, degrees
        Azimuth(s) around the normal, any shape.
    what : str
        The parameter's name (``light_azimuth_deg``, ``view_azimuth_deg``), for the error message.

    Returns
    -------
    numpy.ndarray, float64, the shape of ``azimuth_deg``
        The azimuths as given, degrees (not wrapped).

    Raises
    ------
    SwatchError
        When an azimuth is not finite.
    """
    a = np.asarray(azimuth_deg, dtype=np.float64)
    if not np.all(np.isfinite(a)):
        raise SwatchError(f"`{what}` must be a finite angle in degrees")
    return a


def check_light_view_deg(light_deg, view_deg) -> tuple[np.ndarray, np.ndarray]:
    """The light and view polar angles, each checked by :func:`check_polar_deg`.

    Parameters
    ----------
    light_deg, view_deg : array_like, degrees
        Polar angles from the normal, in [0, 90).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray), float64, the shapes of the inputs
        ``(light_deg, view_deg)`` as given, degrees from the normal, each in [0, 90).
    """
    return check_polar_deg(light_deg, "light_deg"), check_polar_deg(view_deg, "view_deg")


def resolve_view_azimuth_deg(light_azimuth_deg, view_azimuth_deg=None) -> np.ndarray:
    """The view azimuth: as given, or the light's azimuth + 180 when it is None.

    The one definition of the default geometry: light and view in one plane of incidence, on
    opposite sides of the normal.

    Parameters
    ----------
    light_azimuth_deg : array_like, degrees
        Azimuth of the light.
    view_azimuth_deg : array_like or None, degrees
        Azimuth of the view, or None for the opposite side.

    Returns
    -------
    numpy.ndarray, float64, degrees
        The view azimuth, the shape of whichever input it came from.
    """
    if view_azimuth_deg is None:
        return np.asarray(light_azimuth_deg, dtype=np.float64) + 180.0
    return np.asarray(view_azimuth_deg, dtype=np.float64)


def direction(polar_deg, azimuth_deg) -> np.ndarray:
    """Unit vectors for polar angles from +z (the normal) and azimuths from +x.

    Parameters
    ----------
    polar_deg : array_like, degrees
        Polar angle(s) from the normal.
    azimuth_deg : array_like, degrees
        Azimuth(s); broadcasts with ``polar_deg`` to a shape S.

    Returns
    -------
    numpy.ndarray, shape S + (3,)
        ``(sin θ cos φ, sin θ sin φ, cos θ)``.
    """
    t = np.radians(np.asarray(polar_deg, dtype=np.float64))
    p = np.radians(check_azimuth_deg(azimuth_deg, "azimuth_deg"))
    t, p = np.broadcast_arrays(t, p)
    s = np.sin(t)
    return np.stack([s * np.cos(p), s * np.sin(p), np.cos(t)], axis=-1)


def cos_light_view(light_deg, view_deg, light_azimuth_deg=0.0, view_azimuth_deg=None) -> np.ndarray:
    """``l · v``, the cosine of the angle between the light and view directions.

    Parameters
    ----------
    light_deg, view_deg : array_like, degrees
        Polar angles of the light and of the view from the surface normal, in [0, 90).
    light_azimuth_deg : array_like, degrees, optional
        Azimuth of the light around the normal (default 0).
    view_azimuth_deg : array_like, degrees, optional
        Azimuth of the view; None (default) is the light's azimuth + 180, the plane of
        incidence with the view on the opposite side (the paper's geometry). The four
        angles broadcast together to a shape S.

    Returns
    -------
    numpy.ndarray, shape S
        ``cos θl cos θv + sin θl sin θv cos(φl − φv)``, in [-1, 1].
    """
    tl = np.radians(np.asarray(light_deg, dtype=np.float64))
    tv = np.radians(np.asarray(view_deg, dtype=np.float64))
    pl = np.radians(check_azimuth_deg(light_azimuth_deg, "light_azimuth_deg"))
    pv = np.radians(check_azimuth_deg(resolve_view_azimuth_deg(light_azimuth_deg, view_azimuth_deg), "view_azimuth_deg"))
    return np.cos(tl) * np.cos(tv) + np.sin(tl) * np.sin(tv) * np.cos(pl - pv)


def cos_theta_d(light_deg, view_deg, light_azimuth_deg=0.0, view_azimuth_deg=None) -> np.ndarray:
    """Cosine of the incidence angle on the half-vector facet, ``sqrt((1 + l·v) / 2)`` (eq. 5).

    Parameters
    ----------
    light_deg, view_deg : array_like, degrees
        Polar angles of the light and of the view from the surface normal, in [0, 90).
    light_azimuth_deg : array_like, degrees, optional
        Azimuth of the light around the normal (default 0).
    view_azimuth_deg : array_like, degrees, optional
        Azimuth of the view; None (default) is the light's azimuth + 180, the plane of
        incidence with the view on the opposite side (the paper's geometry). The four
        angles broadcast together to a shape S.

    Returns
    -------
    numpy.ndarray, shape S
        ``cos θd = h·l = h·v``, in [0, 1].
    """
    c = cos_light_view(light_deg, view_deg, light_azimuth_deg, view_azimuth_deg)
    return np.sqrt(np.clip(0.5 * (1.0 + c), 0.0, 1.0))


def theta_d_deg(light_deg, view_deg, light_azimuth_deg=0.0, view_azimuth_deg=None) -> np.ndarray:
    """Incidence angle on the half-vector facet, ``θd = ½ arccos(l·v)`` (the paper's eq. 5).

    In the plane of incidence (the default azimuths) it equals ``(θl + θv) / 2``.

    Parameters
    ----------
    light_deg, view_deg : array_like, degrees
        Polar angles of the light and of the view from the surface normal, in [0, 90).
    light_azimuth_deg : array_like, degrees, optional
        Azimuth of the light around the normal (default 0).
    view_azimuth_deg : array_like, degrees, optional
        Azimuth of the view; None (default) is the light's azimuth + 180, the plane of
        incidence with the view on the opposite side (the paper's geometry). The four
        angles broadcast together to a shape S.

    Returns
    -------
    numpy.ndarray, shape S, degrees
        ``θd`` in [0, 90].
    """
    c = cos_light_view(light_deg, view_deg, light_azimuth_deg, view_azimuth_deg)
    return 0.5 * np.degrees(np.arccos(np.clip(c, -1.0, 1.0)))


def cos_theta_h(light_deg, view_deg, light_azimuth_deg=0.0, view_azimuth_deg=None) -> np.ndarray:
    """Cosine of the half vector's polar angle: the tilt of the mirroring facets from the normal.

    Parameters
    ----------
    light_deg, view_deg : array_like, degrees
        Polar angles of the light and of the view from the surface normal, in [0, 90).
    light_azimuth_deg : array_like, degrees, optional
        Azimuth of the light around the normal (default 0).
    view_azimuth_deg : array_like, degrees, optional
        Azimuth of the view; None (default) is the light's azimuth + 180, the plane of
        incidence with the view on the opposite side (the paper's geometry). The four
        angles broadcast together to a shape S.

    Returns
    -------
    numpy.ndarray, shape S
        ``cos θh = n·h`` with ``h = (l + v) / |l + v|``.
    """
    pv = resolve_view_azimuth_deg(light_azimuth_deg, view_azimuth_deg)
    s = direction(light_deg, light_azimuth_deg) + direction(view_deg, pv)
    return s[..., 2] / np.linalg.norm(s, axis=-1)


def aspecular_view_deg(light_deg, aspecular_deg) -> np.ndarray:
    """In-plane signed view angle for an aspecular angle (ASTM E2194 / E2539 multi-angle geometry).

    The specular direction is ``light_deg`` on the far side; the aspecular angle is measured from
    it towards the light.

    Parameters
    ----------
    light_deg : array_like, degrees
        Polar angle of the light.
    aspecular_deg : array_like, degrees
        Aspecular angle(s) (e.g. -15, 15, 25, 45, 75, 110); broadcasts with ``light_deg``.

    Returns
    -------
    numpy.ndarray, degrees
        The view's polar angle with a sign: positive on the far side (opposite the light),
        negative on the light's side.
    """
    return np.asarray(light_deg, dtype=np.float64) - np.asarray(aspecular_deg, dtype=np.float64)
