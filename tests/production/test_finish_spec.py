"""The typed finish spec (issue 48): one checked object through production/, JSON only at the file edges;
a named grade survives the round trip through spec.json."""
from __future__ import annotations

import json

import pytest

from swatch.colorimetry.tolerance import get_tolerance
from swatch.core.errors import SwatchError
from swatch.physics.process import load_process
from swatch.production.finish import FinishSpec
from swatch.production.qc import load_spec_json
from swatch.production.spec import finish_spec


@pytest.fixture(scope="module")
def made():
    target = {"kind": "thickness", "value": 120.0, "thickness_nm": 120.0}
    return finish_spec(target, load_process("titanium-fujii2019"), get_tolerance("csaj", "B"))


def test_a_named_grade_survives_spec_json(made, tmp_path):
    path = tmp_path / "spec.json"
    path.write_text(json.dumps(made.document, indent=2), encoding="utf-8")
    back = load_spec_json(path)
    assert (back.tolerance.scheme, back.tolerance.grade) == ("csaj", "B")
    assert back.tolerance == made.tolerance == get_tolerance("csaj", "B")
    assert back == made  # every typed field the same; the document is compared as JSON below
    assert json.dumps(back.document) == json.dumps(made.document)


def test_the_typed_fields_are_the_documents(made):
    doc = made.document
    assert made.thickness_nm == doc["nominal"]["thickness_nm"] == 120.0
    assert [g.name for g in made.geometries] == [doc["reference"]["geometry"],
                                                 *(e["geometry"] for e in doc["multi_angle"])]
    assert [list(g.Lab) for g in made.geometries] == [doc["reference"]["Lab"], *(e["Lab"] for e in doc["multi_angle"])]
    assert made.judged == ("45:0",) and made.reach is None
    assert made.model.nm_per_V == doc["process"]["nm_per_V"] and made.calibrated_model is False


@pytest.mark.parametrize("spoil", [
    lambda d: d["tolerance"].update(grade=3),
    lambda d: d["tolerance"].update(metric="dE94x"),
    lambda d: d["reference"].update(Lab=[50.0, 1.0]),
    lambda d: d["reference"].update(view_side="below"),
    lambda d: d["process"].pop("film"),
    lambda d: d["process"].update(nm_per_V=float("inf")),
    lambda d: d["tolerance"].update(geometries=["45:61"]),
    lambda d: d["process_window"].update(thickness_minus_nm=[1]),  # (swatch check died on float([1]))
    lambda d: d["process_window"].update(thickness_plus_nm=-2.0),
    lambda d: d.update(process_window=[1, 2]),
    lambda d: d["process"].update(film_index_scale=-5.0),  # a profile allows 0.5 to 1.5
    lambda d: d["process"].update(spread_fraction=1e9),
    lambda d: d["process"].update(offset_nm=float("nan")),
])
def test_a_spoiled_document_is_refused_in_one_sentence(made, spoil):
    doc = json.loads(json.dumps(made.document))
    spoil(doc)
    with pytest.raises(SwatchError, match=r"^x\.json: a value of the spec is missing"):
        FinishSpec.from_json(doc, "x.json")
