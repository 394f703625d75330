"""USD and USDZ presets: one ``UsdShade.Material`` with the OpenPBR network and a UsdPreviewSurface fallback.

Written with Pixar's ``usd-core`` (``pxr``) as a stage: Y up, metres (``metersPerUnit`` 1), the default
prim ``/preset`` (an Xform of kind ``component``) holding the part (a ``UsdGeom.Mesh``: the designer's
triangles, placed in a sphere of :data:`PART_RADIUS_M`, or a sphere of that radius) bound to one material
``/preset/Materials/<name>`` with two surfaces:

- ``outputs:mtlx:surface``: the MaterialX nodes of the ``.mtlx`` preset, an ``ND_open_pbr_surface_surfaceshader``
  with the same inputs (``base_metalness`` 1, ``base_color``, ``specular_roughness``, ``thin_film_weight`` 1,
  ``thin_film_thickness`` in µm, ``thin_film_ior``; brushed: ``specular_roughness_anisotropy`` and an
  ``ND_bitangent_vector3`` as ``geometry_tangent``): the thin film over the metal, for renderers that read
  MaterialX in USD (the ``mtlx`` render context: Omniverse, Houdini, Maya, visionOS);
- ``outputs:surface``: a ``UsdPreviewSurface`` (``metallic`` 1, ``diffuseColor`` the colour fitted at 45:0,
  ``roughness``): :mod:`swatch.presets.preview`. It has no thin film and no view input, so it cannot shift
  with angle; the layer's and the material's documentation strings say so, with its ΔE2000 across angles.

Deterministic: the layer is exported from memory (no file paths, no timestamps in it); a ``.usdz`` is made by
``UsdUtils.CreateNewARKitUsdzPackage`` in a private temporary folder, then the zip headers' modification
times (the packager writes the current time) are set to 1980-01-01 00:00, the zip format's epoch.

References
----------
.. [1] Pixar Animation Studios, "Universal Scene Description", https://openusd.org (``usd-core`` on PyPI).
.. [2] Pixar Animation Studios, "UsdPreviewSurface Specification", https://openusd.org/release/spec_usdpreviewsurface.html
.. [3] Pixar Animation Studios, "Usdz File Format Specification", https://openusd.org/release/spec_usdz.html
"""
from __future__ import annotations

import struct
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from pxr import Gf, Kind, Sdf, Usd, UsdGeom, UsdShade, UsdUtils, Vt

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_USD_PART_TRIANGLES

__all__ = ["PART_RADIUS_M", "UsdPart", "UsdPreset", "sphere_part", "triangle_part", "usd_stage", "usda_bytes",
           "usdz_bytes"]

#: The part's size in the file: its farthest point this far from its centre (metres; a 10 cm object).
PART_RADIUS_M = 0.05
_SPHERE_BANDS = 24  # latitude bands of the default sphere (twice as many longitudes)


@dataclass(frozen=True)
class UsdPart:
    """The part's triangles, in metres, Y up.

    Attributes
    ----------
    points_m : numpy.ndarray
        Vertex positions, metres, shape (P, 3).
    triangles : numpy.ndarray
        Vertex indices of each triangle, counter-clockwise seen from outside, shape (F, 3).
    normals : numpy.ndarray
        Unit vertex normals, shape (P, 3).
    name : str
        What it is (``sphere`` or the mesh file's name), for the documentation string.
    """

    points_m: np.ndarray
    triangles: np.ndarray
    normals: np.ndarray
    name: str


@dataclass(frozen=True)
class UsdPreset:
    """What one USD preset holds.

    Attributes
    ----------
    title : str
        The material's display name (made a valid prim name for its path).
    params : numpy.ndarray
        The OpenPBR preset's ``(thickness_nm, film_ior, base R, G, B)`` as written (the ``.mtlx`` preset's).
    roughness : float
        ``specular_roughness`` and the fallback's ``roughness`` (√α).
    preview_rgb : numpy.ndarray
        The fallback's ``diffuseColor``, linear Rec.709, shape (3,).
    doc : str
        The documentation string (what was fitted, the errors, the fallback's limits).
    part : UsdPart
        The mesh the material is bound to.
    anisotropy : dict, optional
        ``{"specular_roughness_anisotropy": ...}`` of a brushed finish; None: isotropic.
    preview_roughness : float, optional
        The fallback's isotropic ``roughness`` (√α of the lobe of the same area) where it differs from OpenPBR's
        ``specular_roughness`` (a brushed finish); None: ``roughness``.
    """

    title: str
    params: np.ndarray
    roughness: float
    preview_rgb: np.ndarray
    doc: str
    part: UsdPart
    anisotropy: dict | None = None
    preview_roughness: float | None = None


