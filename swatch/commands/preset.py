"""``swatch preset``: a glTF, Blender or MaterialX/OpenPBR material fitted to one thickness's colour."""
from __future__ import annotations

import click

from swatch.commands.common import material_options, thickness_options
from swatch.core.choices import FINISHES
from swatch.presets import DATABASE_FORMATS, EXACT_FORMATS, PRESET_FORMATS, USD_FORMATS


@click.command()
@thickness_options(multiple=False)
@material_options
@click.option("--format", "fmt", type=click.Choice(PRESET_FORMATS + EXACT_FORMATS + USD_FORMATS + DATABASE_FORMATS),
              required=True,
              help="gltf (KHR_materials_iridescence), blender (Principled BSDF script), materialx (OpenPBR), "
                   "mitsuba (swatch's exact anodic_film BSDF: an XML and a JSON scene dictionary), usd/usdz "
                   "(OpenPBR as MaterialX nodes + a UsdPreviewSurface fallback, on a sphere or --mesh), "
                   "physicallybased (a physicallybased.info v2 material)")
@click.option("--mesh", "mesh_file", default=None, metavar="FILE",
              help="usd/usdz: the part the material is bound to (OBJ, PLY, STL, glTF binary, as render --mesh) "
                   "[default: a sphere]")
@click.option("--roughness", type=click.FloatRange(0.0, 1.0), default=None,
              help="GGX α of the finish (written as the renderers' roughness √α) "
                   "[default: the process profile's, else 0.3]")
@click.option("--finish", "finish_name", type=click.Choice(FINISHES), default=None,
              help="a named finish instead of --roughness (brushed: each format's anisotropy; docs/finishes.md)")
@click.option("--base-url", "base_url", default=None, metavar="URL",
              help="physicallybased: the http(s) address the output folder is served from; the pictures' URLs are "
                   "then absolute under it [default: relative to the JSON]")
@click.option("--out", "out", required=True, type=click.Path(file_okay=False, path_type=str), help="output folder")
@click.option("--force", is_flag=True, help="overwrite an existing file")
def preset(thickness, voltage, process, nm_per_volt, film, substrate, fmt, mesh_file, roughness, finish_name, base_url,
           out, force):
    """Write a 3-D material preset for one oxide thickness, fitted to its exact colour.

    The renderer's own thin-film model (ported in swatch.presets) is fitted to the exact colour
    over facet angles 0–60° (D65, CIE 1931 2°); the largest error is printed. ``mitsuba`` is
    exact (swatch's own BSDF for Mitsuba 3; nothing fitted). ``usd``/``usdz`` carry the MaterialX
    preset's OpenPBR network and a UsdPreviewSurface fallback (one colour: both errors printed);
    ``physicallybased`` the film's physical values as a physicallybased.info v2 material, with the
    two pictures its ``images`` name (300 and 600 px PNGs of the built-in engine's sphere under the studio).
    """
    import math
    from pathlib import Path

    from swatch.commands.common import resolve_process, resolve_thickness
    from swatch.core.errors import SwatchError
    from swatch.core.fileio import atomic_write_bytes, check_new, check_writable_dir
    from swatch.physics.finishes import finish_or_roughness
    from swatch.presets.files import single_mitsuba_preset, single_preset
    from swatch.presets.naming import preset_file_name

    finish = finish_or_roughness(finish_name, roughness)
    if roughness is not None and not math.isfinite(roughness):
        raise SwatchError(f"--roughness must be a number from 0 to 1 (got {roughness})")
    if not str(out).strip():
        raise SwatchError("--out is an empty string; give a folder path")
    proc = resolve_process(process, film, substrate, nm_per_volt)
    if finish is not None:  # as render and angular: the option, else the profile's roughness, else 0.3
        roughness = finish.roughness_alpha
    elif roughness is None:
        roughness = 0.3 if proc.roughness is None else proc.roughness
    d, _ = resolve_thickness(thickness, voltage, proc, multiple=False)
    if mesh_file is not None and fmt not in USD_FORMATS:
        raise SwatchError(f"--mesh applies to --format usd or usdz (got --format {fmt})")
    if base_url is not None and fmt not in DATABASE_FORMATS:
        raise SwatchError(f"--base-url applies to --format physicallybased (got --format {fmt})")
    if fmt in USD_FORMATS:
        from swatch.presets.usd import triangle_part
        from swatch.presets.usd_files import single_usd_preset
        from swatch.render.mesh import load_mesh

        part = None
        if mesh_file is not None:
            mesh = load_mesh(mesh_file)  # checked and placed as render --mesh reads it
            corners, normals = mesh.triangle_soup()
            part = triangle_part(corners, normals, Path(mesh_file).name)
        data, summary = single_usd_preset(float(d[0]), fmt, proc.film, proc.substrate, proc.film_index_scale,
                                          roughness, proc.spread, finish, part)
        files = {preset_file_name(f"{float(d[0]):g}nm", fmt): data}
    elif fmt in DATABASE_FORMATS:
        from swatch.report.physicallybased import physicallybased_files

        files, summary = physicallybased_files(float(d[0]), proc.coating(), roughness, base_url)
    elif fmt in EXACT_FORMATS:
        files, summary = single_mitsuba_preset(float(d[0]), proc.film, proc.substrate, proc.film_index_scale,
                                               roughness, proc.spread, finish)
    else:
        data, summary = single_preset(float(d[0]), fmt, proc.film, proc.substrate, proc.film_index_scale, roughness,
                                      proc.spread, finish)  # (before the folder is made: a bad input creates nothing)
        files = {preset_file_name(f"{float(d[0]):g}nm", fmt): data}
    paths = [Path(out) / name for name in files]
    check_new(paths, force)
    check_writable_dir(out)
    for path in paths:
        atomic_write_bytes(path, files[path.name])
    click.echo(f"{', '.join(str(p) for p in paths)}: {summary}")
