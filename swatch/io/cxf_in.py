"""CxF3 measurement files (ISO 17972-1; X-Rite, Konica Minolta, Datacolor) read with colour-cxf.

Each ``Object`` is a sample (named by its ``Name``, else its ``Id``). Its ``ReflectanceSpectrum``
and ``ColorCIELab`` values point to a ``ColorSpecification``, whose ``MeasurementSpec`` gives the
geometry (``SingleAngle``: illumination and measurement angle; ``MultiAngle``: one ``BRDFAngle``
with illumination and aspecular angle, ASTM E2194 / E2539) and the wavelength increment, and
whose ``TristimulusSpec`` gives the illuminant and observer the CIELAB is relative to. A sample
is read as spectra when every geometry has a spectrum, else as CIELAB (which then needs the
white point: a ``TristimulusSpec`` naming a CIE illuminant and observer).

Refused in one line: XML that is not well formed, a document type declaration (anywhere: lxml parses
with DTD and entity loading off and reports it) or an entity reference (the XML must not pull in other
files or expand entities), XML that is not a CxF3 document, transmittance or emissive spectra,
diffuse or annular off-normal geometries, several white points in one file, values that are
not finite numbers (a CIELAB value is checked even where spectra decide), a spectrum of more than
MAX_WAVELENGTHS values, a ``StartWL`` and ``Increment`` whose wavelengths
:func:`swatch.io.measurements.check_spectral_axis` refuses, two samples of one name, and samples
measured at different geometries.
"""
from __future__ import annotations

import warnings

import numpy as np
from colour_cxf.cxf3 import CxF
from lxml import etree
from xsdata.exceptions import ConverterWarning, ParserError
from xsdata.formats.dataclass.context import XmlContext
from xsdata.formats.dataclass.parsers import XmlParser
from xsdata.formats.dataclass.parsers.config import ParserConfig

from swatch.core.errors import SwatchError
from swatch.core.limits import MAX_INSTRUMENT_GEOMETRIES, MAX_INSTRUMENT_SAMPLES, MAX_WAVELENGTHS
from swatch.io.instruments import (
    InstrumentFile,
    Request,
    Sample,
    aspecular_geometry,
    check_agrees,
    check_lab,
    lab_sample,
    parse_illuminant,
    parse_observer,
    same_geometries,
    spectral_sample,
)
from swatch.io.measurements import uniform_spectral_axis

__all__ = ["is_cxf", "read_cxf3"]

_CXF3_NS = "http://colorexchangeformat.com/CxF3-core"


def is_cxf(data: bytes) -> bool:
    r"""Whether ``data`` is XML (a CxF file is; any other XML is refused by :func:`read_cxf3`).

    Parameters
    ----------
    data : bytes
        The file's first bytes (a UTF-8 byte-order mark and white space are skipped).

    Returns
    -------
    bool
        True when the first non-blank character is ``<`` (the bytes are then read as CxF3).

    Examples
    --------
    >>> is_cxf(b"\xef\xbb\xbf <?xml version='1.0'?>"), is_cxf(b"L,a,b")
    (True, False)
    """
    head = data[:512].lstrip(b"\xef\xbb\xbf \t\r\n")
    return head.startswith(b"<")


def _parse(data: bytes, source: str):
    """The CxF3 document of ``data``: parsed strictly by lxml (no DTD, no entities, no network), then bound
    to colour-cxf's classes by xsdata with converter warnings as errors."""
    parser = etree.XMLParser(resolve_entities=False, load_dtd=False, no_network=True, dtd_validation=False,
                             recover=False, huge_tree=False, remove_comments=True, remove_pis=True)
    try:
        tree = etree.fromstring(data, parser).getroottree()
    except etree.XMLSyntaxError as exc:
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise SwatchError(f"{source}: not well-formed XML ({first[:160]}); give a CxF3 file as the instrument "
                          "software exports it") from None
    info = tree.docinfo
    if info.doctype or info.internalDTD is not None or info.externalDTD is not None or info.system_url:
        raise SwatchError(f"{source}: the XML declares a document type or entities; a CxF3 file has neither "
                          "(refused: it could pull in other files or expand without bound)")
    if etree.QName(tree.getroot()).namespace != _CXF3_NS:
        raise SwatchError(f"{source}: not a CxF3 document (no element in the namespace {_CXF3_NS}); export CxF3 "
                          "from the instrument software")
    if any(isinstance(el, etree._Entity) for el in tree.getroot().iter()):
        raise SwatchError(f"{source}: the XML holds an entity reference; a CxF3 file's values are plain text")
    _check_spectrum_sizes(tree.getroot(), source)
    xml_parser = XmlParser(context=XmlContext(), config=ParserConfig(fail_on_converter_warnings=True))
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", ConverterWarning)
            return xml_parser.parse(tree, CxF)
    except (ParserError, ConverterWarning, ValueError, TypeError, SyntaxError) as exc:
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        detail = " ".join(str(exc).split())[:160] if first.startswith("Failed to convert") else first[:160]
        raise SwatchError(f"{source}: not a valid CxF3 document ({detail})") from None


