// colour.js — the embedded colour table and the colorimetry the page does with it.
// Everything physical comes from the build (swatch.catalog.explorer): tristimulus values of the
// half-vector thin-film reflectance over thickness x cos(theta_d), and colour-science's matrices.
// This file only interpolates, applies those matrices and the CIE formulas (L*a*b*, CIEDE2000).

function decodeBlock(block) { // uint16 codes x per-channel scale, or little-endian float32 (type "float32")
  const bin = atob(block.data);
  if (block.type === "float32") {
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return new Float32Array(bytes.buffer);
  }
  const n = bin.length >> 1;
  const out = new Float32Array(n);
  const c = block.shape[block.shape.length - 1];
  const scale = block.scale;
  for (let i = 0; i < n; i++) {
    out[i] = (bin.charCodeAt(2 * i) | (bin.charCodeAt(2 * i + 1) << 8)) * scale[i % c];
  }
  return out;
}

function mulRow(v, M) { // row vector (3) times 3x3 matrix (rows)
  return [v[0] * M[0][0] + v[1] * M[1][0] + v[2] * M[2][0],
          v[0] * M[0][1] + v[1] * M[1][1] + v[2] * M[2][1],
          v[0] * M[0][2] + v[1] * M[1][2] + v[2] * M[2][2]];
}

// The page's one growth law (swatch.physics.growth): thickness_nm = offset_nm + nm_per_V * voltage_V, or two slopes
// continuous at knee_V (nm_per_V up to the knee, nm_per_V_above_knee above). P: the catalog's process (or the
// colour table, which carries the same keys); no voltages without a rate (nm_per_V null).
function voltageOf(P, d) { // the voltage growing d (nm), V; null without a rate
  if (P.nm_per_V == null) return null;
  const x = d - P.offset_nm, knee = P.knee_V ?? null;
  return knee === null || x <= P.nm_per_V * knee ? x / P.nm_per_V : knee + (x - P.nm_per_V * knee) / P.nm_per_V_above_knee;
}
function thicknessOf(P, v) { // the thickness grown at v volts, nm; NaN without a rate
  if (P.nm_per_V == null) return NaN;
  const knee = P.knee_V ?? null;
  return knee === null ? P.offset_nm + v * P.nm_per_V
    : P.offset_nm + P.nm_per_V * Math.min(v, knee) + P.nm_per_V_above_knee * Math.max(v - knee, 0);
}

// sRGB encoding (IEC 61966-2-1) without pow, for the live view's shaders: above the linear toe a minimax fit
// in s1 = c^(1/2), s2 = c^(1/4), s3 = c^(1/8) (three square roots; fitted by linear programming on 12,000 points of
// [0.0031308, 1]), within 0.0031/255 of the exact curve (tests/js/colour.test.mjs): 8-bit output as the exact
// formula's but for a rounding flip on about 0.6 % of values. pow was a third of a point-light frame in
// SwiftShader (issue 21's frame budget).
const SRGB_ENCODE_FIT = [0.933831806, 0.492531019, -0.199519938, -0.201069267, -0.0257852883];  // s1, s2, s3, s1 s3, 1
function srgbEncodeFast(c) {
  c = Math.min(Math.max(c, 0), 1);
  const s1 = Math.sqrt(c), s2 = Math.sqrt(s1), s3 = Math.sqrt(s2), k = SRGB_ENCODE_FIT;
  return c <= 0.0031308 ? 12.92 * c : k[0] * s1 + k[1] * s2 + k[2] * s3 + k[3] * s1 * s3 + k[4];
}
const SRGB_ENCODE_GLSL = `
float enc(float c) {
  c = clamp(c, 0.0, 1.0);
  float s1 = sqrt(c), s2 = sqrt(s1), s3 = sqrt(s2);
  return c <= 0.0031308 ? 12.92 * c : ${SRGB_ENCODE_FIT.map((k, i) => "(" + k.toFixed(9) + ")" + ["* s1", "* s2", "* s3", "* s1 * s3", ""][i]).join(" + ")};
}
`;

// WCAG 2 relative luminance of an sRGB hex colour and the contrast ratio of two (1 to 21)
function relativeLuminance(hex) {
  const h = String(hex).replace(/^#/, "");
  const lin = [0, 2, 4].map((i) => { const c = parseInt(h.slice(i, i + 2), 16) / 255; return c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4; });
  return 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2];
}
function contrastRatio(hexA, hexB) {
  const a = relativeLuminance(hexA), b = relativeLuminance(hexB);
  return (Math.max(a, b) + 0.05) / (Math.min(a, b) + 0.05);
}
// the ink (black or white) with the higher contrast on a chip: at least 4.58, above WCAG AA's 4.5
function inkFor(hex) { return contrastRatio(hex, "#000000") >= contrastRatio(hex, "#ffffff") ? "#000000" : "#ffffff"; }

