// page.js — the catalog page: filters over the cards the build wrote (the page works without
// JavaScript as a plain grid), the live view, compare, find by colour, and window.swatchCatalog.

const cat = JSON.parse(document.getElementById("catalog-data").textContent);
const T = JSON.parse(document.getElementById("explorer-table").textContent);
const envNode = document.getElementById("explorer-env");
const ENV = envNode ? JSON.parse(envNode.textContent) : null;
const C = makeColour(T);
const swatches = cat.swatches;
const $ = (id) => document.getElementById(id);
const fmt = (x, n) => (x === null || x === undefined || !Number.isFinite(Number(x))) ? "–" : Number(x).toFixed(n);
const HEX = /^#[0-9a-f]{6}$/i;
const ref = cat.catalog.reference_geometry;
const geoms = cat.catalog.multi_angle_geometries;
// the catalog's process profile's growth law (colour.js: voltageOf, thicknessOf; no voltages without a rate)
const growth = cat.catalog.process.nm_per_V;
const toV = (d) => voltageOf(cat.catalog.process, d);
const fromV = (v) => thicknessOf(cat.catalog.process, v);
// the tolerance, judged in its own metric (a CSAJ grade bounds ΔE*ab)
const tol = cat.catalog.tolerance, bound = tol.max;
function el(tag, cls, text) {
  const e = document.createElement(tag);
  if (cls) e.className = cls;
  if (text !== undefined) e.textContent = text;
  return e;
}
function paint(node, c) { // sRGB hex, then Display P3 where the browser has it
  node.style.backgroundColor = c.hex;
  if (CSS.supports("color", "color(display-p3 1 1 1)")) {
    node.style.backgroundColor = "color(display-p3 " + c.display_p3.map((v) => v.toFixed(4)).join(" ") + ")";
  }
  node.classList.toggle("out-of-gamut", !c.in_srgb_gamut);
  node.title = c.hex + (c.in_srgb_gamut ? "" : " (outside sRGB: clipped)");
}
function chip(c, cls, label) {
  const d = el("div", "chip " + (cls || ""));
  paint(d, c);
  if (!c.in_srgb_gamut) d.appendChild(el("span", "gamut", "outside sRGB"));
  if (label) { const t = el("span", "chip-label", label); t.style.color = inkFor(c.hex); d.appendChild(t); }
  return d;
}
function geoArgs(g) { // a catalog geometry as colorAt arguments (in plane; view side)
  return {light_deg: g.light_deg, view_deg: g.view_deg, light_azimuth_deg: 0,
          view_azimuth_deg: g.view_side === "light" ? 0 : 180};
}

// -- filters (over the static cards) ---------------------------------------------------------
const main = $("swatches");
const cards = new Map([...main.querySelectorAll("article.card")].map((c) => [c.dataset.id, c]));
const empty = el("p", "empty", "No swatch matches the filters.");
function num(id) { const v = $(id).value.trim(); return v === "" ? null : Number(v); }
function inHue(h, lo, hi) { return lo <= hi ? (h >= lo && h <= hi) : (h >= lo || h <= hi); }
function update() {
  const tmin = num("tmin"), tmax = num("tmax"), vmin = num("vmin"), vmax = num("vmax");
  const hmin = num("hmin"), hmax = num("hmax"), fam = $("family").value;
  const lmin = num("lmin"), lmax = num("lmax");  // lightness L* at the reference geometry
  const key = $("sort").value, dir = $("order").value === "desc" ? -1 : 1;
  const shown = swatches.filter((s) =>
    (tmin === null || s.thickness_nm >= tmin) && (tmax === null || s.thickness_nm <= tmax) &&
    (vmin === null || s.voltage_V >= vmin) && (vmax === null || s.voltage_V <= vmax) &&
    (fam === "" || s.colour_name === fam) &&
    ((hmin === null && hmax === null) || inHue(s.LCh[2], hmin === null ? 0 : hmin, hmax === null ? 360 : hmax)) &&
    (lmin === null || s.LCh[0] >= lmin) && (lmax === null || s.LCh[0] <= lmax));
  const val = (s) => key === "hue" ? s.LCh[2] : key === "lightness" ? s.LCh[0] : key === "voltage" ? s.voltage_V : s.thickness_nm;
  shown.sort((a, b) => dir * (val(a) - val(b)) || (a.index - b.index));
  main.replaceChildren(...shown.map((s) => cards.get(s.id)));
  if (!shown.length) main.appendChild(empty);
  $("count").textContent = "showing " + shown.length + " of " + swatches.length;
}
$("controls").addEventListener("input", update);
$("controls").addEventListener("reset", () => setTimeout(update, 0));
$("controls").addEventListener("submit", (e) => e.preventDefault());