def sphere_part(radius_m: float = PART_RADIUS_M) -> UsdPart:
    """A UV sphere (24 bands, 48 segments) of ``radius_m`` centred at the origin, poles on Y.

    Parameters
    ----------
    radius_m : float, optional
        Radius, metres.

    Returns
    -------
    UsdPart
        Its points, triangles and normals.
    """
    n = _SPHERE_BANDS
    theta = np.linspace(0.0, np.pi, n + 1)[:, None]  # polar angle from +Y
    phi = np.linspace(0.0, 2.0 * np.pi, 2 * n + 1)[None, :-1]
    unit = np.stack(np.broadcast_arrays(np.sin(theta) * np.sin(phi), np.cos(theta) + 0 * phi,
                                        np.sin(theta) * np.cos(phi)), axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n), np.arange(2 * n), indexing="ij")
    a, b = i * 2 * n + j, i * 2 * n + (j + 1) % (2 * n)
    c, d = a + 2 * n, b + 2 * n
    tris = np.concatenate([np.stack([a, c, b], -1).reshape(-1, 3)[2 * n:],  # no triangle at the top pole
                           np.stack([b, c, d], -1).reshape(-1, 3)[:-2 * n]])  # nor at the bottom one
    return UsdPart(unit * radius_m, tris.astype(np.int64), unit, "sphere")


def triangle_part(corners, normals, name: str, radius_m: float = PART_RADIUS_M) -> UsdPart:
    """A placed mesh's triangles (:meth:`swatch.render.mesh.MeshShape.triangle_soup`: in the unit sphere)
    scaled to ``radius_m``; each triangle keeps its own corners, so creases stay sharp.

    Parameters
    ----------
    corners : array_like, shape (F, 3, 3)
        Triangle corners in the unit sphere.
    normals : array_like, shape (F, 3, 3)
        Shading normals at the corners.
    name : str
        The mesh file's name.
    radius_m : float, optional
        The farthest point's distance from the centre in the file, metres.

    Returns
    -------
    UsdPart
        Its points, triangles and normals.

    Raises
    ------
    swatch.core.errors.SwatchError
        More than :data:`swatch.core.limits.MAX_USD_PART_TRIANGLES` triangles.
    """
    triangles = int(np.asarray(corners).shape[0])
    if triangles > MAX_USD_PART_TRIANGLES:  # before the copies are made
        raise SwatchError(f"{name}: {triangles} triangles; a USD preset's part has at most {MAX_USD_PART_TRIANGLES} "
                          "(MAX_USD_PART_TRIANGLES): give a simplified part")
    c = np.asarray(corners, dtype=np.float64).reshape(-1, 3)
    nrm = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    nrm = nrm / np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-300)
    return UsdPart(c * radius_m, np.arange(c.shape[0], dtype=np.int64).reshape(-1, 3), nrm, name)


def _check(params, roughness) -> tuple[float, float, np.ndarray, float]:
    p = np.asarray(params, dtype=np.float64)
    if p.shape != (5,) or not np.all(np.isfinite(p)) or not 0.0 <= float(roughness) <= 1.0:
        raise ValueError("a USD preset needs 5 finite parameters and a roughness in 0..1")  # ours: a bug
    return float(p[0]), float(p[1]), np.clip(p[2:], 0.0, 1.0), float(roughness)


def _color(rgb) -> Gf.Vec3f:
    return Gf.Vec3f(*[round(float(v), 4) for v in rgb])


def _input(shader, name: str, type_name, value) -> None:
    attr = shader.CreateInput(name, type_name)
    attr.Set(value)
    if type_name == Sdf.ValueTypeNames.Color3f:
        attr.GetAttr().SetColorSpace("lin_rec709")


