"""Exports designers import: CxF3 (spectral reflectance and Lab per swatch) and Adobe Swatch Exchange.

* CxF3 is written with colour-science's own CxF library, ``colour-cxf`` (xsdata bindings of the
  CxF3-core schema). One ``ColorSpecification`` per geometry — the reference geometry
  (``SingleAngle``, e.g. 45°:0°) and each multi-angle geometry (``MultiAngle`` with one
  ``BRDFAngle``: illumination and aspecular angle) — each with the illuminant, observer and
  wavelength grid; every swatch is an ``Object`` with CIELab, LCh and the reflectance spectrum
  at every geometry, and sRGB at the reference. The schema requires a creation date: a fixed
  date (1970-01-01T00:00:00Z) keeps builds byte-identical (no clock).
* ASE (Adobe Swatch Exchange, binary, big-endian): ``ASEF``, version 1.0, a group named after
  the catalog holding one global colour per swatch, named ``S001 Ti 20 nm (9.8 V) straw``. Adobe
  applications and GIMP read ASE Lab as D50 with the 2° observer (the ICC connection space,
  ISO 13655), so the ``LAB`` file holds the spectrum at the reference geometry under D50 and the
  CIE 1931 2° observer (L as 0–1, a, b as floats), not the catalog's own Lab; the ``RGB``
  variant (``<slug>-srgb.ase``, for importers without Lab) holds the sRGB hex code as 0–1
  floats (from 2° colorimetry under the catalog's illuminant, like every hex code).
"""
from __future__ import annotations

import struct

from colour_cxf import cxf3
from xsdata.formats.dataclass.serializers import XmlSerializer
from xsdata.formats.dataclass.serializers.config import SerializerConfig
from xsdata.models.datatype import XmlDateTime

from swatch.catalog.spec import CatalogSpec
from swatch.colorimetry.colorimeter import Lab_to_LCh

__all__ = ["ase_bytes", "cxf_bytes", "ase_name", "metal_symbol", "FIXED_DATE", "ASE_MODELS"]

FIXED_DATE = "1970-01-01T00:00:00Z"

# CxF3 enumerations (colour_cxf.cxf3.EilluminantType) for colour-science's illuminant names.
_CXF_ILLUMINANTS = {
    "A": "A", "B": "B", "C": "C", "D50": "D50", "D55": "D55", "D60": "D60", "D65": "D65", "D75": "D75",
    "E": "E", "FL2": "F2", "FL3": "F3", "FL7": "F7", "FL9": "F9", "FL10": "F10", "FL11": "F11", "FL12": "F12",
}


#: ASE colour models we write: the file's model tag and what its values are.
ASE_MODELS = {"lab": b"LAB ", "srgb": b"RGB "}


def metal_symbol(spec: CatalogSpec) -> str:
    """The substrate's element (``Ti`` for ``Ti-Johnson``), for swatch names.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.

    Returns
    -------
    str
        The element symbol (``Ti``, ``Nb``, ``Ta``).
    """
    return spec.substrate.split("-")[0]


def ase_name(rec: dict, metal: str = "Ti") -> str:
    """A swatch's name in the exports: ID, metal, thickness (0.1 nm), voltage (none without a growth rate)
    and colour name (:mod:`swatch.colorimetry.names`, as the sheets and the page say it).

    Parameters
    ----------
    rec : dict
        The record.
    metal : str
        The substrate's element symbol.

    Returns
    -------
    str
        The swatch's name: ID, metal, thickness (nm), voltage (V, in brackets) and colour name.

    Examples
    --------
    >>> ase_name({"id": "S001", "thickness_nm": 20.0, "voltage_V": 9.84, "colour_name": "straw"})
    'S001 Ti 20 nm (9.8 V) straw'
    """
    volts = "" if rec["voltage_V"] is None else f" ({rec['voltage_V']:.1f} V)"
    name = f" {rec['colour_name']}" if rec.get("colour_name") else ""
    return f"{rec['id']} {metal} {round(rec['thickness_nm'], 1):g} nm{volts}{name}"


# -- Adobe Swatch Exchange -------------------------------------------------------------------