// -- live view -------------------------------------------------------------------------------
// the point light's fill: a uniform white surround of this radiance (1 shows a white diffuser as display
// white), so the side turned from the light is the film's colour dimmed, not black
const DEFAULT_FILL = 0.1;
const state = {thickness_nm: C.range[0], light_deg: ref.light_deg,
  view_deg: ref.view_deg, light_azimuth_deg: 0, view_azimuth_deg: ref.view_side === "light" ? 0 : 180,
  shape: "plate", model: T.render.model === "paper" ? "paper" : "microfacet", lighting: "point", fill: DEFAULT_FILL,
  finish: null};
// the finishes the catalog offers (its spec's list; the first is the sheets' and opens the page), each one click away
const FINISH_PARAMS = (cat.catalog.render && cat.catalog.render.finish_params) || {};
const FINISHES = ((cat.catalog.render && cat.catalog.render.finishes) || []).filter((f) => typeof f === "string" && f in FINISH_PARAMS);
state.finish = FINISHES[0] || null;
const canvas = $("view");
let view = null;
try {
  view = makeView(canvas, C, {roughness: T.render.roughness, scene: T.scene, hairlines: T.render.hairlines || null,
    finishes: ENV && ENV.finish_samples ? FINISH_PARAMS : null}, ENV);
} catch (e) { view = null; console.warn(String(e)); }
// the finish bar: a button per offered finish (where the live view can show more than one)
const finishHere = (f) => view && ENV && ENV.finish_samples && f in ENV.finish_samples;
if (FINISHES.filter(finishHere).length > 1) {
  const bar = $("finish-bar");
  bar.appendChild(el("span", "finish-label", "finish:"));
  for (const f of FINISHES.filter(finishHere)) {
    const b = el("button", "", f);
    b.type = "button"; b.dataset.finish = f; b.title = FINISH_PARAMS[f].description || f;
    b.addEventListener("click", () => show({finish: f}));
    bar.appendChild(b);
  }
  const note = el("p", "finish-note"); note.id = "finish-note";
  bar.appendChild(note);
  bar.hidden = false;
}
if (!view) {
  $("view-note").textContent = "This browser has no WebGL2: the live view is off (the colours below still follow the sliders).";
  $("lighting").disabled = true;
}
for (const o of [...$("lighting").options]) if (!(view ? view.lightings : ["point"]).includes(o.value)) o.remove();
// the catalog's own part (its spec's mesh) as a shape of the live view
if (view && view.SHAPES.includes("part")) {
  const o = el("option", "", "your part (" + T.scene.mesh.file + ")");
  o.value = "part";
  $("shape").appendChild(o);
}
// the live view opens under the studio light box (as the sheets' renders), where the page has it
if (view && view.lightings.includes("studio") && state.model === "microfacet") state.lighting = "studio";
const clampT = (d) => Math.min(Math.max(d, C.range[0]), C.range[1]);
// -- heroes: the catalog's path-traced pictures (records' "hero", swatch.catalog.hero), shown over the canvas
// while the view is at a hero's state (its thickness, shape, camera and lighting); the live render once changed
const HERO_SHAPES = {sphere: "sphere", cylinder: "bent sheet", flat: "plate", mesh: "part"};
const HERO_PNG = /^[A-Za-z0-9_-]+(\/[A-Za-z0-9_-]+)*\.png$/;  // a plain relative PNG path (swatch.catalog.html.HERO_PATH)
const heroOk = (h) => h && typeof h === "object" && typeof h.png === "string" && HERO_PNG.test(h.png) &&
  HERO_SHAPES[h.shape || "sphere"] !== undefined;
