// microfacet.js — GGX written once per language of the page, as swatch.physics.microfacet:
// ggxReflectanceFactorCos and ggxDRatio in JavaScript (the live view's exposure rule, view.js) and the same
// function in GLSL (GGX_GLSL, the point-light pass of view.js). The environment passes (envlight.js) take
// their GGX samples from the build (swatch.catalog.explorer_env), so they need no GGX of their own.
// Tested under node --test against the Python functions (tests/js/microfacet.test.mjs).

// pi D G / (4 cos_l cos_v) * max(cos_l, 0) for GGX with height-correlated Smith G
// (swatch.physics.microfacet.ggx_reflectance_factor_cos): cosines n.l, n.v (> 0, a visible surface), n.h
function ggxReflectanceFactorCos(cosL, cosV, cosH, alpha) {
  const c = Math.max(cosL, 0), a2 = alpha * alpha, om = 1 - a2;
  const den = cosH * cosH * (a2 - 1) + 1;
  const vis = c * Math.sqrt(cosV * cosV * om + a2) + cosV * Math.sqrt(c * c * om + a2);
  return 0.5 * a2 * c / Math.max(den * den * vis, 1e-30);
}
// D(h) / D(n) for GGX (swatch.physics.microfacet.D_ratio): 1 on the mirror direction
function ggxDRatio(cosH, alpha) {
  const a2 = alpha * alpha, den = cosH * cosH * (a2 - 1) + 1;
  return a2 * a2 / (den * den);
}
const GGX_GLSL = `
float ggxReflectanceFactorCos(float cosL, float cosV, float cosH, float alpha) {
  float c = max(cosL, 0.0), a2 = alpha * alpha, om = 1.0 - a2;
  float den = cosH * cosH * (a2 - 1.0) + 1.0;
  float vis = c * sqrt(cosV * cosV * om + a2) + cosV * sqrt(c * c * om + a2);
  return 0.5 * a2 * c / max(den * den * vis, 1e-30);
}
`;
