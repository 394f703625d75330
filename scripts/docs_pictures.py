"""Make the pictures of docs/ from the current code, and record what each was made from.

    python scripts/docs_pictures.py                      # every picture (a few minutes: the catalog, Mitsuba)
    python scripts/docs_pictures.py studio-renders.png   # one of them

Each picture is made by one function here from the package as it is now, and ``docs/pictures.json``
records per picture the fingerprint of what makes it (the code of the modules it depends on, comments
and docstrings left out; the inputs; this script) and the picture's own SHA-256. tests/test_docs_pictures.py
recomputes the fingerprints (it renders nothing) and fails when a picture is stale: run this script then.
"""
from __future__ import annotations

import ast
import hashlib
import json
import sys
import tempfile
import tomllib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
RECORD = DOCS / "pictures.json"

#: What every picture depends on: the layers below the renderers (of io/, the image files; not the
#: measurement readers), the optical tables, this script.
BASE = ["swatch/core/*.py", "swatch/physics/*.py", "swatch/colorimetry/*.py", "swatch/io/imageio.py",
        "swatch/io/drawing.py", "swatch/io/pngmeta.py", "swatch/io/imagecheck.py",
        "tables/optical/*.csv", "tables/processes/*.toml", "scripts/docs_pictures.py"]
RENDER = [*BASE, "swatch/render/*.py"]


@dataclass(frozen=True)
class Picture:
    make: Callable[[Path], None]
    depends: tuple[str, ...]


def _source_digest(path: Path) -> bytes:
    """A file's content as far as a picture goes: Python without comments, docstrings and formatting (its
    AST); TOML as its parsed data; anything else byte for byte."""
    if path.suffix == ".py":
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            body = getattr(node, "body", None)
            if (isinstance(body, list) and body and isinstance(body[0], ast.Expr)
                    and isinstance(body[0].value, ast.Constant) and isinstance(body[0].value.value, str)):
                node.body = body[1:] or [ast.Pass()]  # type: ignore[attr-defined]
        return ast.dump(tree).encode("utf-8")
    if path.suffix == ".toml":
        return json.dumps(tomllib.loads(path.read_text(encoding="utf-8")), sort_keys=True).encode("utf-8")
    return path.read_bytes()


def fingerprint(name: str) -> str:
    """The SHA-256 of the files picture ``name`` depends on (:data:`PICTURES`), as :func:`_source_digest`."""
    files = sorted({p for pattern in PICTURES[name].depends for p in ROOT.glob(pattern) if p.is_file()})
    h = hashlib.sha256()
    for p in files:
        h.update(p.relative_to(ROOT).as_posix().encode("utf-8") + b"\0")
        h.update(hashlib.sha256(_source_digest(p)).digest())
    return h.hexdigest()


def _write(path: Path, rgb: np.ndarray, source: str) -> None:
    from swatch.io import imageio

    imageio.write_png(path, np.ascontiguousarray(rgb), {"source": f"scripts/docs_pictures.py: {source}"})


def catalog_sheet(path: Path) -> None:
    """The top left of the default catalog's first sheet at 100 %: the header and two tiles."""
    import OpenImageIO as oiio

    from swatch.catalog.build import build_catalog

    with tempfile.TemporaryDirectory(prefix="swatch-docs-") as tmp:
        build_catalog("titanium", Path(tmp) / "catalog")
        sheet = oiio.ImageBuf(str(Path(tmp) / "catalog" / "sheets" / "sheet_01.png")).get_pixels(oiio.UINT8)
    _write(path, sheet[:500, :900, :3], "the default catalog (bundled titanium), sheets/sheet_01.png, 900 x 500 crop")


def studio_renders(path: Path) -> None:
    """Plate and sphere at 50.8, 120 and 210 nm in the studio, labelled."""
    from swatch.io.drawing import draw_text
    from swatch.render import render_swatch

    size = 240
    columns = []
    for d in (50.8, 120.0, 210.0):
        plate = render_swatch(d, "flat", size, environment="studio").display_rgb
        sphere = render_swatch(d, "sphere", size, environment="studio").display_rgb
        column = np.concatenate([plate, sphere], axis=0)[..., :3].copy()
        column = draw_text(column, f"{d:g} nm", 8, 20, 14, color=(235, 235, 235))
        columns.append(column)
    _write(path, np.concatenate(columns, axis=1), "render_swatch flat and sphere, studio, 50.8/120/210 nm, 240 px")


def mesh_renders(path: Path) -> None:
    """examples/part.glb at 50.8 and 140 nm in the studio and under the point light."""
    from swatch.render import render_swatch
    from swatch.render.mesh import load_mesh

    part = load_mesh(ROOT / "examples" / "part.glb")
    shots = [render_swatch(d, "mesh", 256, mesh=part, environment=env).display_rgb[..., :3]
             for env in ("studio", "point") for d in (50.8, 140.0)]
    _write(path, np.concatenate(shots, axis=1), "render_swatch --mesh examples/part.glb, 50.8/140 nm, studio and point light")


