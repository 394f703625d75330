// The page's address (swatch/catalog/web/link.js) under node --test: what a fragment such as
// #thickness=140&shape=bent+sheet&lighting=point gives show(), what it leaves out, and that the page's
// "link to this view" reads back as the state it was written from.
import {test} from "node:test";
import assert from "node:assert/strict";
import {readFileSync} from "node:fs";
import vm from "node:vm";

const ctx = {};  // link.js is a classic script: its top-level functions become this context's globals
vm.runInNewContext(readFileSync(new URL("../../swatch/catalog/web/link.js", import.meta.url), "utf8"), ctx);
const parse = (h) => JSON.parse(JSON.stringify(ctx.parseViewLink(h)));  // plain objects of this realm

test("a fragment gives show() its keys, numbers as numbers, with or without the #", () => {
  assert.deepEqual(parse("#lighting=point&shape=sphere&thickness=120"),
    {query: {lighting: "point", shape: "sphere", thickness_nm: 120}, ignored: []});
  assert.deepEqual(parse("voltage=25&light=45.5&light_azimuth=-30&view=.5&view_azimuth=1.8e2&fill=0&model=paper"),
    {query: {voltage_V: 25, light_deg: 45.5, light_azimuth_deg: -30, view_deg: 0.5, view_azimuth_deg: 180, fill: 0,
      model: "paper"}, ignored: []});
  assert.deepEqual(parse("#shape=bent+sheet").query, {shape: "bent sheet"});
  assert.deepEqual(parse("#shape=bent%20sheet&&").query, {shape: "bent sheet"});
});

test("a fragment that names no view state (a section, nothing) gives nothing and leaves nothing out", () => {
  for (const h of ["", "#", "#find", "#explorer", undefined, null, 42, {}]) {
    assert.deepEqual(parse(h), {query: {}, ignored: []}, String(h));
  }
});

test("bad values are left out, in order, and never throw: the rest applies", () => {
  const bad = ["thickness=", "thickness2=5", "light=0x10", "view=Infinity", "view_azimuth=1e999", "fill=1,5",
    "fill2", "shape=cube", "shape=Sphere", "model=phong", "lighting=sunset", "light=%E0%A4%A", "__proto__=1",
    "constructor=x", "light= 45", "view=NaN", "thickness=12nm"];
  for (const b of bad) {
    const got = parse("#" + b + "&thickness=80");
    assert.deepEqual(got.query, b.startsWith("thickness=") ? {} : {thickness_nm: 80}, b);
    assert.ok(got.ignored.includes(b), b);
  }
  const got = parse("#fill=%zz&thickness=abc&view=1&light=20&view=2");
  assert.deepEqual(got, {query: {light_deg: 20}, ignored: ["fill=%zz", "thickness=abc", "view=1", "view=2"]});
  const proto = ctx.parseViewLink("#__proto__=1&toString=1").query;  // no key of Object.prototype is taken
  assert.deepEqual(Object.getOwnPropertyNames(proto), []);
  assert.equal(typeof proto.toString, "function");
  assert.equal(Object.getPrototypeOf(Object.getPrototypeOf(proto)), null);  // an ordinary object
  const long = parse("#thickness=1&" + "x".repeat(3000) + "=1");  // no view link: left out whole
  assert.deepEqual(long.query, {});
  assert.equal(long.ignored.length, 1);
});

test("the link of a state reads back as that state (numbers to 2 decimals)", () => {
  const st = {thickness_nm: 140.123, light_deg: 45, view_deg: 12.5, light_azimuth_deg: -30, view_azimuth_deg: 180,
    fill: 0.1, shape: "bent sheet", model: "microfacet", lighting: "studio", exposure: 1.7, coarse: true};
  const link = ctx.viewLink(st);
  assert.equal(link, "#thickness=140.12&light=45&light_azimuth=-30&view=12.5&view_azimuth=180&fill=0.1" +
    "&shape=bent+sheet&model=microfacet&lighting=studio");
  const {exposure, coarse, ...want} = {...st, thickness_nm: 140.12};
  assert.deepEqual(parse(link), {query: want, ignored: []});
});