const heroes = swatches.filter((s) => heroOk(s.hero));
// a swatch's hero in a finish: its entry in hero_finishes (the cover swatch has one per offered finish), else its
// hero where that is in the finish (or the catalog has no finishes)
function heroIn(s, finish) {
  const f = s.hero_finishes && typeof s.hero_finishes === "object" && Object.hasOwn(s.hero_finishes, finish || "") ? s.hero_finishes[finish] : null;
  if (heroOk(f)) return f;
  return (!finish || !s.hero.finish || s.hero.finish === finish) ? s.hero : null;
}
const lightingsHere = () => (view ? view.lightings : ["point"]);
function heroState(s) {
  const shape = HERO_SHAPES[s.hero.shape || "sphere"], cam = shapeCamera(shape);
  const st = {thickness_nm: s.thickness_nm, shape, model: "microfacet", view_deg: cam.view_deg, view_azimuth_deg: cam.view_azimuth_deg};
  if (Number.isFinite(s.hero.view_deg)) st.view_deg = s.hero.view_deg;
  if (Number.isFinite(s.hero.view_azimuth_deg)) st.view_azimuth_deg = s.hero.view_azimuth_deg;
  const lit = s.hero.lighting || "studio";
  if (lightingsHere().includes(lit)) st.lighting = lit;
  return st;
}
const near = (a, b) => Math.abs(a - b) < 1e-6;
function heroAt(st) {
  return heroes.find((s) => {
    const h = heroState(s);
    return heroIn(s, st.finish) !== null && near(h.thickness_nm, st.thickness_nm) && h.shape === st.shape && st.model === "microfacet" &&
      (h.lighting === undefined || h.lighting === st.lighting) && near(h.view_deg, st.view_deg) &&
      near((((h.view_azimuth_deg - st.view_azimuth_deg) % 360) + 540) % 360 - 180, 0);
  }) || null;
}
// the largest of a hero's pictures (its cover, its hero) with at least one rendered pixel for each device pixel of
// the frame's height (no picture is shown larger than it was made: else the live view shows instead), or null
function sharpPicture(h) {
  const need = canvas.getBoundingClientRect().height * (window.devicePixelRatio || 1);
  const px = (p) => Number.isFinite(p.size_px) ? p.size_px : 0;
  const options = [h.cover, h].filter((p) => p && typeof p.png === "string" && HERO_PNG.test(p.png));
  return options.find((p) => px(p) >= need - 0.5) || null;
}
// the image over the canvas, made only where the catalog has heroes (the page itself has no <img> otherwise)
const heroBadge = $("hero-badge"), heroImg = heroes.length ? el("img") : null;
if (heroImg) { heroImg.id = "hero-view"; heroImg.alt = ""; heroImg.hidden = true; heroBadge.before(heroImg); }
// the picture is square and the frame 4:3: its sides continue the picture's own left and right edges (the studio's
// backdrop, top to bottom: the entry's "edges", swatch.catalog.hero.edge_colours) instead of showing bars
function edgeBackground(edges) {
  const ok = (a) => Array.isArray(a) && a.length >= 2 && a.length <= 64 && a.every((c) => typeof c === "string" && HEX.test(c));
  if (!edges || !ok(edges.left) || !ok(edges.right)) return "";
  const g = (a) => "linear-gradient(to bottom, " + a.join(", ") + ")";
  return g(edges.left) + " left top / 50% 100% no-repeat, " + g(edges.right) + " right top / 50% 100% no-repeat";
}
function updateHero() {
  const s = heroImg ? heroAt(state) : null, h = s ? heroIn(s, state.finish) : null, pic = h ? sharpPicture(h) : null;
  heroBadge.hidden = !pic;
  if (heroImg) heroImg.hidden = !pic;
  if (!pic) return;
  if (heroImg.getAttribute("src") !== pic.png) {
    heroImg.setAttribute("src", pic.png);
    heroImg.style.background = edgeBackground(h.edges) || "#2b2b2e";
  }
  heroImg.alt = s.id + " at " + fmt(s.thickness_nm, 1) + " nm, " + (h.finish ? h.finish + ", " : "") + "path-traced" +
    (Number.isFinite(h.spp) ? " (" + h.spp + " samples a pixel)" : "") + ": a " + (h.shape === "mesh" ? "part" : h.shape || "sphere") +
    " under the " + (h.lighting || "studio") + " light";
  heroBadge.textContent = "path-traced · turn or slide for the live view";
}
// the first view sells the metal: a hero where the catalog has them, else the live sphere under the studio; at
// the catalog's most vivid colour (the largest chroma at the reference geometry among the swatches inside sRGB;
// the build makes that swatch's cover by the same rule, swatch.catalog.hero.cover_index)
function vivid(list) {
  let best = null;
  for (const s of list) if (s.in_srgb_gamut && Array.isArray(s.LCh) && (!best || s.LCh[1] > best.LCh[1])) best = s;
  return best || list[0] || null;
}
{
  const first = heroes.find((s) => s.hero.cover) || vivid(heroes.length ? heroes : swatches);
  if (first && heroes.includes(first)) Object.assign(state, heroState(first));
  else Object.assign(state, {thickness_nm: first ? first.thickness_nm : C.range[0], shape: "sphere"}, shapeCamera("sphere"));
  state.thickness_nm = clampT(state.thickness_nm);
}
function readout() {
  const c = C.colorAt(state);
  paint($("state-chip"), c);
  $("state-gamut").hidden = c.in_srgb_gamut;
  const lch = C.LCh(c.Lab);
  // under an environment there is no one light: the readout is the facet colour of the point-light
  // geometry the (greyed) light slider still sets, and says so
  $("state-label").textContent = state.lighting === "point" ? "this light and view"
    : "at light " + fmt(state.light_deg, 0) + "°, view " + fmt(state.view_deg, 0) + "° (" +
      lightingWords(state.lighting) + " has no single lamp)";
  // plain words first (the colour's name, and the angle it holds at), the numbers after
  $("state-text").textContent = nameHere(nameOf(lch), c.theta_d_deg) + " · L*a*b* " + c.Lab.map((v) => fmt(v, 2)).join("  ") +
    " · " + c.hex;
  const r = C.refColour(state.thickness_nm);
  paint($("ref-chip"), r);
  $("ref-text").textContent = nameSeen(nameOf(C.LCh(r.Lab))) + " · L*a*b* " + r.Lab.map((v) => fmt(v, 2)).join("  ") + " · " + r.hex;
  $("t-out").textContent = fmt(state.thickness_nm, 1) + " nm";
  $("v-out").textContent = fmt(toV(state.thickness_nm), 1) + " V";
  $("l-out").textContent = fmt(state.light_deg, 1) + "°";
  $("la-out").textContent = fmt(state.light_azimuth_deg, 0) + "°";
  $("f-out").textContent = fmt(state.fill, 2);
  $("w-out").textContent = fmt(state.view_deg, 1) + "°, turned " + fmt(state.view_azimuth_deg, 0) + "° (azimuth)";
  viewLinkA.href = viewLink(state);
}
// "link to this view": the page's address with the live view's state (link.js), to share or bookmark
const viewLinkA = el("a", "", "link to this view"), linkNote = el("span", "link-note");
viewLinkA.id = "view-link"; linkNote.id = "link-note";
{ const p = el("p", "hint"); p.append(viewLinkA, " ", linkNote); $("pin").parentElement.after(p); }
let drag = null;
function draw() {
  if (view) state.exposure = view.draw(drag ? Object.assign({coarse: true}, state) : state); // coarse while dragged
  updateHero();
  readout();
}
function syncInputs() {
  $("thickness").value = state.thickness_nm; $("voltage").value = growth === null ? "" : fmt(toV(state.thickness_nm), 2);
  if (growth !== null) $("voltage-range").value = toV(state.thickness_nm);
  $("light").value = state.light_deg; $("view-deg").value = state.view_deg;
  $("shape").value = state.shape; $("model").value = state.model; $("lighting").value = state.lighting;
  $("light").disabled = state.lighting !== "point"; // an environment lights from everywhere
  $("light-azimuth").value = ((state.light_azimuth_deg + 540) % 360) - 180;
  $("light-azimuth").disabled = state.lighting !== "point";
  $("fill").value = state.fill; $("fill").disabled = state.lighting !== "point" || state.model === "paper";
  for (const b of $("finish-bar").querySelectorAll("button")) b.setAttribute("aria-pressed", String(b.dataset.finish === state.finish));
  const fn = $("finish-note");
  if (fn && FINISH_PARAMS[state.finish]) fn.textContent = FINISH_PARAMS[state.finish].description || "";
}
// the checks of show(), in its order: each key of q as given (numbers clamped to their range), or an Error
// before it changes anything (one key at a time: the page's address applies what is good, link.js)
const SHOW_KEYS = ["thickness_nm", "voltage_V", "light_deg", "view_deg", "light_azimuth_deg", "view_azimuth_deg", "fill",
  "shape", "model", "lighting", "finish"];
