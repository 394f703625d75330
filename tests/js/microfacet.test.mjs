// The page's one GGX in JavaScript (swatch/catalog/web/microfacet.js) under node --test, against
// swatch.physics.microfacet (ggx_reflectance_factor_cos, D_ratio) on values the Python side writes into the
// fixture named by SWATCH_JS_FIXTURE (tests/catalog/test_page_js.py); the Python functions are themselves checked
// against scipy quadrature (the furnace test, tests/physics/test_microfacet.py).
import {test} from "node:test";
import assert from "node:assert/strict";
import {readFileSync} from "node:fs";
import vm from "node:vm";

const here = new URL(".", import.meta.url);
const ctx = {};
vm.runInNewContext(readFileSync(new URL("../../swatch/catalog/web/microfacet.js", here), "utf8"), ctx);
const skip = !process.env.SWATCH_JS_FIXTURE;
const fx = skip ? null : JSON.parse(readFileSync(process.env.SWATCH_JS_FIXTURE, "utf8"));

test("GGX reflectance factor and D(h)/D(n) agree with swatch.physics.microfacet", {skip}, () => {
  assert.ok(fx.ggx.length >= 200);
  for (const [cl, cv, ch, alpha, want, ratio] of fx.ggx) {
    const got = ctx.ggxReflectanceFactorCos(cl, cv, ch, alpha);
    assert.ok(Math.abs(got - want) <= 1e-9 * Math.max(1, Math.abs(want)), `${[cl, cv, ch, alpha]}: ${got} against ${want}`);
    assert.ok(Math.abs(ctx.ggxDRatio(ch, alpha) - ratio) <= 1e-9 * Math.max(1, ratio), `${[ch, alpha]}: D ratio`);
  }
  assert.equal(ctx.ggxReflectanceFactorCos(-0.2, 0.5, 0.9, 0.3), 0);  // lit from behind: nothing
});

test("the GLSL GGX is the JavaScript one, term for term", () => {
  const js = ctx.ggxReflectanceFactorCos.toString().replace(/Math\.|const |\s+/g, "").replace(/1e-30/, "");
  const glsl = vm.runInContext("GGX_GLSL", ctx).replace(/float |\s+|\.0(?=\D)/g, "").replace(/1e-30/, "");
  for (const part of ["a2=alpha*alpha", "om=1-a2", "den=cosH*cosH*(a2-1)+1", "vis=c*sqrt(cosV*cosV*om+a2)+cosV*sqrt(c*c*om+a2)",
    "0.5*a2*c/max(den*den*vis,"]) {
    assert.ok(js.includes(part), "js: " + part + " in " + js);
    assert.ok(glsl.includes(part), "glsl: " + part + " in " + glsl);
  }
});
