"""Issue #48: one small case-insensitive registry (name -> implementation, description) for the engines,
lightings, intensity models, microfacet distributions, tolerance metrics and schemes."""
from __future__ import annotations

import numpy as np
import pytest

from swatch.core.errors import SwatchError
from swatch.core.registry import Registry


def _toy() -> Registry:
    return Registry("shape", "shape", {"flat": ("F", "a plate"), "dE00": ("D", "a symbol")})


def test_names_are_found_in_any_case_and_kept_in_their_spelling():
    r = _toy()
    assert r.validate(" FLAT ") == "flat" and r.validate("de00") == "dE00"
    assert r["Flat"] == "F" and r["DE00"] == "D"
    assert "FLAT" in r and "round" not in r and 3 not in r
    assert r.names() == ("flat", "dE00") and list(r) == ["flat", "dE00"] and len(r) == 2
    assert r.description("FLAT") == "a plate"
    assert r.help() == "flat: a plate; dE00: a symbol"


def test_an_unknown_name_is_refused_naming_the_parameter_and_the_choices():
    with pytest.raises(SwatchError) as err:
        _toy().validate("round")
    assert str(err.value) == "unknown shape 'round' for `shape`; use one of flat, dE00"
    with pytest.raises(SwatchError, match="use one of flat, dE00"):
        _toy()["round"]


def test_a_declared_name_waits_for_its_implementation():
    r = Registry.declare("engine", "engine", {"fast": "the quick one"})
    with pytest.raises(LookupError, match="no implementation"):
        r["fast"]
    r.implement("fast", len)
    assert r["FAST"] is len
    with pytest.raises(KeyError):
        r.implement("slow", len)
    with pytest.raises(ValueError, match="differ only in case"):
        Registry("x", "x", {"a": (1, ""), "A": (2, "")})


def test_one_engine_registry_the_cli_offers_and_the_dispatcher_runs():
    from swatch.commands.render import render
    from swatch.core import choices
    from swatch.render import ENGINES
    from swatch.render.dispatch import render_builtin

    assert ENGINES is choices.ENGINES
    assert ENGINES["BuiltIn"] is render_builtin
    option = next(p for p in render.params if p.name == "engine")
    assert tuple(option.type.choices) == ENGINES.names() and option.type.case_sensitive is False


def test_lightings_name_the_engines_that_render_them():
    from swatch.catalog.explorer_env import PAGE_LIGHTINGS
    from swatch.core.choices import ENGINES, LIGHTINGS, POINT_LIGHT, lightings_of

    assert POINT_LIGHT == "point" and "none" not in LIGHTINGS
    assert all(set(engines) <= set(ENGINES) for engines in LIGHTINGS.values())
    # the page's live view: the built-in engine's, the point light first (the names its links and JS use)
    assert PAGE_LIGHTINGS == lightings_of("builtin") == ("point", "uniform", "studio")
    assert lightings_of("mitsuba") == ("uniform", "studio", "sun")


def test_distributions_and_models_run_through_their_registries():
    from swatch.physics import microfacet
    from swatch.render.builtin import shading
    c = np.linspace(0.2, 1.0, 9)
    a = 0.3
    # Beckmann's D written out here (Walter et al. 2007, eq. 25), not taken from the module
    t2 = (1 - c**2) / c**2
    beckmann = np.exp(-t2 / a**2) / (np.pi * a**2 * c**4)
    np.testing.assert_allclose(microfacet.D(c, a, "BECKMANN"), beckmann, rtol=1e-12)
    # GGX's Smith Lambda (Heitz 2014, eq. 72)
    np.testing.assert_allclose(microfacet.smith_lambda(c, a, " GGX"), 0.5 * (np.sqrt(1 + a * a * t2) - 1), rtol=1e-12)
    with pytest.raises(SwatchError, match="`distribution`; use one of ggx, beckmann"):
        microfacet.D(c, a, "phong")
    assert shading.check_model("Paper") == "paper"
    cl = np.array([0.5, -0.1, 0.5])
    cv = np.array([0.5, 0.5, 0.0])
    assert shading.intensity(cl, cv, cl, cl, "PAPER").tolist() == [1.0, 0.0, 0.0]
    with pytest.raises(SwatchError, match="`model`; use one of paper, microfacet"):
        shading.check_model("phong")


def test_tolerance_metrics_and_schemes_in_any_case():
    import colour

    from swatch.colorimetry import tolerance

    lab1, lab2 = np.array([50.0, 20.0, -30.0]), np.array([52.0, 18.0, -25.0])
    want = colour.delta_E(lab1, lab2, method="CIE 2000")
    assert float(tolerance.delta_E("de00", lab1, lab2)) == pytest.approx(float(want), rel=1e-12)
    assert float(tolerance.METRICS["DEAB"](lab1, lab2)) == pytest.approx(float(np.linalg.norm(lab1 - lab2)), rel=1e-12)
    assert tolerance.METRICS.description("dE00") == "CIEDE2000 ΔE00"
    assert tolerance.check_scheme(" CSAJ ") == "csaj" and tolerance.schemes() == ["csaj", "nbs"]
    assert tolerance.get_tolerance("NBS", "Slight") == tolerance.get_tolerance("nbs", "slight")
    assert tolerance.get_tolerance("CSAJ", "b").scheme == "csaj"
    assert tolerance.grades("Csaj") == tolerance.grades("csaj")
    with pytest.raises(SwatchError, match="unknown tolerance scheme 'jis' for `scheme`; use one of csaj, nbs"):
        tolerance.grades("jis")
    with pytest.raises(SwatchError, match="unknown colour-difference metric 'dE94'"):
        tolerance.get_tolerance(metric="dE94", max=2.0)