def _check_spectrum_sizes(root, source: str) -> None:
    """Refuse a ReflectanceSpectrum of more than MAX_WAVELENGTHS values from the XML text, before xsdata binds
    the document (it converts every value in Python: 2 s of CPU for a million); :func:`read_cxf3` checks the
    bound values again (both bounds)."""
    for k, obj in enumerate(root.iter(f"{{{_CXF3_NS}}}Object")):
        for el in obj.iter(f"{{{_CXF3_NS}}}ReflectanceSpectrum"):
            count = len((el.text or "").split())
            if count > MAX_WAVELENGTHS:
                name = obj.get("Name") or obj.get("Id") or str(k + 1)
                raise SwatchError(f"{source}: object {name!r}: a ReflectanceSpectrum of {count} values; a "
                                  f"spectrum has 2 to {MAX_WAVELENGTHS} values")


def _spec_geometry(spec, source: str, request: Request):
    """(light_deg, signed view_deg) of a ColorSpecification, or None when it states none."""
    ms = getattr(spec, "measurement_spec", None)
    if ms is not None and ms.measurement_type is not None:
        kind = str(getattr(ms.measurement_type.value, "value", ms.measurement_type.value))
        if kind and kind != "Spectrum_Reflectance":
            raise SwatchError(f"{source}: ColorSpecification {spec.id!r} is a {kind} measurement; swatch reads "
                              "reflectance (Spectrum_Reflectance)")
    gc = getattr(ms, "geometry_choice", None) if ms is not None else None
    raw = getattr(gc, "choice", None)
    choice = list(raw) if isinstance(raw, (list, tuple)) else ([] if raw is None else [raw])
    if not choice:
        return None
    if len(choice) > 1:
        raise SwatchError(f"{source}: ColorSpecification {spec.id!r} gives several geometries; one per specification")
    g = choice[0]
    if hasattr(g, "brdfangle"):
        if len(g.brdfangle) != 1:
            raise SwatchError(f"{source}: ColorSpecification {spec.id!r} has {len(g.brdfangle)} BRDFAngles; a multi-angle "
                              "value needs exactly one (illumination and aspecular angle)")
        b = g.brdfangle[0]
        if b.illumination_angle is None or b.aspecular is None:
            raise SwatchError(f"{source}: ColorSpecification {spec.id!r}: a BRDFAngle needs IlluminationAngle and "
                              "Aspecular")
        if b.azimuth not in (None, 0, 0.0):
            raise SwatchError(f"{source}: ColorSpecification {spec.id!r}: out-of-plane BRDFAngle (Azimuth "
                              f"{b.azimuth:g}°); swatch reads in-plane multi-angle geometries")
        return aspecular_geometry(float(b.illumination_angle), float(b.aspecular), source)
    if hasattr(g, "illumination_angle") and hasattr(g, "measurement_angle"):
        if g.illumination_angle is None or g.measurement_angle is None:
            return None
        light, view = float(g.illumination_angle), float(g.measurement_angle)
        conf = getattr(getattr(g, "single_angle_configuration", None), "value", None)
        conf = str(getattr(conf, "value", conf) or "")
        if conf in ("Annular", "Circumferential") and light and view:
            raise SwatchError(f"{source}: ColorSpecification {spec.id!r}: {conf} {light:g}/{view:g} averages over "
                              "azimuth; swatch reads in-plane geometries (or annular with one angle 0)")
        return light, view
    raise SwatchError(f"{source}: ColorSpecification {spec.id!r}: a {type(g).__name__} geometry (sphere or "
                      "other); swatch models directional geometries such as 45/0")


