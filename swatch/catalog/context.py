"""The catalog context: what every stage of a build computes with, built once from the validated spec.

``catalog build`` used to hand the spec to every module, each rebuilding the wavelength grid, the
coating and the colorimeters from it (issue #17). :func:`catalog_context` builds them once (and
refuses an unknown illuminant there, naming the spec's key); the records, the explorer tables, the
chips and the exports take the :class:`CatalogContext`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from swatch.catalog.spec import CatalogSpec
from swatch.colorimetry.colorimeter import Colorimeter, get_colorimeter
from swatch.colorimetry.tolerance import Tolerance
from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_PAGE_MESH_TRIANGLES
from swatch.physics.materials import wavelength_grid
from swatch.physics.model import Coating
from swatch.render.mesh import MeshShape, load_mesh

__all__ = ["CatalogContext", "catalog_context", "catalog_mesh", "ICC_ILLUMINANT", "ICC_OBSERVER"]

#: The ICC profile connection space's illuminant and observer (ISO 13655): what print workflows and
#: Adobe applications assume CIELAB to be (the ASE file's Lab, ``Lab_D50_2``).
ICC_ILLUMINANT = "D50"
ICC_OBSERVER = "2"


@dataclass(frozen=True)
class CatalogContext:
    """The grid, coating, colorimeters and tolerance of one catalog, built once by :func:`catalog_context`.

    Attributes
    ----------
    spec : CatalogSpec
        The validated spec (names, geometries, render options, layout and the process's growth law:
        :meth:`CatalogSpec.voltage_of`).
    wavelength_nm : numpy.ndarray
        The spectral grid, nm, shape (W,): 380–780 nm at the spec's ``colour.wavelength_step_nm``.
    coating : swatch.physics.model.Coating
        The film on its substrate on that grid (index scale and thickness spread of the process).
    colorimeter : swatch.colorimetry.colorimeter.Colorimeter
        The spec's illuminant and observer on that grid (its ``display_colorimeter`` gives the
        sRGB and Display P3 values, CIE 1931 2°).
    colorimeter_icc : swatch.colorimetry.colorimeter.Colorimeter
        D50, CIE 1931 2° (ICC PCS, ISO 13655) on that grid.
    tolerance : swatch.colorimetry.tolerance.Tolerance
        The spec's tolerance (a named grade or a written bound), in its own metric.
    mesh : swatch.render.mesh.MeshShape or None
        The designer's part (``[render] mesh``), read and checked (:func:`catalog_mesh`); None without one.
    """

    spec: CatalogSpec
    wavelength_nm: np.ndarray
    coating: Coating
    colorimeter: Colorimeter
    colorimeter_icc: Colorimeter
    tolerance: Tolerance
    mesh: MeshShape | None = None


def catalog_mesh(spec: CatalogSpec) -> MeshShape | None:
    """The spec's part read and checked by :func:`swatch.render.mesh.load_mesh` (its formats and caps), the very
    bytes the spec hashed (:attr:`CatalogSpec.mesh_sha256`).

    Parameters
    ----------
    spec : CatalogSpec
        The validated spec (its ``mesh``, ``mesh_path`` and ``mesh_sha256``).

    Returns
    -------
    swatch.render.mesh.MeshShape or None
        The placed mesh; None when the spec names no part.

    Raises
    ------
    swatch.core.errors.SwatchError
        A file the mesh reader refuses (no triangles, too many, not its format …), one over the page's
        :data:`swatch.core.limits.MAX_PAGE_MESH_TRIANGLES`, or one changed since the spec was read: one line naming
        the spec and the key ``render.mesh``.
    """
    if spec.mesh is None or spec.mesh_path is None:
        return None
    try:
        mesh = load_mesh(spec.mesh_path)
    except SwatchError as exc:
        raise SwatchError(f"{spec.source}: key render.mesh: {exc}") from None
    if mesh.key != f"mesh:{spec.mesh_sha256}":
        raise SwatchError(f"{spec.source}: key render.mesh: {spec.mesh} changed while the build read it; build again")
    if mesh.triangles > MAX_PAGE_MESH_TRIANGLES:  # the page's live view draws the part's triangles
        raise SwatchError(f"{spec.source}: key render.mesh: {spec.mesh} has {mesh.triangles} triangles; the catalog page "
                          f"draws at most {MAX_PAGE_MESH_TRIANGLES} (MAX_PAGE_MESH_TRIANGLES): give a simplified part")
    return mesh


def catalog_context(spec: CatalogSpec) -> CatalogContext:
    """Build the :class:`CatalogContext` of a validated spec (the one place a build makes them).

    Parameters
    ----------
    spec : CatalogSpec
        A spec from :func:`swatch.catalog.spec.load_spec` or :func:`~swatch.catalog.spec.parse_spec`.

    Returns
    -------
    CatalogContext
        The build's wavelength grid, coating, colorimeters and tolerance, made once.

    Raises
    ------
    swatch.core.errors.SwatchError
        The spec's illuminant is not one colour-science knows (the message names the spec's file and
        the key ``colour.illuminant``), or its part is not a mesh the renderer reads (:func:`catalog_mesh`).

    Examples
    --------
    >>> from swatch.catalog.spec import parse_spec
    >>> ctx = catalog_context(parse_spec({"name": "Demo", "thickness": {"list_nm": [60, 120]}}))
    >>> ctx.wavelength_nm.shape, ctx.colorimeter.illuminant, ctx.colorimeter_icc.illuminant
    ((81,), 'D65', 'D50')
    """
    wl = wavelength_grid(380.0, 780.0, spec.wavelength_step_nm)
    try:
        cm = get_colorimeter(wl, spec.illuminant, spec.observer)
    except SwatchError as exc:
        raise SwatchError(f"{spec.source}: key colour.illuminant: {exc}") from None
    return CatalogContext(spec=spec, wavelength_nm=wl, coating=spec.coating(wl), colorimeter=cm,
                          colorimeter_icc=get_colorimeter(wl, ICC_ILLUMINANT, ICC_OBSERVER),
                          tolerance=spec.tolerance, mesh=catalog_mesh(spec))
