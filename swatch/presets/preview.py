"""UsdPreviewSurface's metal: the fallback of the USD presets, one colour that cannot shift with angle.

UsdPreviewSurface (the USD specification's portable surface) in its metallic workflow
(``useSpecularWorkflow`` 0, ``metallic`` 1) reflects with the Schlick Fresnel term
``F = F0 + (1 − F0)(1 − cos θ)^5`` towards white, ``F0 = diffuseColor`` and ``cos θ = V·H``
(the specification [1]_ and the reference shader of Hydra Storm, ``previewSurface.glslfx`` [2]_; a
port of those texts, not checked in a renderer here). It has no thin film and no input that depends
on the view, so an anodised colour that changes with angle is one fixed colour there:
:func:`preview_base_color` fits ``diffuseColor`` so that ``F`` equals the exact colour at one stated
facet angle (the catalog's 45:0: 22.5°), and :func:`preview_delta_E_00` is how far it then is from the
exact colour across mirror geometries 0–60° (D65, CIE 1931 2°).

References
----------
.. [1] Pixar Animation Studios, "UsdPreviewSurface Specification", version 2.6,
   https://openusd.org/release/spec_usdpreviewsurface.html
.. [2] Pixar Animation Studios, OpenUSD, ``pxr/usdImaging/plugin/usdShaders/shaders/previewSurface.glslfx``
   (``evaluateDirectLight``: ``mix(F0, F90, SchlickFresnel(EdotH))``, ``F90`` = 1).
"""
from __future__ import annotations

import colour
import numpy as np

from swatch.colorimetry.colorimeter import delta_E_00
from swatch.presets.fit import FIT_ANGLES_DEG, exact_Lab
from swatch.presets.spectral import rgb_to_Lab, rgb_to_xyz_matrix

__all__ = ["PREVIEW_FACET_DEG", "schlick_metal_fresnel", "preview_base_color", "preview_delta_E_00"]

#: The facet angle the fallback's colour is fitted at: the catalog's reference geometry 45:0 (degrees).
PREVIEW_FACET_DEG = 22.5


def schlick_metal_fresnel(cos_theta, base_color) -> np.ndarray:
    """UsdPreviewSurface's Fresnel factor of a metal: ``F0 + (1 − F0)(1 − cos θ)^5`` (..., 3).

    Parameters
    ----------
    cos_theta : array_like
        Cosine of the angle between the view and the half vector (V·H), clipped to [0, 1].
    base_color : array_like, shape (..., 3)
        ``diffuseColor`` (the metal's F0), linear Rec.709, 0–1.

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        Linear Rec.709 reflectance relative to a white metal.

    Examples
    --------
    >>> schlick_metal_fresnel(1.0, [0.5, 0.25, 0.0]).tolist()
    [0.5, 0.25, 0.0]
    """
    c = np.clip(np.asarray(cos_theta, dtype=np.float64), 0.0, 1.0)[..., None]
    f0 = np.asarray(base_color, dtype=np.float64)
    return f0 + (1.0 - f0) * (1.0 - c) ** 5


def preview_base_color(thickness_nm, film=None, substrate=None, film_index_scale: float = 1.0, spread=None,
                       facet_deg: float = PREVIEW_FACET_DEG) -> np.ndarray:
    """The ``diffuseColor`` (N, 3) whose Schlick metal shows the exact colour at ``facet_deg``, clipped to 0–1
    (a colour outside Rec.709 cannot be reached) and rounded to 1e-4 as written.

    Parameters
    ----------
    thickness_nm : array_like, shape (N,)
        Film thicknesses, nm.
    film, substrate : str, optional
        Table names (default TiO2 on Ti).
    film_index_scale : float, optional
        Factor on the film's real index (a process profile's; default 1).
    spread : swatch.physics.spread.ThicknessSpread, optional
        The film's thickness spread; None: uniform.
    facet_deg : float, optional
        The facet angle it is fitted at, degrees (default :data:`PREVIEW_FACET_DEG`, 45:0).

    Returns
    -------
    numpy.ndarray, shape (N, 3)
        Linear Rec.709, 0–1.
    """
    lab = exact_Lab(thickness_nm, [facet_deg], film, substrate, film_index_scale, spread)[:, 0]
    matrix, white = rgb_to_xyz_matrix()
    rgb = np.linalg.solve(matrix, colour.Lab_to_XYZ(lab, white).T).T  # XYZ (white Y = 1) -> linear Rec.709
    s = (1.0 - np.cos(np.radians(facet_deg))) ** 5
    return np.round(np.clip((rgb - s) / (1.0 - s), 0.0, 1.0), 4)


def preview_delta_E_00(base_color, thickness_nm, angles_deg=FIT_ANGLES_DEG, film=None, substrate=None,
                       film_index_scale: float = 1.0, spread=None) -> np.ndarray:
    """ΔE2000 (N, A) between the fallback with ``base_color`` and the exact colour at mirror geometries.

    Parameters
    ----------
    base_color : array_like, shape (N, 3)
        ``diffuseColor`` as written.
    thickness_nm : array_like, shape (N,)
        Film thicknesses, nm.
    angles_deg : array_like, shape (A,), optional
        Facet angles, degrees (default 0–60° in 5° steps).
    film, substrate, film_index_scale, spread
        As :func:`preview_base_color`.

    Returns
    -------
    numpy.ndarray, shape (N, A)
        CIEDE2000 (D65, CIE 1931 2°).
    """
    c = np.cos(np.radians(np.asarray(angles_deg, dtype=np.float64)))
    shown = rgb_to_Lab(schlick_metal_fresnel(c[None, :], np.asarray(base_color, dtype=np.float64)[:, None, :]))
    return delta_E_00(shown, exact_Lab(thickness_nm, angles_deg, film, substrate, film_index_scale, spread))