def _white(spec):
    """(illuminant name, observer) stated by a ColorSpecification's TristimulusSpec, or (None, None)."""
    ts = getattr(spec, "tristimulus_spec", None)
    if ts is None:
        return None, None
    ill = ts.illuminant_or_custom_illuminant
    ill_name = None
    if ill is not None:
        value = getattr(ill, "value", None)
        value = str(getattr(value, "value", value) or "")
        ill_name = "custom" if not hasattr(ill, "value") or value in ("", "Custom") else value
    obs = None
    if ts.observer is not None and ts.observer.value is not None:
        obs = str(getattr(ts.observer.value, "value", ts.observer.value))
    return ill_name, obs


def _tags(obj, source: str, name: str) -> tuple[float | None, float | None]:
    """(voltage_V, thickness_nm) from an object's tags (``voltage_V``, ``thickness_nm``), where present."""
    found: dict[str, float] = {}
    for tc in obj.tag_collection or []:
        for tag in tc.tag or []:
            if tag.name in ("voltage_V", "thickness_nm") and tag.value not in (None, "", "None"):
                try:
                    found[tag.name] = float(tag.value)
                except ValueError:
                    raise SwatchError(f"{source}: object {name!r}: tag {tag.name} {tag.value!r} is not a number") from None
    return found.get("voltage_V"), found.get("thickness_nm")


