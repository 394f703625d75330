"""physicallybased.info materials with their pictures: the v2 material of
:mod:`swatch.presets.physicallybased` and the two renders its ``images`` name.

The schema requires each material's ``images``: a 300 and a 600 px picture (the database's own are Cycles
renders on its shader ball). swatch's pictures are its own built-in engine's
(:func:`swatch.render.render_swatch`): a sphere seen from its default view under the studio (the engine's
default lighting for the GGX model: an overhead soft box, tall strip boxes left and right, dark-grey walls, a
light floor with a horizon), at the material's roughness, the exact thin-film colour (Airy on the half-vector
facet, D65), on the grey background, display sRGB from the CIE 1931 2° observer. Each is a PNG written by
:func:`swatch.io.imageio.write_png` with the render's conditions in its metadata, and is named beside the
document (:func:`swatch.presets.naming.preset_file_name`, ``physicallybased_300`` / ``_600``).
"""
from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from swatch.io.imageio import write_png
from swatch.physics.materials import metal_name
from swatch.presets import physicallybased
from swatch.presets.files import roughness_factor
from swatch.presets.naming import preset_file_name
from swatch.render import render_swatch

__all__ = ["PICTURE_METADATA", "picture_png", "material_with_pictures", "physicallybased_files"]

#: The render's metadata a picture carries (what it shows and how; no software version, so the bytes stay).
PICTURE_METADATA = ("shape", "lighting", "model", "distribution", "roughness", "film", "substrate", "thickness_nm",
                    "units", "display")


def picture_png(thickness_nm: float, size_px: int, coating, roughness_alpha: float) -> bytes:
    """One picture: the built-in engine's sphere under the studio, as PNG bytes.

    Parameters
    ----------
    thickness_nm : float
        Film thickness, nm.
    size_px : int
        The picture's side, pixels.
    coating : swatch.physics.model.Coating
        Film, substrate, index scale and thickness spread.
    roughness_alpha : float
        GGX α of the surface (dimensionless).

    Returns
    -------
    bytes
        The PNG (display sRGB, 8 bits, RGB), byte-identical for the same inputs.
    """
    image = render_swatch(float(thickness_nm), "sphere", int(size_px), coating=coating,
                          roughness_alpha=float(roughness_alpha))
    meta = {k: image.metadata[k] for k in PICTURE_METADATA if k in image.metadata}
    with tempfile.TemporaryDirectory(prefix="swatch-picture-") as folder:
        path = Path(folder) / "picture.png"
        write_png(path, np.ascontiguousarray(image.display_rgb[..., :3]), meta)
        return path.read_bytes()


def material_with_pictures(ident: str, name: str, thickness_nm: float, coating, roughness_alpha: float,
                           base_url: str | None = None, note: str = "") -> tuple[dict, dict[str, bytes]]:
    """One material of the v2 schema with its ``images``, and those pictures' files.

    Parameters
    ----------
    ident : str
        The pictures' file-name stem (the swatch id, or ``<thickness>nm``).
    name : str
        The material's name.
    thickness_nm : float
        Film thickness, nm.
    coating : swatch.physics.model.Coating
        Film, substrate, index scale and thickness spread.
    roughness_alpha : float
        GGX α (the document's roughness is √α).
    base_url : str, optional
        The address the document's folder is served from: the pictures' URLs are absolute under it; None:
        relative references to the files beside the document.
    note : str, optional
        Appended to the description.

    Returns
    -------
    entry : dict
        The material (:func:`swatch.presets.physicallybased.material_entry`).
    files : dict
        Picture file name -> PNG bytes (each of :data:`swatch.presets.physicallybased.IMAGE_SIZES_PX`).
    """
    names = {s: preset_file_name(ident, f"physicallybased_{s}") for s in physicallybased.IMAGE_SIZES_PX}
    images = physicallybased.image_entries(names, base_url)  # (the address checked before anything renders)
    entry = physicallybased.material_entry(name, float(thickness_nm), coating.film, coating.substrate,
                                           coating.film_index_scale, roughness_factor(roughness_alpha), images, note,
                                           coating.spread)
    files = {names[s]: picture_png(thickness_nm, s, coating, roughness_alpha) for s in physicallybased.IMAGE_SIZES_PX}
    return entry, files


def physicallybased_files(thickness_nm: float, coating, roughness_alpha: float,
                          base_url: str | None = None) -> tuple[dict[str, bytes], str]:
    """One thickness as a physicallybased.info v2 document and its two pictures (``swatch preset --format
    physicallybased``).

    Parameters
    ----------
    thickness_nm : float
        Film thickness, nm.
    coating : swatch.physics.model.Coating
        Film, substrate, index scale and thickness spread.
    roughness_alpha : float
        GGX α (written as the roughness √α).
    base_url : str, optional
        The address the output folder is served from (absolute picture URLs); None: relative references.

    Returns
    -------
    (dict, str)
        File name -> bytes (the JSON document first, then its pictures), and a line saying what they hold.
    """
    d = float(thickness_nm)
    ident = f"{d:g}nm"
    entry, pictures = material_with_pictures(ident, f"{metal_name(coating.substrate).capitalize()} (Anodized, {d:g} nm)",
                                             d, coating, roughness_alpha, base_url)
    files = {preset_file_name(ident, "physicallybased"): physicallybased.document_bytes([entry]), **pictures}
    sizes = " and ".join(f"{s} px" for s in physicallybased.IMAGE_SIZES_PX)
    return files, (f"physicallybased.info v2 material: thinFilmThickness {d:g} nm, thinFilmIor "
                   f"{entry['thinFilmIor']:g}; pictures {sizes} (built-in engine, sphere, studio)")