// CIEDE2000 (Sharma, Wu, Dalal 2005, doi:10.1002/col.20070), as colour.delta_E(method="CIE 2000"); tested on the
// paper's 34 pairs and on values colour-science writes (tests/js/colour.test.mjs, run by tests/catalog/test_page_js.py)
const DEG_ = Math.PI / 180;
function deltaE00(a, b) { // [L, a, b] twice -> a number
  const [L1, a1, b1] = a, [L2, a2, b2] = b;
  const C1 = Math.hypot(a1, b1), C2 = Math.hypot(a2, b2), Cm = (C1 + C2) / 2;
  const G = 0.5 * (1 - Math.sqrt(Cm ** 7 / (Cm ** 7 + 25 ** 7)));
  const ap1 = (1 + G) * a1, ap2 = (1 + G) * a2;
  const Cp1 = Math.hypot(ap1, b1), Cp2 = Math.hypot(ap2, b2);
  const hue = (x, y) => { if (x === 0 && y === 0) return 0; const h = Math.atan2(y, x) / DEG_; return h < 0 ? h + 360 : h; };
  const hp1 = hue(ap1, b1), hp2 = hue(ap2, b2);
  const dL = L2 - L1, dC = Cp2 - Cp1;
  let dh = 0;
  if (Cp1 * Cp2 !== 0) { dh = hp2 - hp1; if (dh > 180) dh -= 360; else if (dh < -180) dh += 360; }
  const dH = 2 * Math.sqrt(Cp1 * Cp2) * Math.sin(dh / 2 * DEG_);
  const Lm = (L1 + L2) / 2, Cpm = (Cp1 + Cp2) / 2;
  let hm = hp1 + hp2;
  if (Cp1 * Cp2 !== 0) {
    if (Math.abs(hp1 - hp2) <= 180) hm = (hp1 + hp2) / 2;
    else hm = (hp1 + hp2 < 360) ? (hp1 + hp2 + 360) / 2 : (hp1 + hp2 - 360) / 2;
  }
  const Tt = 1 - 0.17 * Math.cos((hm - 30) * DEG_) + 0.24 * Math.cos(2 * hm * DEG_) +
    0.32 * Math.cos((3 * hm + 6) * DEG_) - 0.2 * Math.cos((4 * hm - 63) * DEG_);
  const dTheta = 30 * Math.exp(-(((hm - 275) / 25) ** 2));
  const Rc = 2 * Math.sqrt(Cpm ** 7 / (Cpm ** 7 + 25 ** 7));
  const Sl = 1 + 0.015 * (Lm - 50) ** 2 / Math.sqrt(20 + (Lm - 50) ** 2);
  const Sc = 1 + 0.045 * Cpm, Sh = 1 + 0.015 * Cpm * Tt;
  const Rt = -Math.sin(2 * dTheta * DEG_) * Rc;
  return Math.sqrt((dL / Sl) ** 2 + (dC / Sc) ** 2 + (dH / Sh) ** 2 + Rt * (dC / Sc) * (dH / Sh));
}

// whether a match candidate ({delta_E_ab, delta_E_00}) lies within a tolerance, judged in its own metric
// ("dEab": CIE 1976, which a CSAJ grade bounds; "dE00": CIEDE2000), as swatch.fit.matching.judge_candidates
function withinTolerance(hit, metric, bound) {
  if (metric !== "dEab" && metric !== "dE00") throw new Error("withinTolerance: metric must be dEab or dE00");
  return (metric === "dEab" ? hit.delta_E_ab : hit.delta_E_00) <= bound;
}