def read_cxf3(data: bytes, source: str, request: Request) -> InstrumentFile:
    """Read a CxF3 document's objects into samples (see the module docstring).

    A document that declares a DOCTYPE or entities is refused unread (it could pull in other files or
    expand without bound); the parser is colour-cxf's (xsdata), on the document's bytes.

    Parameters
    ----------
    data : bytes
        The document (already size-capped by the caller).
    source : str
        Names the file in messages.
    request : swatch.io.instruments.Request
        The command line's conditions; a contradicting explicit option is refused.

    Returns
    -------
    swatch.io.instruments.InstrumentFile
        Format ``"cxf3"``: one sample per ``Object`` (CIELAB or reflectance spectra at their colour
        specification's geometries; ``voltage_V`` / ``thickness_nm`` tags for coupons).

    Raises
    ------
    swatch.core.errors.SwatchError
        Not a CxF3 document, no or too many objects, unsupported or contradictory specifications, bad values.
    """
    doc = _parse(data, source)
    res = doc.resources
    specs = {}
    if res is not None and res.color_specification_collection is not None:
        specs = {s.id: s for s in res.color_specification_collection.color_specification}
    objects = list(res.object_collection.object_value) if res is not None and res.object_collection else []
    if not objects:
        raise SwatchError(f"{source}: the CxF3 document holds no Object (no samples)")
    if len(objects) > MAX_INSTRUMENT_SAMPLES:
        raise SwatchError(f"{source}: {len(objects)} objects; a file holds at most {MAX_INSTRUMENT_SAMPLES} samples")
    cli_geom = (request.light_deg, request.view_deg)
    samples: list[Sample] = []
    whites: set[tuple] = set()
    stated_geom = set()
    stated_whites: set[tuple] = set()
    for obj in objects:
        name = str(obj.name or obj.id or len(samples) + 1)
        spectra, labs = {}, {}
        for v in (obj.color_values.choice if obj.color_values is not None else []):
            kind = type(v).__name__
            if kind not in ("ReflectanceSpectrum", "ColorCielab", "TransmittanceSpectrum", "EmissiveSpectrum"):
                continue
            if kind in ("TransmittanceSpectrum", "EmissiveSpectrum"):
                raise SwatchError(f"{source}: object {name!r} holds a {kind}; swatch reads reflectance")
            spec = specs.get(v.color_specification)
            if v.color_specification is not None and spec is None:
                raise SwatchError(f"{source}: object {name!r} refers to ColorSpecification "
                                  f"{v.color_specification!r}, which the file does not define")
            geom = _spec_geometry(spec, source, request) if spec is not None else None
            if geom is not None:
                stated_geom.add(geom)
                check_agrees(source, "geometry", geom, "its ColorSpecification", request, "geometry", cli_geom,
                             "`light_deg`/`view_deg`")
            geom = geom if geom is not None else cli_geom
            if kind == "ReflectanceSpectrum":
                inc = getattr(getattr(getattr(spec, "measurement_spec", None), "wavelength_range", None),
                              "increment", None)
                start = v.start_wl if v.start_wl is not None else getattr(
                    getattr(getattr(spec, "measurement_spec", None), "wavelength_range", None), "start_wl", None)
                if inc is None or start is None:
                    raise SwatchError(f"{source}: object {name!r}: a ReflectanceSpectrum needs StartWL and its "
                                      "ColorSpecification's WavelengthRange Increment")
                if spec is not None and None not in _white(spec):
                    stated_whites.add(_white(spec))
                count = len(v.value or ())
                if not 2 <= count <= MAX_WAVELENGTHS:
                    raise SwatchError(f"{source}: object {name!r}: a ReflectanceSpectrum of {count} values; a "
                                      f"spectrum has 2 to {MAX_WAVELENGTHS} values")
                vals = np.asarray(v.value, dtype=np.float64)
                spectra[geom] = (uniform_spectral_axis(start, inc, vals.size, source, f"object {name!r}: StartWL",
                                                       f"object {name!r}: WavelengthRange Increment"), vals)
            else:
                lab = [v.l, v.a, v.b]
                if any(x is None or isinstance(x, str) for x in lab):  # absent, or empty (xsdata keeps "")
                    raise SwatchError(f"{source}: object {name!r}: a ColorCIELab without "
                                      f"{'/'.join(c for c, x in zip('LAB', lab, strict=True) if x is None or isinstance(x, str))}; "
                                      "give L, A and B as numbers")
                check_lab(source, name, lab)  # checked even where spectra decide: a bad value is a bad file
                labs[geom] = (lab, _white(spec) if spec is not None else (None, None))
        geoms = list(dict.fromkeys([*spectra, *labs]))
        if not geoms:
            raise SwatchError(f"{source}: object {name!r} has no ReflectanceSpectrum or ColorCIELab value")
        if len(geoms) > MAX_INSTRUMENT_GEOMETRIES:
            raise SwatchError(f"{source}: object {name!r} has {len(geoms)} geometries; at most "
                              f"{MAX_INSTRUMENT_GEOMETRIES}")
        if all(g in spectra for g in geoms):
            wl0 = spectra[geoms[0]][0]
            if any(spectra[g][0].shape != wl0.shape or not np.allclose(spectra[g][0], wl0) for g in geoms):
                raise SwatchError(f"{source}: object {name!r}: its spectra are on different wavelengths")
            samples.append(spectral_sample(source, name, geoms, wl0, np.stack([spectra[g][1] for g in geoms]),
                                           request.percent, *_tags(obj, source, name)))
        else:
            if any(lab[0][i] is None for lab in labs.values() for i in range(3)) or set(labs) != set(geoms):
                raise SwatchError(f"{source}: object {name!r}: every geometry needs L, A and B (or a spectrum)")
            whites |= {w for _, w in labs.values()}
            samples.append(lab_sample(source, name, geoms, [labs[g][0] for g in geoms], *_tags(obj, source, name)))
    out = tuple(samples)
    same_geometries(out, source)
    stated: dict = {}
    ill, obs = request.illuminant, request.observer
    if not whites and stated_whites:  # spectra: the white the file's own colorimetry was computed under
        whites = stated_whites
    if whites:
        if len(whites) > 1:
            raise SwatchError(f"{source}: the CIELAB values use several white points "
                              f"({', '.join(sorted(f'{i}/{o}' for i, o in whites))}); a file holds one")
        w_ill, w_obs = next(iter(whites))
        if w_ill is None or w_obs is None:
            missing = [n for n, v in (("illuminant", w_ill), ("observer", w_obs)) if v is None]
            if not all(m in request.given for m in missing):
                raise SwatchError(f"{source}: CIELAB without a white point: its ColorSpecification states no "
                                  f"{' or '.join(missing)}; give `illuminant` and `observer` as measured")
        if w_ill == "custom":
            raise SwatchError(f"{source}: CIELAB under a custom illuminant; swatch reads CIE illuminants "
                              "(or give the spectra)")
        if w_ill is not None:
            ill = parse_illuminant(w_ill, source)
            stated["illuminant"] = ill
            if "illuminant" in request.given:
                check_agrees(source, "illuminant", ill, "TristimulusSpec", request, "illuminant",
                             parse_illuminant(request.illuminant, "`illuminant`"), "`illuminant`")
        if w_obs is not None:
            obs = parse_observer(w_obs, source)
            stated["observer"] = obs
            if "observer" in request.given:
                check_agrees(source, "observer", obs, "TristimulusSpec", request, "observer",
                             parse_observer(request.observer, "`observer`"), "`observer`")
    if stated_geom:
        stated["geometry"] = ", ".join(f"{a:g}:{b:g}" for a, b in sorted(stated_geom))
    return InstrumentFile(source, "cxf3", out, ill, obs, stated)
