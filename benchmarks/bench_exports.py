"""Exports benchmark: what the designer exports add to a catalog build (default titanium catalog).

* ``exports_chips_s``: the 57 print chips (50 mm at 300 dpi: PNG and TIFF, 16-bit) written in one
  process (the build spreads them over its worker pool);
* ``exports_cxf_s`` and ``exports_ase_s``: the CxF3 document and the two ASE files.
Medians of 3 (after one warm-up run).
"""
from __future__ import annotations

import tempfile
from pathlib import Path

from benchmarks.timing import bench_spec, median_seconds


def run() -> list[str]:
    import swatch  # noqa: F401
    from swatch.catalog import chips
    from swatch.catalog.context import catalog_context
    from swatch.catalog.execute import catalog_header
    from swatch.catalog.exports import ase_bytes, cxf_bytes, metal_symbol
    from swatch.catalog.records import compute
    from swatch.catalog.spec import load_spec

    with tempfile.TemporaryDirectory(prefix="swatch-bench-chips-") as tmp:
        spec_path = bench_spec(tmp)
        spec, _ = load_spec(spec_path)
        data = compute(catalog_context(spec))
        header = catalog_header(spec, data, spec_path.name)
        (Path(tmp) / "chips").mkdir()  # the catalog folder's chips/ (the build makes it in its staging folder)

        def write_all():
            for args in chips.chip_batches(tmp, header, data, data.records, metal_symbol(spec), spec.chip_size_mm,
                                           spec.chip_dpi, 1):
                chips.write_chips(*args)

        t_chips = median_seconds(write_all, repeats=3)
        size = sum(p.stat().st_size for p in (Path(tmp) / "chips").iterdir())
    t_cxf = median_seconds(lambda: cxf_bytes(spec, data), repeats=3)
    t_ase = median_seconds(lambda: (ase_bytes(spec, data.records, "lab"), ase_bytes(spec, data.records, "srgb")),
                           repeats=3)
    return [f"exports_chips_s={t_chips:.2f} exports_chips_MB={size / 1e6:.2f} exports_cxf_s={t_cxf:.3f} "
            f"exports_ase_s={t_ase:.4f}"]


if __name__ == "__main__":
    print("\n".join(run()))