function setState(q) {
  const n = (v, lo, hi) => { const x = Number(v); if (!Number.isFinite(x)) throw new Error("show: numbers expected"); return Math.min(Math.max(x, lo), hi); };
  if (q.thickness_nm !== undefined) state.thickness_nm = clampT(n(q.thickness_nm, -1e9, 1e9));
  if (q.voltage_V !== undefined) {
    if (growth === null) throw new Error("show: this catalog's process has no growth rate; give thickness_nm");
    state.thickness_nm = clampT(fromV(n(q.voltage_V, -1e9, 1e9)));
  }
  if (q.light_deg !== undefined) state.light_deg = n(q.light_deg, 0, 89);
  if (q.view_deg !== undefined) state.view_deg = n(q.view_deg, 0, 89);
  if (q.light_azimuth_deg !== undefined) state.light_azimuth_deg = n(q.light_azimuth_deg, -720, 720);
  if (q.view_azimuth_deg !== undefined) state.view_azimuth_deg = n(q.view_azimuth_deg, -720, 720);
  if (q.fill !== undefined) state.fill = n(q.fill, 0, 1);
  if (q.shape !== undefined && view && view.SHAPES.includes(q.shape)) state.shape = q.shape;
  if (q.model === "paper" || q.model === "microfacet") {
    state.model = q.model;
    if (q.model === "paper") state.lighting = "point"; // environments integrate the microfacet BRDF
  }
  if (q.finish !== undefined) {
    if (!FINISHES.includes(q.finish) || !finishHere(q.finish)) throw new Error("show: finish must be one of " + FINISHES.filter(finishHere).join(", "));
    state.finish = q.finish;
  }
  if (q.lighting !== undefined) {
    const allowed = view ? view.lightings : ["point"];
    if (!allowed.includes(q.lighting)) throw new Error("show: lighting must be one of " + allowed.join(", "));
    state.lighting = q.lighting;
    if (q.lighting !== "point") state.model = "microfacet";
  }
}
function show(q) {
  setState(q || {});
  syncInputs();
  draw();
  return Object.assign({}, state);
}
// a shape's own camera, as swatch render --shape (swatch.render.scene.DEFAULT_VIEW_DEG), seen from the front
function shapeCamera(shape) {
  const py = T.scene[{"plate": "flat", "bent sheet": "cylinder", "sphere": "sphere", "part": "mesh"}[shape]];
  return {view_deg: py ? py.default_view_deg : state.view_deg, view_azimuth_deg: 180};
}
$("thickness").min = C.range[0]; $("thickness").max = C.range[1];
// finishers set a voltage: a second slider over the same range through the growth law
if (growth === null) $("voltage-range-label").hidden = true;
else { $("voltage-range").min = Math.min(toV(C.range[0]), toV(C.range[1])); $("voltage-range").max = Math.max(toV(C.range[0]), toV(C.range[1])); }
$("live-form").addEventListener("input", (e) => {
  const id = e.target.id;
  if (id === "thickness") show({thickness_nm: e.target.value});
  else if (id === "voltage-range") show({voltage_V: e.target.value});
  else if (id === "voltage") { if (e.target.value !== "" && growth !== null) { state.thickness_nm = clampT(fromV(Number(e.target.value))); $("thickness").value = state.thickness_nm; draw(); } }
  else if (id === "light") show({light_deg: e.target.value});
  else if (id === "light-azimuth") show({light_azimuth_deg: e.target.value});
  else if (id === "view-deg") show({view_deg: e.target.value});
  else if (id === "fill") show({fill: e.target.value});
  else if (id === "shape") show(Object.assign({shape: e.target.value}, shapeCamera(e.target.value)));
  else if (id === "model") show({model: e.target.value});
  else if (id === "lighting") show({lighting: e.target.value});
});
$("live-form").addEventListener("submit", (e) => e.preventDefault());
canvas.addEventListener("pointerdown", (e) => { drag = [e.clientX, e.clientY, state.view_azimuth_deg, state.view_deg]; canvas.setPointerCapture(e.pointerId); });
canvas.addEventListener("pointermove", (e) => {
  if (!drag) return;
  show({view_azimuth_deg: drag[2] - (e.clientX - drag[0]) * 0.5, view_deg: drag[3] + (e.clientY - drag[1]) * 0.3});
});
canvas.addEventListener("pointerup", () => { drag = null; draw(); }); // refined when let go
// the keyboard turns it too (the canvas takes focus): arrows left/right the azimuth, up/down the view angle
canvas.addEventListener("keydown", (e) => {
  const step = e.shiftKey ? 15 : 5;
  const turn = {ArrowLeft: [step, 0], ArrowRight: [-step, 0], ArrowUp: [0, -step / 2], ArrowDown: [0, step / 2]}[e.key];
  if (!turn) return;
  e.preventDefault();
  show({view_azimuth_deg: state.view_azimuth_deg + turn[0], view_deg: state.view_deg + turn[1]});
});

