// link.js — the live view's state in the page's address: index.html#thickness=140&shape=sphere&lighting=point
// opens the page in that view (a link to share, a bookmark), and the page's "link to this view" writes one.
// Pure functions (no DOM), tested under node --test (tests/js/link.test.mjs); page.js applies what they read
// through the same checks as window.swatchCatalog.show, one name at a time, so a bad value is left out and
// the rest still applies.

// the names of the fragment, each the key of show() it sets, and what it takes
const LINK_NUMBERS = {thickness: "thickness_nm", voltage: "voltage_V", light: "light_deg", light_azimuth: "light_azimuth_deg",
  view: "view_deg", view_azimuth: "view_azimuth_deg", fill: "fill"};
const LINK_WORDS = {shape: ["plate", "bent sheet", "sphere", "part"], model: ["microfacet", "paper"],
  lighting: ["point", "uniform", "studio"], finish: ["polished", "satin", "brushed", "bead-blasted"]};
// a plain decimal number (no hex, no Infinity, no empty string: Number("") is 0)
const LINK_NUMBER = /^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d{1,3})?$/;
const LINK_MAX_CHARS = 2000;  // a longer fragment is not a view link

// The fragment (location.hash, with or without its "#") as show() arguments: {query, ignored}. A name not
// listed above, a value of the wrong kind, a name given twice or a malformed escape is left out and named in
// ignored (as "name=value"); a fragment without "=" (a link to a section, #find) gives an empty query. Never throws.
function parseViewLink(hash) {
  const query = {}, ignored = [];
  let s = typeof hash === "string" ? hash : "";
  if (s.startsWith("#")) s = s.slice(1);
  if (!s.includes("=")) return {query, ignored};
  if (s.length > LINK_MAX_CHARS) return {query, ignored: [s.slice(0, 40) + "…"]};
  const pairs = [];
  for (const part of s.split("&")) {
    if (part === "") continue;
    const eq = part.indexOf("=");
    try {
      pairs.push([part, decodeURIComponent((eq < 0 ? part : part.slice(0, eq)).replace(/\+/g, " ")),
        eq < 0 ? null : decodeURIComponent(part.slice(eq + 1).replace(/\+/g, " "))]);
    } catch (e) { pairs.push([part, null, null]); }  // a malformed %-escape
  }
  const count = new Map();
  for (const [, name] of pairs) count.set(name, (count.get(name) || 0) + 1);
  for (const [part, name, value] of pairs) {
    if (name === null || count.get(name) > 1) ignored.push(part);  // given twice: which one was meant?
    else if (value !== null && Object.hasOwn(LINK_NUMBERS, name) && LINK_NUMBER.test(value) && Number.isFinite(Number(value))) {
      query[LINK_NUMBERS[name]] = Number(value);
    } else if (value !== null && Object.hasOwn(LINK_WORDS, name) && LINK_WORDS[name].includes(value)) query[name] = value;
    else ignored.push(part);
  }
  return {query, ignored};
}

// The fragment of a live-view state (show()'s return), "#thickness=…&…": numbers to 2 decimals, as parseViewLink reads.
function viewLink(st) {
  const num = (x) => String(Number(Number(x).toFixed(2)));
  const parts = [];
  for (const [name, key] of Object.entries(LINK_NUMBERS)) {
    if (key !== "voltage_V" && Number.isFinite(Number(st[key]))) parts.push(name + "=" + num(st[key]));
  }
  for (const name of Object.keys(LINK_WORDS)) {
    if (typeof st[name] === "string") parts.push(name + "=" + encodeURIComponent(st[name]).replace(/%20/g, "+"));
  }
  return "#" + parts.join("&");
}