def _utf16_name(name: str) -> bytes:
    raw = name.encode("utf-16-be") + b"\x00\x00"
    return struct.pack(">H", len(raw) // 2) + raw


def ase_bytes(spec: CatalogSpec, records: list[dict], model: str = "lab") -> bytes:
    """The Adobe Swatch Exchange file: one group (the catalog's name) of global colours.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.
    records : list of dict
        The swatches' records (JSON view).
    model : str
        ``"lab"``: CIELAB under D50, CIE 1931 2° at the reference geometry (``Lab_D50_2``, how Adobe
        applications read ASE Lab); ``"srgb"``: the records' sRGB hex codes as 0–1 floats.

    Returns
    -------
    bytes
        The Adobe Swatch Exchange file.

    Raises
    ------
    ValueError
        An unknown ``model`` (a programming error: the build passes one of :data:`ASE_MODELS`).
    """
    if model not in ASE_MODELS:
        raise ValueError(f"ASE model {model!r}; use one of {', '.join(ASE_MODELS)}")
    metal = metal_symbol(spec)
    blocks = []
    blocks.append((0xC001, _utf16_name(spec.name)))
    for rec in records:
        values: tuple[float, ...]
        if model == "lab":
            L, a, b = rec["Lab_D50_2"]
            values = (L / 100.0, a, b)
        else:
            values = tuple(int(rec["srgb_hex"][i:i + 2], 16) / 255.0 for i in (1, 3, 5))
        body = (_utf16_name(ase_name(rec, metal)) + ASE_MODELS[model] + struct.pack(">fff", *values)
                + struct.pack(">H", 0))
        blocks.append((0x0001, body))
    blocks.append((0xC002, b""))
    out = [b"ASEF", struct.pack(">HHI", 1, 0, len(blocks))]
    for kind, body in blocks:
        out.append(struct.pack(">HI", kind, len(body)))
        out.append(body)
    return b"".join(out)


# -- CxF3 ------------------------------------------------------------------------------------

def cxf_bytes(spec: CatalogSpec, data) -> bytes:
    """The CxF3 document (ISO 17972-1, UTF-8 XML) of a computed catalog: every swatch's reflectance spectrum
    and CIELAB / LCh at the reference and the multi-angle geometries, with their colour specifications.

    Parameters
    ----------
    spec : swatch.catalog.spec.CatalogSpec
        The validated catalog spec.
    data : swatch.catalog.records.CatalogData
        The computed records (their spectra).

    Returns
    -------
    bytes
        Deterministic (a fixed creation date).
    """

    date = XmlDateTime.from_string(FIXED_DATE)
    wl = data.wavelength_nm
    start, inc = round(wl[0]), round(wl[1] - wl[0])
    # colour.sd_to_XYZ's ASTM E308 practice: 1 and 5 nm data are weighted by the 1 nm tables at the
    # data's wavelengths; 10 and 20 nm data by weights for bandpass-corrected data (Table 6).
    method = cxf3.EastmTableType.E308_1NM if inc in (1, 5) else cxf3.EastmTableType.E308_TABLE6

    # the build's colorimeters (its context): the catalog's, the ICC PCS's (D50, 2°) and the display's (the
    # catalog's illuminant, 2°: sRGB's definition) — the three specifications below
    ctx = data.context
    colorimeters = {(data.illuminant, data.observer): ctx.colorimeter, ("D50", "2"): ctx.colorimeter_icc,
                    (data.illuminant, "2"): ctx.colorimeter.display_colorimeter}

    def tristimulus(illuminant_name: str, observer: str) -> cxf3.TristimulusSpec:
        white = colorimeters[(illuminant_name, observer)].white_XYZ  # Y = 100
        xyz = dict(x=round(float(white[0]), 4), y=round(float(white[1]), 4), z=round(float(white[2]), 4))
        ill_name = _CXF_ILLUMINANTS.get(illuminant_name)
        if ill_name is not None:
            illuminant = cxf3.Illuminant(value=cxf3.EilluminantType(ill_name), **xyz)
        else:
            illuminant = cxf3.Illuminant(value=cxf3.EilluminantType.CUSTOM, name=illuminant_name, **xyz)
        return cxf3.TristimulusSpec(
            illuminant_or_custom_illuminant=illuminant,
            observer=cxf3.Observer(value=cxf3.EobserverType("10_Degree" if observer == "10" else "2_Degree")),
            method=cxf3.Method(value=method),
        )

    def colour_spec(cs_id: str, geometry_choice, illuminant_name=data.illuminant,
                    observer=data.observer) -> cxf3.ColorSpecification:
        return cxf3.ColorSpecification(
            id=cs_id,
            tristimulus_spec=tristimulus(illuminant_name, observer),
            measurement_spec=cxf3.MeasurementSpec(
                measurement_type=cxf3.MeasurementType(value=cxf3.EspectrumType.SPECTRUM_REFLECTANCE),
                geometry_choice=geometry_choice,
                wavelength_range=cxf3.WavelengthRange(start_wl=start, increment=inc),
            ),
        )

    ref = spec.reference

    def ref_geometry():
        return cxf3.GeometryChoice(choice=[cxf3.SingleAngleType(
            single_angle_configuration=cxf3.SingleAngleConfiguration(
                value=cxf3.EsingleAngleConfigurationType.UNIPLANAR),
            illumination_angle=ref.light_deg, measurement_angle=ref.view_deg)])

    ref_id = "CS-" + ref.name.replace(":", "-")
    specs = [colour_spec(ref_id, ref_geometry())]
    # The same reference spectrum under D50 / CIE 1931 2° (what print workflows and ICC assume),
    # and the 2° specification sRGB is defined on (the catalog's illuminant, 2° observer).
    extra = {}
    for ill, obs in (("D50", "2"), (data.illuminant, "2")):
        cs_id = f"{ref_id}-{ill}-{obs}deg"
        if (ill, obs) == (data.illuminant, data.observer):
            extra[(ill, obs)] = ref_id
        elif (ill, obs) not in extra:
            extra[(ill, obs)] = cs_id
            specs.append(colour_spec(cs_id, ref_geometry(), ill, obs))
    d50_id, srgb_id = extra[("D50", "2")], extra[(data.illuminant, "2")]
    n_ref = len(specs)
    for g in spec.multi_angle:
        specs.append(colour_spec("CS-" + g.name, cxf3.GeometryChoice(choice=[cxf3.MultiAngleType(
            brdfangle=[cxf3.Brdfangle(illumination_angle=g.light_deg, aspecular=g.aspecular_deg, notation=g.name)])])))

    def rnd(x, nd=5):
        return round(float(x), nd)

    objects = []
    for i, rec in enumerate(data.records):
        values = [
            cxf3.ColorCielab(l=rec["Lab"][0], a=rec["Lab"][1], b=rec["Lab"][2], color_specification=ref_id),
            cxf3.ColorCielch(l=rec["LCh"][0], c=rec["LCh"][1], h=rec["LCh"][2], color_specification=ref_id),
            cxf3.ReflectanceSpectrum(value=[rnd(v) for v in data.reflectance[i]], start_wl=start,
                                     color_specification=ref_id),
        ]
        if d50_id != ref_id:
            L, a, b = rec["Lab_D50_2"]
            LCh = Lab_to_LCh(rec["Lab_D50_2"])
            values += [cxf3.ColorCielab(l=L, a=a, b=b, color_specification=d50_id),
                       cxf3.ColorCielch(l=L, c=rnd(LCh[1], 4), h=rnd(LCh[2], 4), color_specification=d50_id)]
        values.append(cxf3.ColorSrgb(r=int(rec["srgb_hex"][1:3], 16), g=int(rec["srgb_hex"][3:5], 16),
                                     b=int(rec["srgb_hex"][5:7], 16), color_specification=srgb_id))
        for j, g in enumerate(spec.multi_angle):
            cs = specs[j + n_ref].id
            Lab = rec["multi_angle"][g.name]
            LCh = rec["multi_angle_LCh"][g.name]
            values += [
                cxf3.ColorCielab(l=Lab[0], a=Lab[1], b=Lab[2], color_specification=cs),
                cxf3.ColorCielch(l=LCh[0], c=LCh[1], h=LCh[2], color_specification=cs),
                cxf3.ReflectanceSpectrum(value=[rnd(v) for v in data.multi_reflectance[j, i]], start_wl=start,
                                         color_specification=cs),
            ]
        pw = rec["process_window"]
        tags = [
            ("thickness_nm", rec["thickness_nm"]), ("voltage_V", rec["voltage_V"]),
            ("process_window_grade", f"{pw['scheme'] or ''} {pw['grade']} ({pw['metric']} <= {pw['max']:g})".strip()),
            ("thickness_minus_nm", pw["thickness_minus_nm"]), ("thickness_plus_nm", pw["thickness_plus_nm"]),
            ("voltage_minus_V", pw["voltage_minus_V"]), ("voltage_plus_V", pw["voltage_plus_V"]),
        ]
        objects.append(cxf3.Object(
            object_type="Standard", name=ase_name(rec, metal_symbol(spec)), id=rec["id"],
            creation_date=cxf3.CreationDate(value=date),
            color_values=cxf3.ColorValues(choice=values),
            tag_collection=[cxf3.TagCollection(name="swatch", tag=[cxf3.Tag(name=k, value=str(v)) for k, v in tags])],
        ))
    doc = cxf3.CxF(
        file_information=cxf3.FileInformation(
            creator="swatch (anodic-swatch)", creation_date=cxf3.CreationDate(value=date),
            description=spec.name,
            comment=(f"{spec.film} on {spec.substrate}; half-vector thin-film model "
                     f"(Fujii et al. 2019); reflectance factor on the half-vector facet; "
                     f"CIELAB under {data.illuminant}, CIE {'1964 10°' if data.observer == '10' else '1931 2°'} "
                     f"observer (colour-science, ASTM E308 weighting on a {inc} nm grid); the reference "
                     f"geometry also under D50 and the CIE 1931 2° observer; sRGB from CIE 1931 2° "
                     f"colorimetry under {data.illuminant} (Bradford-adapted to D65)"),
        ),
        resources=cxf3.Resources(
            object_collection=cxf3.ObjectCollection(object_value=objects),
            color_specification_collection=cxf3.ColorSpecificationCollection(color_specification=specs),
        ),
    )
    # colour_cxf.write_cxf renders with an ``ns0`` prefix on one line; the same xsdata serializer
    # with the customary ``cc`` prefix and indentation gives a file people can read and diff.
    serializer = XmlSerializer(config=SerializerConfig(indent="  "))
    return serializer.render(doc, ns_map={"cc": "http://colorexchangeformat.com/CxF3-core"}).encode("utf-8")