// -- names (swatch.colorimetry.names.NAME_RULES, embedded) -----------------------------------------
function nameOf(lch) {
  const [L, Ch, h0] = lch, h = ((h0 % 360) + 360) % 360;
  for (const [name, ha, hb, c0, c1, l0, l1] of T.name_rules) {
    const inHue = ha <= hb ? (h >= ha && h < hb) : (h >= ha || h < hb);
    if (inHue && (c0 === null || Ch >= c0) && (c1 === null || Ch < c1) && (l0 === null || L >= l0) && (l1 === null || L < l1)) return name;
  }
  return "";
}
// -- plain words first, the code after (swatch.catalog.words: the same rules) -----------------------
// where a geometry looks from, by its view and aspecular angles (words.geometry_words)
function geometryWords(g) {
  if (g.view_deg < 2.5) return "face on";
  const a = Number.isFinite(g.aspecular_deg) ? g.aspecular_deg : g.light_deg + (g.view_side === "light" ? g.view_deg : -g.view_deg);
  return a < 0 ? "from the side" : a <= 20 ? "near the gloss" : a <= 60 ? "off the gloss" : a <= 90 ? "far from the gloss"
    : "from beside the light";
}
// a tolerance: its grade where it has one, then its bound in its own metric (words.tolerance_words)
function tolWords(t) {
  const bound = ({dEab: "ΔE*ab", dE00: "ΔE00"}[t.metric] || t.metric) + " ≤ " + t.max;
  return t.scheme ? ({csaj: "CSAJ", nbs: "NBS"}[t.scheme] || t.scheme) + " grade " + t.grade + ", " + bound : bound;
}
function lightingWords(n) { return {studio: "the photo studio", uniform: "even white light", point: "one lamp"}[n] || n; }
// a colour name says the angle it holds at: the reference geometry (the cards' names) ...
function nameSeen(name) { return (name ? name + " " : "") + "seen " + geometryWords(ref) + " (" + ref.name + ")"; }
// ... or the live view's facet angle
function nameHere(name, thetaD) { return (name ? name + " " : "") + "at this angle (θd " + fmt(thetaD, 1) + "°)"; }

