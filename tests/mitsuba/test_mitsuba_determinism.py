"""The Mitsuba engine is deterministic (#23): the same seed and spp give the same bytes for any spp, on
the first render of a process or after others, with a warm or a cold Dr.Jit kernel cache; and it is
reached through the one render dispatcher (#17). Few samples; image sizes shared with other tests' renders
(their compiled kernels reused, #17)."""
from __future__ import annotations

import hashlib
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tests.mitsuba_setup import irregular_spectrum, mitsuba_variant

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def mi():
    return mitsuba_variant()


def _digest(img) -> str:
    return hashlib.sha256(np.ascontiguousarray(img.linear_rgb).tobytes()).hexdigest()


def test_the_studio_keeps_its_shapes_and_emitters_in_dictionary_order(mi):
    """#23: the studio scene loads with its shapes and emitters in the dictionary's order every time.
    Mitsuba's default object merging (``load_dict(optimize=True)``) swapped the two strip boxes in about
    one load in eight, and the light sampler, which picks emitters by index, then drew another sample
    stream for the same seed."""
    from swatch.render.mitsuba.scene import lighting, load_scene, object_shapes

    entries = {**object_shapes("sphere", {"type": "diffuse"}, None), **lighting("studio", -1.0, None, None)}
    orders = {tuple(s.id() for s in load_scene({"type": "scene", **entries}).shapes()) for _ in range(24)}
    assert orders == {tuple(k for k in entries if k != "fill")}


#: The catalog's ``brushed`` finish (α_u 0.12 along, 0.4 across) at the hero renders' size (128 px, studio,
#: sphere: swatch.catalog.hero): the renders below reuse the hero's compiled kernel (#17: image size and the
#: anisotropic code path are constants of Dr.Jit's kernels; spp and seed are not).
_LOBE, _SIZE = (0.12, 0.4), 128

_COLD = f"""
import hashlib
import numpy as np
from tests.mitsuba_setup import mitsuba_variant
from swatch.render.mitsuba.engine import render_swatch_mitsuba
mitsuba_variant()
for spp in (3, 8):
    img = render_swatch_mitsuba(80.0, "sphere", {_SIZE}, spp, 3, "studio", roughness_alpha={_LOBE!r})
    print(hashlib.sha256(np.ascontiguousarray(img.linear_rgb).tobytes()).hexdigest())
"""


def _roughconductor() -> dict:
    """Mitsuba's own roughconductor with Ti-Johnson's n, k (GGX, α 0.2): the one of test_mitsuba_checks.py's
    zero-thickness pair (32 px, studio), whose kernel the render below reuses."""
    from swatch.physics.materials import load_material

    s = load_material("Ti-Johnson")
    return {"type": "roughconductor", "distribution": "ggx", "alpha": 0.2,
            "eta": irregular_spectrum(s.wavelength_nm, s.n), "k": irregular_spectrum(s.wavelength_nm, s.k)}


@pytest.mark.slow
def test_same_seed_same_bytes_for_any_spp_after_other_renders_and_with_a_cold_cache(mi, tmp_path):
    """#23: a render at 3 and 8 spp (three passes, one pass; 128 px, brushed) gives the same bytes when repeated
    after another render (Mitsuba's own roughconductor, 32 px, another seed) in the same process, and in a fresh
    process with an empty Dr.Jit kernel cache (a new HOME: Dr.Jit keeps its cache in ~/.drjit)."""
    from swatch.render.mitsuba.engine import mitsuba_lighting, render_swatch_mitsuba

    light = mitsuba_lighting("studio")

    def digests():
        return [_digest(render_swatch_mitsuba(80.0, "sphere", _SIZE, spp, 3, light, roughness_alpha=_LOBE))
                for spp in (3, 8)]

    first = digests()
    render_swatch_mitsuba(0.0, "sphere", 32, 4, 9, light, bsdf_override=_roughconductor())
    again = digests()
    assert again == first and first[0] != first[1]
    env = dict(os.environ, HOME=str(tmp_path), PYTHONPATH=str(ROOT))
    proc = subprocess.run([sys.executable, "-c", _COLD], capture_output=True, text=True, env=env, cwd=ROOT,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / ".drjit").is_dir()  # the cache really was the new, empty one
    assert proc.stdout.strip().splitlines()[-2:] == first


@pytest.mark.slow
def test_the_dispatcher_renders_what_the_engine_renders(mi):
    """#17/#23: ``render_swatch(..., engine="mitsuba")`` is the Mitsuba engine (same bytes and metadata), with
    the coating's tables and film index scale, and the lighting resolved once for that engine. (48 px: the
    size of test_mitsuba_checks.py's white furnace, whose compiled kernel it reuses, #17.)"""
    from swatch.physics.model import get_coating
    from swatch.render import render_swatch
    from swatch.render.lighting import resolve_lighting
    from swatch.render.mitsuba.engine import render_swatch_mitsuba

    coating = get_coating(film_index_scale=0.9)
    light = resolve_lighting("uniform", "mitsuba")
    a = render_swatch(60.0, "sphere", 48, roughness_alpha=0.2, coating=coating, environment=light,
                      engine="mitsuba", spp=4, seed=1)
    b = render_swatch_mitsuba(60.0, "sphere", 48, 4, 1, light, roughness_alpha=0.2, coating=coating)
    assert _digest(a) == _digest(b)
    assert a.metadata == b.metadata
    assert "index scale 0.9" in a.metadata["bsdf"]
    with pytest.raises(Exception, match="builtin engine"):
        render_swatch(60.0, "sphere", 48, environment=resolve_lighting("uniform", "builtin"), engine="mitsuba")
