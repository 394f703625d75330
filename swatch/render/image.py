"""What every renderer returns and shares: the rendered image, its size and background checks, the
silhouette pixels re-rendered for anti-aliasing, and the metadata of a mesh.

This module is below every renderer (:mod:`swatch.render.builtin.pointlight`, :mod:`swatch.render.builtin.env_render`,
and any further engine registered in :mod:`swatch.render.dispatch`); it imports no renderer.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from swatch.core.choices import BACKGROUNDS
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_ANISO_RENDER_PX, MAX_SIZE_PX

__all__ = ["SwatchImage", "layered_pixels", "SUPERSAMPLE", "BACKGROUND_WHITE", "check_size_px", "check_background",
           "edge_pixels", "mesh_metadata", "check_finish_lighting", "finish_meta"]

#: Sub-samples per axis of a silhouette pixel (SUPERSAMPLE² stratified samples).
SUPERSAMPLE = 4

#: The white background's linear value: the display shoulder maps it (and anything above 1.73)
#: to 255, so the page is white; display only (the EXR keeps alpha).
BACKGROUND_WHITE = 2.0


@dataclass
class SwatchImage:
    """A rendered swatch: scene-referred linear RGB (premultiplied), coverage, display sRGB, metadata.

    Attributes
    ----------
    linear_rgb : numpy.ndarray
        (H, W, 3) float32, scene-referred linear RGB in the render's space, premultiplied by ``coverage``.
    coverage : numpy.ndarray
        (H, W) float32 in [0, 1]: the fraction of the pixel the object covers (alpha).
    display_rgb : numpy.ndarray
        (H, W, 3) uint8 sRGB, exposure applied and composited on the background.
    metadata : dict
        What was rendered and how (JSON-serialisable).
    exposure : float
        The display exposure k (linear × k before encoding).
    layers : dict of str to numpy.ndarray
        Extra (H, W, 3) float32 images of the same render, by name, for compositing: the Mitsuba
        engine's denoised renders keep ``raw`` (the undenoised estimate, in ``linear_rgb``'s units and
        space) and the denoiser's ``albedo`` and ``normal`` buffers. Empty otherwise.
    """

    linear_rgb: np.ndarray
    coverage: np.ndarray
    display_rgb: np.ndarray
    metadata: dict = field(default_factory=dict)
    exposure: float = 1.0
    layers: dict = field(default_factory=dict)

    @property
    def rgba(self) -> np.ndarray:
        """Linear RGB and coverage as one array (what the EXR writes: R, G, B, A).

        Returns
        -------
        numpy.ndarray, shape (H, W, 4)
            Linear RGB premultiplied by coverage, and the coverage as alpha (float32).
        """
        return np.concatenate([self.linear_rgb, self.coverage[..., None]], axis=-1)


def layered_pixels(img: SwatchImage) -> tuple[np.ndarray, tuple[str, ...]]:
    """``img.rgba`` followed by its ``layers`` (each (H, W, 3), in name order), and the EXR channel names:
    R, G, B, A, then ``<layer>.R/G/B`` (``normal``: ``.X/Y/Z``).

    Parameters
    ----------
    img : SwatchImage
        The rendered image (premultiplied linear RGB, coverage and named layers).

    Returns
    -------
    (numpy.ndarray, tuple of str)
        (H, W, 4 + 3 L) float32 pixels and their channel names.
    """
    parts, names = [img.rgba], ["R", "G", "B", "A"]
    for name in sorted(img.layers):
        parts.append(np.asarray(img.layers[name], dtype=np.float32))
        names += [f"{name}.{c}" for c in ("XYZ" if name == "normal" else "RGB")]
    return np.concatenate(parts, axis=-1), tuple(names)


def check_size_px(size_px) -> int:
    """The image size as an int.

    Parameters
    ----------
    size_px : int or float
        Pixels per side, a whole number from 1 to :data:`swatch.core.limits.MAX_SIZE_PX`.

    Returns
    -------
    int
        ``size_px`` as an int.

    Raises
    ------
    swatch.core.errors.SwatchError
        Not a whole number in that range.

    Examples
    --------
    >>> check_size_px(256.0)
    256
    """
    try:
        ok = float(size_px) == int(size_px)
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok or not 1 <= int(size_px) <= MAX_SIZE_PX:
        raise SwatchError(f"image size must be a whole number of pixels from 1 to {MAX_SIZE_PX}, got {size_px!r}")
    return int(size_px)


def check_background(name: str) -> str:
    """A background name of :data:`swatch.core.choices.BACKGROUNDS` (case-insensitive).

    Parameters
    ----------
    name : str
        ``grey``, ``white`` or ``environment`` (:data:`swatch.core.choices.BACKGROUNDS`).

    Returns
    -------
    str
        Lower case.

    Raises
    ------
    swatch.core.errors.SwatchError
        Any other name.
    """
    key = str(name).strip().lower()
    if key not in BACKGROUNDS:
        raise SwatchError(f"unknown background {name!r}; use one of {', '.join(BACKGROUNDS)}")
    return key


def edge_pixels(hit: np.ndarray) -> np.ndarray:
    """The pixels a silhouette crosses: those whose centre differs from one of its 8 neighbours'.

    A corner clipped by less than half a pixel's diagonal is the only miss.

    Parameters
    ----------
    hit : numpy.ndarray of bool, shape (H, W)
        Pixel centres on the object.

    Returns
    -------
    numpy.ndarray of int
        Flat indices into ``hit``.

    Examples
    --------
    >>> edge_pixels(np.array([[True, False], [False, False]])).tolist()
    [0, 1, 2, 3]
    """
    e = np.zeros_like(hit)
    for a, b in (((slice(None), slice(1, None)), (slice(None), slice(None, -1))),
                 ((slice(1, None), slice(None)), (slice(None, -1), slice(None))),
                 ((slice(1, None), slice(1, None)), (slice(None, -1), slice(None, -1))),
                 ((slice(1, None), slice(None, -1)), (slice(None, -1), slice(1, None)))):
        d = hit[a] != hit[b]
        e[a] |= d
        e[b] |= d
    return np.flatnonzero(e)


def mesh_metadata(mesh) -> dict:
    """The ``mesh`` entry of a mesh render's metadata (file name, SHA-256, triangles, placement), or nothing.

    Parameters
    ----------
    mesh : swatch.render.mesh.MeshShape or None
        The rendered mesh, or None for a built-in shape.

    Returns
    -------
    dict
        ``{"mesh": {...}}`` or ``{}``.
    """
    if mesh is None:
        return {}
    return {"mesh": {"file": mesh.file_name, "sha256": mesh.key.split(":", 1)[1], "triangles": mesh.triangles,
                     "placement": "bounding-box centre at the origin, farthest vertex at 1, +y up as written",
                     "shading_normals": "vertex normals interpolated; face normals across creases over 30 deg"}}


def check_finish_lighting(finish, environment, model: str, distribution: str, size_px: int) -> None:
    """Refuse a finish the built-in engine cannot render under the given lighting.

    An anisotropic finish (brushed) needs the GGX microfacet model under an environment, at most
    :data:`swatch.core.limits.MAX_ANISO_RENDER_PX` pixels per side (its gather is four times the isotropic one's).

    Parameters
    ----------
    finish : swatch.physics.finishes.Finish or None
        The named finish (None: nothing to check).
    environment : object or None
        The environment (None: the point light).
    model, distribution : str
        The intensity model and facet distribution of the render.
    size_px : int
        Image side, pixels.

    Returns
    -------
    None
        Returns only when the finish can be rendered so.

    Raises
    ------
    swatch.core.errors.SwatchError
    """
    if finish is None or not finish.anisotropic:
        return
    if environment is None or model != "microfacet" or distribution != "ggx":
        raise SwatchError(f"the {finish.name} finish is anisotropic: the built-in engine renders it with the GGX "
                          "microfacet model under an environment (studio, uniform or an .exr), not the point "
                          "light; use an isotropic finish or `roughness_alpha` there")
    if int(size_px) > MAX_ANISO_RENDER_PX:
        raise SwatchError(f"renders of the {finish.name} finish are at most {MAX_ANISO_RENDER_PX} pixels per side "
                          "(memory); use a smaller `size_px`")


def finish_meta(finish) -> dict:
    """The ``finish`` entry of a render's metadata (name, roughness, basis), or nothing.

    Parameters
    ----------
    finish : swatch.physics.finishes.Finish or None
        The render's named finish, if any.

    Returns
    -------
    dict
        ``{"finish": {...}}`` (name, α_u, α_v, basis) or ``{}``.
    """
    return {} if finish is None else {"finish": finish.metadata()}