def mitsuba_gallery(path: Path) -> None:
    """scripts/mitsuba_gallery.py's four Mitsuba scenes (about 2 minutes on 2 cores)."""
    sys.path.insert(0, str(ROOT / "scripts"))
    import mitsuba_gallery as gallery

    with tempfile.TemporaryDirectory(prefix="swatch-docs-") as tmp:
        gallery.main(tmp)
        path.write_bytes((Path(tmp) / "mitsuba-gallery.png").read_bytes())


def usd_in_blender(path: Path) -> None:
    """scripts/usd_in_blender.py: the .usdz presets imported into Blender 5.0 and rendered by Cycles (the ``bpy``
    module of .venv-blender, as .ci/run installs it; about a minute on 2 cores), above swatch's exact model."""
    sys.path.insert(0, str(ROOT / "scripts"))
    import usd_in_blender as picture

    picture.make(path)


def _swatch(*args: str, cwd: Path) -> None:
    """Run the ``swatch`` command of this checkout (``python -m swatch.cli``) in ``cwd``; its exit status 0 or 1."""
    import subprocess

    done = subprocess.run([sys.executable, "-m", "swatch.cli", *args], check=False, cwd=cwd, capture_output=True,
                          text=True)
    if done.returncode not in (0, 1):
        raise SystemExit(f"swatch {' '.join(args)}: {done.stderr.strip()}")


def spec_card(path: Path) -> None:
    """The finisher's spec card (docs/finisher.md: #2579b8, dE00 2, examples/line.toml), page 1 at 100 dpi
    (poppler's pdftoppm)."""
    import subprocess

    with tempfile.TemporaryDirectory(prefix="swatch-docs-") as tmp:
        _swatch("spec", "--hex", "2579b8", "--tolerance", "dE00:2", "--process", str(ROOT / "examples" / "line.toml"),
                "--out", "spec", cwd=Path(tmp))
        subprocess.run(["pdftoppm", "-png", "-r", "100", "-singlefile", "spec/spec.pdf", "card"], cwd=tmp, check=True)
        path.write_bytes((Path(tmp) / "card.png").read_bytes())


def check_report(path: Path) -> None:
    """``swatch check examples/parts.cxf`` against that spec: qc/check.png."""
    with tempfile.TemporaryDirectory(prefix="swatch-docs-") as tmp:
        _swatch("spec", "--hex", "2579b8", "--tolerance", "dE00:2", "--process", str(ROOT / "examples" / "line.toml"),
                "--out", "spec", cwd=Path(tmp))
        _swatch("check", str(ROOT / "examples" / "parts.cxf"), "--spec", "spec/spec.json", "--report", "qc",
                cwd=Path(tmp))
        path.write_bytes((Path(tmp) / "qc" / "check.png").read_bytes())


#: What the spec card and the check report depend on: fits, the production layer, the readers, the commands.
PRODUCTION = (*BASE, "swatch/fit/*.py", "swatch/io/*.py", "swatch/report/*.py", "swatch/production/*.py",
              "swatch/commands/spec.py", "swatch/commands/check.py", "swatch/commands/common.py",
              "examples/line.toml", "tables/*.csv")

PICTURES: dict[str, Picture] = {
    "spec-card.png": Picture(spec_card, PRODUCTION),
    "check-report.png": Picture(check_report, (*PRODUCTION, "examples/parts.cxf")),
    "catalog-sheet.png": Picture(catalog_sheet, (*RENDER, "swatch/presets/*.py", "swatch/report/*.py",
                                                 "swatch/catalog/*.py", "swatch/catalog/web/*", "catalog/titanium.toml",
                                                 "tables/*.csv", "tables/renderers/*.csv")),
    "studio-renders.png": Picture(studio_renders, tuple(RENDER)),
    "mesh-renders.png": Picture(mesh_renders, (*RENDER, "examples/part.glb")),
    "mitsuba-gallery.png": Picture(mitsuba_gallery, (*RENDER, "swatch/render/mitsuba/*.py", "swatch/mitsuba/*.py",
                                                     "scripts/mitsuba_gallery.py")),
    "usd-in-blender.png": Picture(usd_in_blender, (*RENDER, "swatch/presets/*.py", "scripts/usd_in_blender.py",
                                                   "scripts/blender_usd_render.py")),
}


def main(argv: list[str]) -> int:
    names = argv or list(PICTURES)
    unknown = [n for n in names if n not in PICTURES]
    if unknown:
        print(f"docs_pictures: unknown picture(s) {unknown}; pictures: {', '.join(PICTURES)}", file=sys.stderr)
        return 2
    record = json.loads(RECORD.read_text(encoding="utf-8")) if RECORD.exists() else {}
    for name in names:
        path = DOCS / name
        PICTURES[name].make(path)
        record[name] = {"fingerprint": fingerprint(name), "sha256": hashlib.sha256(path.read_bytes()).hexdigest()}
        RECORD.write_text(json.dumps(dict(sorted(record.items())), indent=1) + "\n", encoding="utf-8")
        print(f"{path.relative_to(ROOT)}: made")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
