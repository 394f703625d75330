// The page's colorimetry (swatch/catalog/web/colour.js) under node --test, outside the browser:
// CIEDE2000 on the 34 published pairs of Sharma, Wu & Dalal 2005 (tests/data/ciede2000_sharma2005.csv) and
// on the values colour-science computes for random pairs (a fixture tests/catalog/test_page_js.py writes and names
// in SWATCH_JS_FIXTURE); the WCAG ink choice of the compare labels.
import {test} from "node:test";
import assert from "node:assert/strict";
import {readFileSync} from "node:fs";
import vm from "node:vm";

const here = new URL(".", import.meta.url);
const ctx = {};  // colour.js is a classic script: its top-level functions become this context's globals (its consts: vm.runInContext)
vm.runInNewContext(readFileSync(new URL("../../swatch/catalog/web/colour.js", here), "utf8"), ctx);

const pairs = readFileSync(new URL("../data/ciede2000_sharma2005.csv", here), "utf8").split("\n")
  .filter((l) => /^\d/.test(l)).map((l) => l.split(",").map(Number));

test("CIEDE2000 gives the 34 published pairs of Sharma, Wu & Dalal 2005 to their 4 decimals", () => {
  assert.equal(pairs.length, 34);
  for (const [n, L1, a1, b1, L2, a2, b2, want] of pairs) {
    for (const [x, y] of [[[L1, a1, b1], [L2, a2, b2]], [[L2, a2, b2], [L1, a1, b1]]]) {  // symmetric
      const got = ctx.deltaE00(x, y);
      assert.ok(Math.abs(got - want) <= 5e-5, `pair ${n}: ${got} against ${want}`);
    }
  }
});

test("CIEDE2000 agrees with colour-science on the fixture the Python side writes", {skip: !process.env.SWATCH_JS_FIXTURE}, () => {
  const fx = JSON.parse(readFileSync(process.env.SWATCH_JS_FIXTURE, "utf8"));
  assert.ok(fx.delta_E_00.length >= 100);
  fx.delta_E_00.forEach(([lab1, lab2, want], i) => {
    const got = ctx.deltaE00(lab1, lab2);
    assert.ok(Math.abs(got - want) <= 1e-9 * Math.max(1, want), `#${i}: ${got} against ${want}`);
  });
});

test("the ink on a chip has WCAG contrast of at least 4.5, black on pale chips and white on dark ones", () => {
  assert.equal(ctx.inkFor("#ffffff"), "#000000");
  assert.equal(ctx.inkFor("#000000"), "#ffffff");
  assert.equal(ctx.inkFor("#e8d27a"), "#000000");  // straw
  const hex = (rgb) => "#" + rgb.map((x) => x.toString(16).padStart(2, "0")).join("");
  for (let v = 0; v < 256; v += 5) {
    for (const c of [hex([v, v, v]), hex([v, 255 - v, 128]), hex([255, v, 0])]) {
      assert.ok(ctx.contrastRatio(c, ctx.inkFor(c)) >= 4.5, c);
    }
  }
});

test("the shaders' sRGB encoding without pow stays within 0.004/255 of IEC 61966-2-1's formula", () => {
  const exact = (c) => c <= 0.0031308 ? 12.92 * c : 1.055 * Math.pow(c, 1 / 2.4) - 0.055;
  let worst = 0, flips = 0, n = 0;
  for (let i = 0; i <= 200000; i++) {
    const c = i < 100000 ? i / 100000 : Math.pow(10, -6 + 6 * (i - 100000) / 100000);  // uniform and logarithmic
    const e = Math.abs(ctx.srgbEncodeFast(c) - exact(c)) * 255;
    worst = Math.max(worst, e);
    if (Math.round(ctx.srgbEncodeFast(c) * 255) !== Math.round(exact(c) * 255)) flips++;
    n++;
  }
  assert.ok(worst <= 0.004, `worst ${worst}/255`);
  assert.ok(flips / n < 0.01, `${flips} of ${n} 8-bit values differ`);
  assert.equal(ctx.srgbEncodeFast(0), 0);
  assert.ok(Math.abs(ctx.srgbEncodeFast(1) - 1) < 2e-5 && ctx.srgbEncodeFast(2) === ctx.srgbEncodeFast(1));
  // the GLSL the live view compiles carries the same coefficients
  for (const k of vm.runInContext("SRGB_ENCODE_FIT", ctx)) assert.ok(vm.runInContext("SRGB_ENCODE_GLSL", ctx).includes("(" + k.toFixed(9) + ")"), String(k));
});

test("the growth law (voltageOf, thicknessOf) is swatch.physics.growth's, one slope or two", {skip: !process.env.SWATCH_JS_FIXTURE}, () => {
  const fx = JSON.parse(readFileSync(process.env.SWATCH_JS_FIXTURE, "utf8"));
  assert.equal(fx.growth.length, 2);
  for (const {law, voltage_V, thickness_nm, voltage_back_V} of fx.growth) {
    voltage_V.forEach((v, i) => {
      assert.ok(Math.abs(ctx.thicknessOf(law, v) - thickness_nm[i]) <= 1e-9, `thicknessOf(${v})`);
      assert.ok(Math.abs(ctx.voltageOf(law, thickness_nm[i]) - voltage_back_V[i]) <= 1e-9, `voltageOf(${thickness_nm[i]})`);
    });
  }
  assert.equal(ctx.voltageOf({nm_per_V: null, offset_nm: 0}, 50), null);
  assert.ok(Number.isNaN(ctx.thicknessOf({nm_per_V: null, offset_nm: 0}, 20)));
});