function makeColour(T) {
  const grid = decodeBlock(T.grid);
  const col = decodeBlock(T.reference.values);
  const nd = T.thickness_nm.count, nc = T.cos_theta_d.count;
  const d0 = T.thickness_nm.start, dstep = T.thickness_nm.step;
  const R = T.reference.thickness_nm;
  const W = T.white_XYZ;
  const DEG = Math.PI / 180;

  function direction(polar, azimuth) {
    const t = polar * DEG, p = azimuth * DEG;
    return [Math.sin(t) * Math.cos(p), Math.sin(t) * Math.sin(p), Math.cos(t)];
  }
  // as swatch.physics.geometry.cos_theta_d: view azimuth defaults to the opposite side of the light
  function cosThetaD(light_deg, view_deg, light_az, view_az) {
    const la = light_az === undefined || light_az === null ? 0 : light_az;
    const va = view_az === undefined || view_az === null ? la + 180 : view_az;
    const l = direction(light_deg, la), v = direction(view_deg, va);
    const lv = l[0] * v[0] + l[1] * v[1] + l[2] * v[2];
    return Math.sqrt(Math.max(0, (1 + lv) / 2));
  }
  function clampD(d) { return Math.min(Math.max(d, d0), d0 + dstep * (nd - 1)); }
  // bilinear interpolation of the grid: 6 channels (XYZ catalog observer, XYZ 2 deg)
  function gridAt(d, cosd) {
    const x = (clampD(d) - d0) / dstep;
    const y = Math.min(Math.max(cosd, 0), 1) * (nc - 1);
    const i = Math.min(Math.floor(x), nd - 2), j = Math.min(Math.floor(y), nc - 2);
    const fx = x - i, fy = y - j;
    const out = new Array(6);
    const a = (i * nc + j) * 6, b = ((i + 1) * nc + j) * 6;
    for (let k = 0; k < 6; k++) {
      out[k] = (1 - fx) * ((1 - fy) * grid[a + k] + fy * grid[a + 6 + k]) +
               fx * ((1 - fy) * grid[b + k] + fy * grid[b + 6 + k]);
    }
    return out;
  }
  // one thickness row over cos(theta_d) as linear sRGB (for the shader)
  function rowLinearSrgb(d) {
    const x = (clampD(d) - d0) / dstep;
    const i = Math.min(Math.floor(x), nd - 2), fx = x - i;
    const out = new Float32Array(nc * 4);
    for (let j = 0; j < nc; j++) {
      const a = (i * nc + j) * 6, b = ((i + 1) * nc + j) * 6;
      const xyz = [0, 0, 0];
      for (let k = 0; k < 3; k++) xyz[k] = (1 - fx) * grid[a + 3 + k] + fx * grid[b + 3 + k];
      const rgb = mulRow(xyz, T.XYZ2_to_srgb_linear);
      out[4 * j] = rgb[0]; out[4 * j + 1] = rgb[1]; out[4 * j + 2] = rgb[2]; out[4 * j + 3] = 1;
    }
    return out;
  }
  function f(t) { return t > 216 / 24389 ? Math.cbrt(t) : (24389 / 27 * t + 16) / 116; }
  function XYZtoLab(X, white) { // XYZ on the Y = 100 scale, white with Y = 1 (colour.XYZ_to_Lab)
    const w = white || W;
    const fx = f(X[0] / 100 / w[0]), fy = f(X[1] / 100 / w[1]), fz = f(X[2] / 100 / w[2]);
    return [116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)];
  }
  function LabtoXYZ(Lab, white) { // colour.Lab_to_XYZ, on the Y = 100 scale
    const w = white || W;
    const fy = (Lab[0] + 16) / 116, fx = fy + Lab[1] / 500, fz = fy - Lab[2] / 200;
    const inv = (t) => t ** 3 > 216 / 24389 ? t ** 3 : (116 * t - 16) / (24389 / 27);
    return [inv(fx) * w[0] * 100, inv(fy) * w[1] * 100, inv(fz) * w[2] * 100];
  }
  function encode(c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * Math.pow(c, 1 / 2.4) - 0.055; }
  function decode(c) { return c <= 0.04045 ? c / 12.92 : Math.pow((c + 0.055) / 1.055, 2.4); }
  const TOL = 1e-3; // as swatch.colorimetry.colorimeter.Colorimeter.display
  function display(XYZ2, M) {
    const lin = mulRow(XYZ2, M || T.XYZ2_to_srgb_linear);
    const inGamut = lin.every((c) => c >= -TOL && c <= 1 + TOL);
    return {encoded: lin.map((c) => Math.min(Math.max(encode(Math.min(Math.max(c, 0), 1)), 0), 1)), inGamut};
  }
  function hexOf(enc) {
    return "#" + enc.map((c) => Math.round(Math.min(Math.max(c, 0), 1) * 255).toString(16).padStart(2, "0")).join("");
  }
  function hexLinear(hex) {
    const h = String(hex).trim().replace(/^#/, "");
    if (!/^[0-9a-f]{6}$/i.test(h)) throw new Error("bad hex colour " + JSON.stringify(hex) + "; give six hex digits like 1f4e9a");
    return [0, 2, 4].map((i) => decode(parseInt(h.slice(i, i + 2), 16) / 255));
  }
  function hexToLab(hex) {
    return XYZtoLab(mulRow(hexLinear(hex), T.srgb_linear_to_XYZ2), T.white_XYZ2); // as swatch.colorimetry.colorimeter.hex_to_Lab_2deg
  }
  // in the catalog's observer, as swatch.colorimetry.observers.hex_to_document_Lab (swatch match --hex)
  function hexToDocumentLab(hex) { return XYZtoLab(mulRow(hexLinear(hex), T.srgb_linear_to_XYZ), W); }
  const dE00 = deltaE00;
  function dEab(a, b) { return Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }
  function LCh(Lab) { const h = Math.atan2(Lab[2], Lab[1]) / DEG; return [Lab[0], Math.hypot(Lab[1], Lab[2]), h < 0 ? h + 360 : h]; }

  function describe(v6) {
    const Lab = XYZtoLab(v6.slice(0, 3));
    const s = display(v6.slice(3, 6));
    const p3 = display(v6.slice(3, 6), T.XYZ2_to_p3_linear);
    return {Lab, hex: hexOf(s.encoded), in_srgb_gamut: s.inGamut, display_p3: p3.encoded, in_display_p3_gamut: p3.inGamut};
  }
  function colorAt(q) {
    const d = Number(q.thickness_nm);
    if (!Number.isFinite(d)) throw new Error("colorAt: thickness_nm must be a number");
    const light = Number(q.light_deg === undefined ? T.reference.geometry.light_deg : q.light_deg);
    const view = Number(q.view_deg === undefined ? T.reference.geometry.view_deg : q.view_deg);
    if (!(light >= 0 && light <= 90 && view >= 0 && view <= 90)) throw new Error("colorAt: light_deg and view_deg must be in [0, 90]");
    const cosd = cosThetaD(light, view, q.light_azimuth_deg, q.view_azimuth_deg);
    const out = describe(gridAt(d, cosd));
    out.thickness_nm = clampD(d);
    out.theta_d_deg = Math.acos(Math.min(1, cosd)) / DEG;
    return out;
  }
  // the reference-geometry column at 0.1 nm (as swatch match samples it)
  const nr = R.count;
  function refAt(d) { // linear between column nodes
    const x = Math.min(Math.max((d - R.start) / R.step, 0), nr - 1);
    const i = Math.min(Math.floor(x), nr - 2), fx = x - i;
    const out = new Array(6);
    for (let k = 0; k < 6; k++) out[k] = (1 - fx) * col[i * 6 + k] + fx * col[(i + 1) * 6 + k];
    return out;
  }
  // L*a*b* of the column's nodes: catalog observer (o = 0) or 2° (o = 3, for hex targets)
  const refLabs = {};
  function refLab(o) {
    if (!refLabs[o]) {
      const w = o ? T.white_XYZ2 : W, out = new Array(nr);
      for (let i = 0; i < nr; i++) out[i] = XYZtoLab([col[i * 6 + o], col[i * 6 + o + 1], col[i * 6 + o + 2]], w);
      refLabs[o] = out;
    }
    return refLabs[o];
  }
  function refColour(d) { return describe(refAt(d)); }
  // a chip for a target: a hex as it is (2° sRGB); an L*a*b* through XYZ against the 2° white to display
  // sRGB (a display approximation when the catalog's observer is 10°)
  function hexColour(hex) {
    const Lab = hexToLab(hex), h = "#" + String(hex).trim().replace(/^#/, "").toLowerCase();
    return {Lab, hex: h, in_srgb_gamut: true, display_p3: display(LabtoXYZ(Lab, T.white_XYZ2), T.XYZ2_to_p3_linear).encoded};
  }
  function labColour(Lab) {
    const XYZ = LabtoXYZ(Lab, T.white_XYZ2), s = display(XYZ), p3 = display(XYZ, T.XYZ2_to_p3_linear);
    return {Lab, hex: hexOf(s.encoded), in_srgb_gamut: s.inGamut, display_p3: p3.encoded};
  }
  // as swatch.fit.matching.match_colour over the catalog's range: local minima of the sampled
  // CIEDE2000 curve (an end counts only when lower than every interior minimum), the best
  // refined within one step, kept at least min_separation apart, ranked by CIEDE2000.
  // A Lab target is in the catalog's observer; a hex target is sRGB (2°), brought into the catalog's
  // observer through its smoothest reflectance (as swatch match --hex, docs/processes.md).
  function match(target, n) {
    let Lab;
    if (target && target.Lab) Lab = Array.from(target.Lab, Number);
    else if (target && target.hex !== undefined) Lab = hexToDocumentLab(target.hex);
    else throw new Error("match: give {Lab: [L, a, b]} or {hex: '#rrggbb'}");
    if (Lab.length !== 3) throw new Error("match: Lab must have three numbers");
    const labAt = (d) => XYZtoLab(refAt(d).slice(0, 3), W);
    if (!Lab.every(Number.isFinite) || Lab[0] < 0 || Lab[0] > 100) throw new Error("match: Lab must be finite with L in [0, 100]");
    const top = n === undefined ? 5 : Math.floor(Number(n));
    if (!(top >= 1 && top <= 100)) throw new Error("match: n must be from 1 to 100");
    const fcurve = refLab(0).map((x) => dE00(x, Lab));
    const fine = (d) => dE00(labAt(d), Lab);
    const idx = [];
    for (let i = 0; i < nr; i++) {
      const left = i === 0 || fcurve[i] < fcurve[i - 1];
      const right = i === nr - 1 || fcurve[i] <= fcurve[i + 1];
      if (left && right) idx.push(i);
    }
    const interior = idx.filter((i) => i > 0 && i < nr - 1);
    let cand = idx;
    if (interior.length) {
      const best = Math.min(...interior.map((i) => fcurve[i]));
      cand = interior.concat(idx.filter((i) => (i === 0 || i === nr - 1) && fcurve[i] < best));
    }
    cand.sort((a, b) => fcurve[a] - fcurve[b]);
    cand = cand.slice(0, 8).slice(0, Math.max(top, 3) + 2);
    const lo = R.start, hi = R.start + R.step * (nr - 1);
    const minima = cand.map((i) => {
      const g = R.start + R.step * i;
      let a = Math.max(lo, g - R.step), b = Math.min(hi, g + R.step);
      const gr = (Math.sqrt(5) - 1) / 2;
      let c = b - gr * (b - a), e = a + gr * (b - a), fc = fine(c), fe = fine(e);
      for (let k = 0; k < 40 && b - a > 1e-4; k++) {
        if (fc < fe) { b = e; e = c; fe = fc; c = b - gr * (b - a); fc = fine(c); }
        else { a = c; c = e; fc = fe; e = a + gr * (b - a); fe = fine(e); }
      }
      let d = (a + b) / 2, fd = fine(d);
      if (fcurve[i] < fd) { d = g; fd = fcurve[i]; }
      return [d, fd];
    }).sort((x, y) => x[1] - y[1]);
    const kept = [];
    for (const [d, fd] of minima) if (kept.every(([k]) => Math.abs(d - k) > T.match.min_separation_nm)) kept.push([d, fd]);
    return kept.slice(0, top).map(([d, fd]) => ({thickness_nm: d, voltage_V: voltageOf(T, d), delta_E_00: fd,
      delta_E_ab: dEab(labAt(d), Lab), hex: refColour(d).hex, target_Lab: Lab}));
  }
  // process window at any thickness (as swatch.catalog.records.process_window, on the 0.1 nm column),
  // judged in the tolerance's own metric ("dEab" or "dE00")
  function windowAt(d, bound, search_nm, metric) {
    const dE = metric === "dEab" ? dEab : dE00;
    const Lab0 = XYZtoLab(refAt(d).slice(0, 3));
    const edge = (sign) => {
      let prev = 0, e0 = 0;
      for (let k = 1; k * R.step <= search_nm + 1e-9; k++) {
        const dd = d + sign * k * R.step;
        if (dd < R.start - 1e-9 || dd > hi + 1e-9) return {nm: prev, capped: true};
        const e = dE(XYZtoLab(refAt(dd).slice(0, 3)), Lab0);
        if (e > bound) return {nm: prev + (e > e0 ? (bound - e0) / (e - e0) : 0) * R.step, capped: false};
        prev = k * R.step; e0 = e;
      }
      return {nm: search_nm, capped: true};
    };
    const hi = R.start + R.step * (nr - 1);
    return {minus: edge(-1), plus: edge(1)};
  }
  return {colorAt, match, gridAt, rowLinearSrgb, refColour, hexColour, labColour, windowAt, dE00, dEab, LCh, XYZtoLab, LabtoXYZ, hexToLab, hexToDocumentLab,
          cosThetaD, range: [d0, d0 + dstep * (nd - 1)], cosNodes: nc};
}
