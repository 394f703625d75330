"""The render request (issue 36): one function checks a render's inputs and names the parameter at fault;
engines render the checked request (swatch.render.ENGINES), and ``render_swatch`` is request + engine."""
from __future__ import annotations

import numpy as np
import pytest

from swatch.core.errors import SwatchError
from swatch.render import ENGINES, RenderRequest, render_request, render_swatch
from swatch.render.lighting import Lighting


@pytest.mark.parametrize(("options", "words"), [
    ({"size_px": 0}, "image size"),
    ({"roughness_alpha": 0.0}, "roughness"),
    ({"light_deg": 95.0}, "`light_deg`"),
    ({"view_deg": 91.0}, "`view_deg`"),
    ({"engine": "povray"}, "`engine`"),
    ({"model": "phong"}, "model"),
    ({"background": "black"}, "background"),
    ({"environment": "sun"}, "`engine='mitsuba'`"),
    ({"exposure": 2.0}, "`exposure`"),
    ({"engine": "mitsuba", "spp": 0}, "samples per pixel"),
    ({"engine": "mitsuba", "seed": -1}, "seed"),
    ({"engine": "mitsuba", "model": "paper"}, "`model='paper'`"),
    ({"engine": "mitsuba", "environment": "point"}, "`environment`"),
    ({"engine": "mitsuba", "background": "grey"}, "`background='environment'`"),
    ({"engine": "mitsuba", "window_px": (0, 0, 40, 1)}, "window_px"),
    ({"engine": "mitsuba", "exposure": 100.0}, "exposure"),
])
def test_one_function_refuses_each_bad_input_naming_it(options, words):
    size = options.pop("size_px", 32)
    with pytest.raises(SwatchError) as err:
        render_request(80.0, "sphere", size, **options)
    assert words in str(err.value)


def test_an_unknown_keyword_is_a_type_error():
    with pytest.raises(TypeError, match="sizepx"):
        render_request(80.0, "sphere", 32, sizepx=3)  # type: ignore[call-arg]


def test_the_request_holds_the_checked_values_and_a_series_reuses_it():
    req = render_request(np.float64(80.0), " Sphere ", 24.0, roughness_alpha=0.2, environment="uniform",
                         engine="BUILTIN")
    assert isinstance(req, RenderRequest)
    assert (req.engine, req.shape, req.size_px, req.lobe, req.background) == ("builtin", "sphere", 24, (0.2,), "grey")
    assert isinstance(req.lighting, Lighting) and req.lighting.kind == "uniform"
    again = req.with_thickness(120.0)
    assert again.thickness_nm == 120.0 and again.lighting is req.lighting and again.scene is req.scene
    with pytest.raises(SwatchError, match="thickness"):
        req.with_thickness(5000.0)
    with pytest.raises(AttributeError):
        req.size_px = 3  # type: ignore[misc]  # frozen


def test_render_swatch_is_the_request_rendered_by_its_engine():
    req = render_request(80.0, "flat", 16, environment=None)
    a = ENGINES["builtin"](req, None)
    b = render_swatch(80.0, "flat", 16, environment=None)
    assert np.array_equal(a.display_rgb, b.display_rgb) and np.array_equal(a.linear_rgb, b.linear_rgb)
    assert a.metadata == b.metadata


def test_a_mitsuba_request_is_checked_without_loading_mitsuba():
    """The request of the mitsuba engine is checked by plain arithmetic (swatch.render.checks): building one
    imports neither Mitsuba nor Dr.Jit."""
    import subprocess
    import sys

    code = ("import sys; from swatch.render import render_request; "
            "r = render_request(80.0, 'sphere', 16, engine='mitsuba', spp=4, environment='uniform'); "
            "print(r.engine, r.spp, r.background, r.exposure, "
            "sorted(m for m in sys.modules if m.split('.')[0] in ('mitsuba', 'drjit')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert out == ["mitsuba", "4", "grey", "1.0", "[]"]


def test_a_mitsuba_request_checks_its_variant():
    """The variant is checked with the request (swatch.render.checks.check_variant), not by the engine."""
    with pytest.raises(SwatchError, match="spectral"):
        render_request(80.0, "sphere", 16, engine="mitsuba", variant="llvm_ad_rgb")
    assert render_request(80.0, "sphere", 16, engine="mitsuba", environment="uniform").variant == "llvm_ad_spectral"