// -- compare ---------------------------------------------------------------------------------
const pinned = [];
const MAX_PINS = 4;
function pin(item) {
  if (pinned.length >= MAX_PINS) pinned.shift();
  pinned.push(item);
  renderCompare();
}
function windowOf(item) {
  const r = item.record;
  if (r) return {minus: r.process_window.thickness_minus_nm, plus: r.process_window.thickness_plus_nm};
  const w = C.windowAt(item.thickness_nm, bound, tol.search_nm, tol.metric);
  return {minus: w.minus.nm, plus: w.plus.nm};
}
function renderCompare() {
  const list = $("compare-list");
  list.replaceChildren();
  $("compare").hidden = pinned.length === 0;
  pinned.forEach((item, k) => {
    const box = el("div", "pin");
    const d = item.thickness_nm;
    const r = C.refColour(d);
    box.appendChild(el("div", "pin-title", item.label));
    box.appendChild(chip(r, "big", geometryWords(ref) + " (" + ref.name + ")"));
    box.appendChild(el("div", "pin-sub", nameSeen(nameOf(C.LCh(r.Lab))) + " · " + fmt(d, 1) + " nm · " + fmt(toV(d), 1) + " V · " + r.hex));
    const strip = el("div", "strip");
    for (const g of geoms) strip.appendChild(chip(C.colorAt(Object.assign({thickness_nm: d}, geoArgs(g))), "", geometryWords(g) + " (" + g.name + ")"));
    box.appendChild(strip);
    const w = windowOf(item);
    const ends = el("div", "ends");
    ends.appendChild(chip(C.refColour(d - w.minus), "", "thin end " + fmt(d - w.minus, 1) + " nm"));
    ends.appendChild(chip(C.refColour(d + w.plus), "", "thick end " + fmt(d + w.plus, 1) + " nm"));
    box.appendChild(el("div", "pin-sub", "forgives a drift of −" + fmt(w.minus, 1) + " / +" + fmt(w.plus, 1) + " nm (process window, " +
      tolWords(tol) + ")"));
    box.appendChild(ends);
    const rm = el("button", "unpin", "remove");
    rm.type = "button";
    rm.addEventListener("click", () => { pinned.splice(k, 1); renderCompare(); });
    box.appendChild(rm);
    list.appendChild(box);
  });
  const tb = $("compare-delta");
  tb.replaceChildren();
  if (pinned.length > 1) {
    const head = el("tr"); head.appendChild(el("th", "", "difference, seen " + geometryWords(ref) + " (ΔE00 / ΔE*ab at " + ref.name + ")"));
    pinned.forEach((p) => head.appendChild(el("th", "", p.label)));
    tb.appendChild(head);
    pinned.forEach((a) => {
      const tr = el("tr"); tr.appendChild(el("th", "", a.label));
      const La = C.refColour(a.thickness_nm).Lab;
      pinned.forEach((b) => {
        const Lb = C.refColour(b.thickness_nm).Lab;
        tr.appendChild(el("td", "num", a === b ? "–" : fmt(C.dE00(La, Lb), 2) + " / " + fmt(C.dEab(La, Lb), 2)));
      });
      tb.appendChild(tr);
    });
  }
}
$("pin").addEventListener("click", () => pin({thickness_nm: state.thickness_nm, label: fmt(state.thickness_nm, 1) + " nm (slider)"}));
for (const s of swatches) {
  const card = cards.get(s.id);
  if (!card) continue;
  const tools = el("div", "tools");
  const bp = el("button", "", "compare"); bp.type = "button";
  bp.addEventListener("click", () => pin({thickness_nm: s.thickness_nm, label: s.id + " · " + fmt(s.thickness_nm, 1) + " nm", record: s}));
  const bs = el("button", "", "live view"); bs.type = "button";
  // a card with a hero opens the live view on its hero; the others at their thickness, as the view is
  bs.addEventListener("click", () => { show(heroes.includes(s) ? heroState(s) : {thickness_nm: s.thickness_nm}); $("explorer").scrollIntoView(); });
  tools.append(bp, bs);
  card.querySelector(".body").appendChild(tools);
}

