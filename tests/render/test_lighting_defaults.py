"""Issue #48: one lighting vocabulary, one owner of the defaults. ``render_swatch`` without ``environment``
draws the picture ``swatch render`` draws without ``--environment`` (the studio; the point light for the paper
model), and an option that would change nothing in the picture is refused in one line, not ignored."""
from __future__ import annotations

import numpy as np
import OpenImageIO as oiio
import pytest

from swatch.core.errors import SwatchError
from swatch.render import render_request, render_swatch
from tests.cli_helpers import assert_one_line_error, run_swatch


def _png_pixels(path) -> np.ndarray:
    """The PNG's pixels as OpenImageIO decodes them (a reader we did not write)."""
    buf = oiio.ImageBuf(str(path))
    assert not buf.has_error, buf.geterror()
    return buf.get_pixels(oiio.UINT8)[..., :3]


@pytest.mark.parametrize("extra", [(), ("--model", "paper")])
def test_the_library_default_is_the_commands_default(tmp_path, extra):
    """The same bytes: `swatch render` with no lighting named, and render_swatch with none named."""
    proc = run_swatch("render", "--thickness", "80", "--shape", "sphere", "--size", "48", *extra,
                      "--out", tmp_path / "out")
    assert proc.returncode == 0, proc.stderr
    options = dict(zip(extra[::2], extra[1::2], strict=True))
    img = render_swatch(80.0, "sphere", 48, model=options.get("--model", "microfacet"))
    assert np.array_equal(_png_pixels(tmp_path / "out" / "sphere_080.0nm.png"), img.display_rgb[..., :3])
    want = "studio" if not extra else "point"
    assert render_request(80.0, "sphere", 48, **({"model": "paper"} if extra else {})).lighting.kind == want


def test_the_point_light_is_named_point_everywhere():
    req = render_request(80.0, "flat", 16, environment="POINT", light_deg=10.0)
    assert (req.lighting.kind, req.lighting.name, req.light_deg) == ("point", "point", 10.0)
    with pytest.raises(SwatchError, match="unknown environment 'none'; use one of point, uniform, studio"):
        render_request(80.0, "flat", 16, environment="none")


@pytest.mark.parametrize(("options", "words"), [
    ({"light_deg": 10.0}, "`light_deg` places the point light, and the studio lighting has none"),
    ({"light_deg": 45.0, "environment": "uniform"}, "the uniform lighting has none; drop it, or add `environment='point'`"),
    ({"light_deg": 45.0, "engine": "mitsuba"}, "the mitsuba engine has none"),
    ({"spp": 3}, "`spp` is an option of the mitsuba engine; add `engine='mitsuba'`"),
    ({"seed": 9, "environment": "point"}, "`seed` is an option of the mitsuba engine"),
    ({"denoise": False}, "`denoise` is an option of the mitsuba engine"),
    ({"exposure": 2.0}, "`exposure` is an option of the mitsuba engine"),
    ({"roughness_alpha": 0.2, "finish": "satin"}, "`roughness_alpha` is the `finish`'s"),
])
def test_an_option_that_would_change_nothing_is_refused(options, words):
    from swatch.physics.finishes import get_finish

    if "finish" in options:
        options = options | {"finish": get_finish(options["finish"])}
    with pytest.raises(SwatchError) as err:
        render_request(80.0, "sphere", 32, **options)
    assert words in str(err.value)


def test_the_options_are_taken_where_they_change_the_picture():
    from swatch.physics.finishes import get_finish

    assert render_request(80.0, "sphere", 32, light_deg=10.0, environment="point").light_deg == 10.0
    req = render_request(80.0, "sphere", 32, engine="mitsuba", spp=3, seed=9, denoise=False, exposure=2.0)
    assert (req.spp, req.seed, req.denoise, req.exposure) == (3, 9, None, 2.0)
    assert render_request(80.0, "sphere", 32, finish=get_finish("satin")).finish is not None


@pytest.mark.parametrize(("args", "words"), [
    (["--light", "80"], ["--light places the point light", "--environment point"]),
    (["--spp", "3", "--seed", "9"], ["--spp is an option of the mitsuba engine; add --engine mitsuba"]),
    (["--no-denoise"], ["--denoise is an option of the mitsuba engine"]),
    (["--keep-raw"], ["--keep-raw", "--engine mitsuba"]),
    (["--environment", "none"], ["unknown environment 'none'", "point, uniform, studio"]),
    (["--finish", "satin", "--roughness", "0.2"], ["a finish or a roughness, not both"]),
])
def test_the_command_refuses_them_in_one_line(tmp_path, args, words):
    proc = run_swatch("render", "--thickness", "80", "--size", "16", *args, "--out", tmp_path / "out")
    assert proc.returncode == 2
    assert_one_line_error(proc, *words)
    assert not (tmp_path / "out").exists()


def test_names_take_any_case_on_the_command_line(tmp_path):
    import json

    a = run_swatch("match", "--hex", "2579b8", "--scheme", "CSAJ", "--grade", "B", "--json")
    b = run_swatch("match", "--hex", "2579b8", "--scheme", "csaj", "--grade", "B", "--json")
    assert a.returncode == 0 == b.returncode, a.stderr
    assert a.stdout == b.stdout and json.loads(a.stdout)["tolerance"]["scheme"] == "csaj"
    assert_one_line_error(run_swatch("match", "--hex", "2579b8", "--scheme", "jis"),
                          "unknown tolerance scheme 'jis' for --scheme; use one of csaj, nbs")
    proc = run_swatch("render", "--thickness", "80", "--size", "16", "--engine", "BuiltIn", "--model", "Paper",
                      "--out", tmp_path / "out")
    assert proc.returncode == 0, proc.stderr