def usd_stage(preset: UsdPreset) -> Usd.Stage:
    """The preset as an in-memory stage (Y up, metres, default prim ``/preset``).

    Parameters
    ----------
    preset : UsdPreset
        What it holds.

    Returns
    -------
    pxr.Usd.Stage
        The stage (its root layer anonymous: no path of this machine in it).
    """
    d, eta, base, rough = _check(preset.params, preset.roughness)
    stage = Usd.Stage.CreateInMemory()
    layer = stage.GetRootLayer()
    layer.documentation = preset.doc
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, UsdGeom.LinearUnits.meters)
    root = UsdGeom.Xform.Define(stage, "/preset")
    stage.SetDefaultPrim(root.GetPrim())
    Usd.ModelAPI(root.GetPrim()).SetKind(Kind.Tokens.component)
    name = "".join(ch if ch.isascii() and ch.isalnum() else "_" for ch in preset.title).strip("_") or "anodised"
    name = f"m_{name}" if name[0].isdigit() else name  # a prim name starts with a letter or _
    material = UsdShade.Material.Define(stage, f"/preset/Materials/{name}")
    UsdGeom.Scope.Define(stage, "/preset/Materials")
    material.GetPrim().SetDocumentation(preset.doc)
    path = material.GetPath()
    # (a) the OpenPBR network of the .mtlx preset, as MaterialX nodes (the mtlx render context)
    pbr = UsdShade.Shader.Define(stage, path.AppendChild("OpenPBR"))
    pbr.CreateIdAttr("ND_open_pbr_surface_surfaceshader")
    f, c3 = Sdf.ValueTypeNames.Float, Sdf.ValueTypeNames.Color3f
    _input(pbr, "base_color", c3, _color(base))
    _input(pbr, "base_metalness", f, 1.0)
    _input(pbr, "specular_roughness", f, round(rough, 6))
    _input(pbr, "thin_film_weight", f, 1.0)
    _input(pbr, "thin_film_thickness", f, round(d / 1000.0, 6))  # µm
    _input(pbr, "thin_film_ior", f, round(eta, 6))
    if preset.anisotropy is not None:
        _input(pbr, "specular_roughness_anisotropy", f, round(float(preset.anisotropy["specular_roughness_anisotropy"]), 6))
        across = UsdShade.Shader.Define(stage, path.AppendChild("across_grain"))
        across.CreateIdAttr("ND_bitangent_vector3")
        out = across.CreateOutput("out", Sdf.ValueTypeNames.Vector3f)
        pbr.CreateInput("geometry_tangent", Sdf.ValueTypeNames.Vector3f).ConnectToSource(out)
    material.CreateSurfaceOutput("mtlx").ConnectToSource(pbr.CreateOutput("out", Sdf.ValueTypeNames.Token))
    # (b) the UsdPreviewSurface fallback: metallic, one colour
    prev = UsdShade.Shader.Define(stage, path.AppendChild("PreviewSurface"))
    prev.CreateIdAttr("UsdPreviewSurface")
    _input(prev, "diffuseColor", c3, _color(preset.preview_rgb))
    _input(prev, "metallic", f, 1.0)
    _input(prev, "roughness", f, round(rough if preset.preview_roughness is None else float(preset.preview_roughness), 6))
    material.CreateSurfaceOutput().ConnectToSource(prev.CreateOutput("surface", Sdf.ValueTypeNames.Token))
    # the part
    part = preset.part
    mesh = UsdGeom.Mesh.Define(stage, "/preset/part")
    pts = np.asarray(part.points_m, dtype=np.float32)
    mesh.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(pts))
    mesh.CreateFaceVertexCountsAttr(Vt.IntArray.FromNumpy(np.full(len(part.triangles), 3, dtype=np.int32)))
    mesh.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(np.asarray(part.triangles, dtype=np.int32).ravel()))
    mesh.CreateNormalsAttr(Vt.Vec3fArray.FromNumpy(np.asarray(part.normals, dtype=np.float32)))
    mesh.SetNormalsInterpolation(UsdGeom.Tokens.vertex)
    mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    mesh.CreateDoubleSidedAttr(True)  # both faces are the anodised metal, as swatch renders them
    mesh.CreateExtentAttr(Vt.Vec3fArray([Gf.Vec3f(*map(float, pts.min(axis=0))), Gf.Vec3f(*map(float, pts.max(axis=0)))]))
    UsdShade.MaterialBindingAPI.Apply(mesh.GetPrim()).Bind(material)
    return stage


def usda_bytes(preset: UsdPreset) -> bytes:
    """The preset as a ``.usda`` text layer.

    Parameters
    ----------
    preset : UsdPreset
        What it holds.

    Returns
    -------
    bytes
        UTF-8 USD text, byte-identical for the same preset.
    """
    stage = usd_stage(preset)  # held: the layer lives as long as its stage
    return stage.GetRootLayer().ExportToString().encode("utf-8")


def _fix_zip_times(blob: bytes) -> bytes:
    """The zip with every entry's modification time and date set to the zip epoch (1980-01-01 00:00)."""
    data = bytearray(blob)
    end = data.rfind(b"PK\x05\x06")
    count, _size, start = struct.unpack_from("<HII", data, end + 10)
    pos = start
    for _ in range(count):  # the central directory's entries, each pointing to its local header
        names, extra, comment = struct.unpack_from("<HHH", data, pos + 28)
        local = struct.unpack_from("<I", data, pos + 42)[0]
        struct.pack_into("<HH", data, pos + 12, 0, 0x21)
        struct.pack_into("<HH", data, local + 10, 0, 0x21)
        pos += 46 + names + extra + comment
    return bytes(data)


def usdz_bytes(preset: UsdPreset, stem: str) -> bytes:
    """The preset as a ``.usdz`` package (``UsdUtils.CreateNewARKitUsdzPackage``: one ``<stem>.usdc`` inside).

    Parameters
    ----------
    preset : UsdPreset
        What it holds.
    stem : str
        The layer's name inside the package (the ``.usdz`` file's own stem).

    Returns
    -------
    bytes
        The package, byte-identical for the same preset and stem.
    """
    with tempfile.TemporaryDirectory(prefix="swatch-usdz-") as tmp:
        src, dst = Path(tmp) / f"{stem}.usda", Path(tmp) / f"{stem}.usdz"
        stage = usd_stage(preset)
        stage.GetRootLayer().Export(str(src))
        if not UsdUtils.CreateNewARKitUsdzPackage(Sdf.AssetPath(str(src)), str(dst)):
            raise RuntimeError(f"usd-core could not package {src.name}")  # our own layer: a bug, not bad input
        return _fix_zip_times(dst.read_bytes())