// -- find by colour --------------------------------------------------------------------------
// the target beside the results: its chip (a hex as typed; an L*a*b* shown in sRGB against the 2°
// white, a display approximation), the nearest swatches with their CIEDE2000 and CIE 1976 ΔE*ab, whether
// each lies within the catalog's tolerance (in its own metric) and its process window
function findTarget(text, c) {
  const box = $("find-target");
  box.replaceChildren();
  if (c) box.appendChild(chip(c, "small"));
  if (text) box.appendChild(el("span", "", text));
}
function find(target) {
  const res = $("find-results");
  res.replaceChildren();
  let hits;
  try { hits = C.match(target, 5); } catch (e) {
    findTarget("");  // the previous target does not stay on screen beside an error
    findVerdict([]);
    res.appendChild(el("li", "error", String(e.message)));
    return;
  }
  const tLab = hits.length ? hits[0].target_Lab : [];
  // the target's L*a*b* is in the catalog's observer: a hex (sRGB, 2°) brought into it through its smoothest
  // reflectance, as swatch match --hex (match's target_Lab)
  const how = target.Lab ? "" : "; the sRGB hex's smoothest reflectance";
  const tChip = target.Lab ? C.labColour(tLab) : C.hexColour(target.hex);
  findTarget("your colour " + tChip.hex + " · L*a*b* " + tLab.map((v) => fmt(v, 2)).join("  ") + " (" + T.illuminant + ", " +
    T.observer + "°" + how + ")", tChip);
  findVerdict(hits);
  for (const h of hits) {
    const li = el("li");
    const r = C.refColour(h.thickness_nm);
    li.appendChild(chip(r, "small"));
    const ok = withinTolerance(h, tol.metric, bound);
    const w = C.windowAt(h.thickness_nm, bound, tol.search_nm, tol.metric);
    li.appendChild(el("span", "num", nameSeen(nameOf(C.LCh(r.Lab))) + " · " + fmt(h.thickness_nm, 2) + "\u00a0nm · " + fmt(h.voltage_V, 1) +
      "\u00a0V · colour difference ΔE00 " + fmt(h.delta_E_00, 2) + " · ΔE*ab " + fmt(h.delta_E_ab, 2)));
    li.appendChild(el("span", ok ? "tol ok" : "tol out", (ok ? "close enough" : "too far") + " (colour tolerance " + tolWords(tol) +
      ") · forgives a drift of −" + fmt(w.minus.nm, 1) + " / +" + fmt(w.plus.nm, 1) + " nm (process window)"));
    const b = el("button", "", "live view"); b.type = "button";
    b.addEventListener("click", () => show({thickness_nm: h.thickness_nm}));
    const p = el("button", "", "compare"); p.type = "button";
    p.addEventListener("click", () => pin({thickness_nm: h.thickness_nm, label: fmt(h.thickness_nm, 1) + " nm (match)"}));
    li.append(b, p);
    res.appendChild(li);
  }
}
// the answer in a sentence above the list: can the metal make this colour (a thickness within the catalog's
// tolerance, in its own metric), and which colour it makes is closest (by ΔE2000) and how far
function findVerdict(hits) {
  const box = $("find-verdict");
  box.replaceChildren();
  box.hidden = !hits.length;
  if (!hits.length) return;
  const good = hits.find((h) => withinTolerance(h, tol.metric, bound)), best = good || hits[0];
  const r = C.refColour(best.thickness_nm);
  const metal = {Ti: "titanium", Nb: "niobium", Ta: "tantalum"}[String(cat.catalog.substrate).split("-")[0]] || "metal";
  const what = nameSeen(nameOf(C.LCh(r.Lab))) + ": " + fmt(best.thickness_nm, 1) + "\u00a0nm of oxide" +
    (growth === null ? "" : " (" + fmt(best.voltage_V, 1) + "\u00a0V)") + ", " + r.hex + ", a colour difference of " +
    fmt(best.delta_E_00, 1) + " (ΔE00)";
  const tolerance = "the catalog's colour tolerance (" + tolWords(tol) + ")";
  box.classList.toggle("unreachable", !good);
  const text = el("span");
  if (good) {
    text.append(el("strong", "", "Anodised " + metal + " can make this colour."), " The nearest within " + tolerance + " is " +
      what + ".");
  } else {
    text.append(el("strong", "", "Anodised " + metal + " cannot make this colour."), " The closest colour it makes is " + what +
      "; no oxide thickness from " + fmt(C.range[0], 0) + " to " + fmt(C.range[1], 0) + "\u00a0nm comes within " + tolerance + ".");
  }
  box.append(chip(r, "small"), text);
}
$("find-form").addEventListener("submit", (e) => {
  e.preventDefault();
  const lab = $("find-lab").value.trim();
  if (lab) find({Lab: lab.split(/[\s,;]+/).map(Number)});
  else find({hex: $("find-hex").value});
});
// the picker follows a typed hex (and a picked colour fills in the hex)
$("find-hex").addEventListener("input", (e) => {
  const h = e.target.value.trim().replace(/^#?/, "#");
  if (HEX.test(h)) $("find-picker").value = h.toLowerCase();
});
$("find-picker").addEventListener("input", (e) => { $("find-hex").value = e.target.value; $("find-lab").value = ""; find({hex: e.target.value}); });

// -- printing: open the explanations and the cards' multi-angle tables, close them again after --
let openedForPrint = [];
window.addEventListener("beforeprint", () => {
  openedForPrint = [...document.querySelectorAll("details:not([open])")];
  for (const d of openedForPrint) d.open = true;
});
window.addEventListener("afterprint", () => { for (const d of openedForPrint) d.open = false; openedForPrint = []; });

// -- start -----------------------------------------------------------------------------------
for (const id of ["explorer", "find"]) $(id).hidden = false;
document.documentElement.classList.add("js");
update();
// the drawing buffer is the canvas's displayed size in device pixels (sharp on a HiDPI screen, not resampled
// by the browser; 640 x 480 beside the panel, about 310 x 233 on a phone at one device pixel a CSS pixel), at
// most MAX_VIEW_PX pixels (the gather pass under an environment costs per pixel): a 390 px phone's full width at
// 3 device pixels a CSS pixel, 1026 x 770, is drawn at one buffer pixel a device pixel, as no picture on the page
// is shown larger than it was made; the bench's frame times are at 640 x 480 (benchmarks/bench_explorer.py)
const MAX_VIEW_PX = 1100 * 830;
function fitCanvas() {
  const r = canvas.getBoundingClientRect(), dpr = window.devicePixelRatio || 1;
  let w = r.width * dpr, h = r.height * dpr;
  if (!(w >= 1 && h >= 1)) return false;  // not laid out (hidden, printed): keep the buffer
  const s = Math.min(1, Math.sqrt(MAX_VIEW_PX / (w * h)));
  w = Math.max(1, Math.round(w * s)); h = Math.max(1, Math.round(h * s));
  if (w === canvas.width && h === canvas.height) return false;
  canvas.width = w; canvas.height = h;
  return true;
}
// no picture is shown larger than it was made: each card's hero and each render or angular map cut from a sheet
// drawn at most one device pixel for each of its pixels (smaller on a screen of more device pixels a CSS pixel)
function noUpscale() {
  const dpr = window.devicePixelRatio || 1;
  for (const img of document.querySelectorAll("img.hero")) {
    const css = Number(img.getAttribute("width")), px = img.naturalWidth || Number(img.dataset.px) || 0;
    if (css > 0 && px > 0) img.style.width = img.style.height = Math.min(css, Math.floor(px / dpr)) + "px";
  }
  for (const d of document.querySelectorAll("[data-src-px]")) {
    const css = parseFloat(d.style.width), px = Number(d.dataset.srcPx);
    d.style.zoom = css > 0 && px > 0 ? String(Math.min(1, px / (css * dpr))) : "";
  }
}
noUpscale();
for (const img of document.querySelectorAll("img.hero")) img.addEventListener("load", noUpscale);
window.addEventListener("resize", noUpscale);
if (view) {
  fitCanvas();  // before the first frame: the observer's first report then finds the size unchanged
  if (typeof ResizeObserver === "function") new ResizeObserver(() => { if (fitCanvas()) draw(); }).observe(canvas);
}
// the page's address: #thickness=140&shape=sphere&lighting=point opens it in that view (link.js; what is not a
// view state is left out, and said so below the link); a fragment that names no view state (#find) changes nothing
function applyLink(hash) {
  const {query, ignored} = parseViewLink(hash);
  if (!Object.keys(query).length && !ignored.length) return false;
  if (query.shape !== undefined && query.view_deg === undefined && query.view_azimuth_deg === undefined) {
    Object.assign(query, shapeCamera(query.shape));  // as the shape menu: the shape's own camera
  }
  for (const k of SHOW_KEYS) {
    if (query[k] === undefined) continue;
    try { setState({[k]: query[k]}); } catch (e) {  // not on this page (a lighting it lacks, a voltage without a growth law)
      ignored.push((Object.keys(LINK_NUMBERS).find((m) => LINK_NUMBERS[m] === k) || k) + "=" + query[k]);
    }
  }
  linkNote.textContent = ignored.length ? "(left out of the page's address: " + ignored.join(", ") + ")" : "";
  syncInputs();
  draw();
  return true;
}
if (!applyLink(location.hash)) show({});
window.addEventListener("hashchange", () => applyLink(location.hash));
window.swatchCatalog = Object.freeze({
  colorAt: (q) => { const c = C.colorAt(q); return {Lab: c.Lab, hex: c.hex, in_srgb_gamut: c.in_srgb_gamut, theta_d_deg: c.theta_d_deg}; },
  // CIEDE2000 of two L*a*b* (arrays of three numbers)
  deltaE00: (lab1, lab2) => {
    const a = Array.from(lab1 || [], Number), b = Array.from(lab2 || [], Number);
    if (a.length !== 3 || b.length !== 3 || ![...a, ...b].every(Number.isFinite)) throw new Error("deltaE00: give two arrays of three finite numbers");
    return deltaE00(a, b);
  },
  match: (target, n) => C.match(target, n).map((h) => ({thickness_nm: h.thickness_nm, voltage_V: h.voltage_V, delta_E_00: h.delta_E_00})),
  show,
  // the displayed sRGB at a canvas pixel ({x, y}: drawing-buffer pixels from the top-left corner)
  pixel: (q) => {
    if (!view) throw new Error("pixel: the live view needs WebGL2");
    const x = Number(q && q.x), y = Number(q && q.y);
    if (!(x >= 0 && x < canvas.width && y >= 0 && y < canvas.height)) throw new Error("pixel: x, y must lie on the canvas");
    const rgb = view.pixel(x, y);
    return {rgb, hex: "#" + rgb.map((c) => c.toString(16).padStart(2, "0")).join("")};
  },
  lightings: Object.freeze(view ? view.lightings.slice() : ["point"]),
  // the id of the swatch whose hero the live view shows now (at its state), or null
  hero: () => { const s = heroAt(state); return s ? s.id : null; },
  swatches: Object.freeze(swatches.map((s) => Object.freeze(s))),
});
