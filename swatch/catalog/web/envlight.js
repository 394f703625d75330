// envlight.js — the live view under an environment (the studio, uniform): the thin-film
// GGX BRDF integrated over the environment as swatch.render.builtin.env_shading does it. Everything physical
// comes from the build (swatch.catalog.explorer_env): per view bin the renderer's fixed GGX
// visible-normal samples, the environment's blurred octahedral maps, the dense directional albedo
// matrix and the weights of the per-bin projection of F. Two passes (explorer_env's module doc):
//  * gather, when the view, the shape or the lighting changes: per pixel the moments
//    M_k = sum_i u_ik E_i of the environment over the pixel's samples (an RGBA32UI target);
//  * shade, every frame: radiance = sum_k (p_jk + d_j q_jk) M_k, with p_jk = sum_i u_ik F(x_i),
//    q_jk = sum_i u_ik and the level d_j = ((H F)_j - sum_i w_i F(x_i)) / sum_i w_i computed here per
//    thickness from the colour table's row;
//    then exposure 1 (the white diffuser under the same environment is white), the shoulder above
//    0.8 and sRGB encoding, as swatch render's PNG.

const ENV_GATHER = `
uniform sampler2D samp, wts, atlas;
uniform vec4 levels[8];
uniform vec2 atlasSize;
uniform int bins;
uniform int stride;  // every stride-th sample, weighted stride times (1; more while the view is dragged)
layout(location = 0) out uvec4 outM;
vec3 toEnv(vec3 p) { return vec3(-p.y, p.z, -p.x); }
vec3 toPage(vec3 e) { return vec3(-e.z, -e.x, e.y); }
float sgn(float x) { return x >= 0.0 ? 1.0 : -1.0; }
void main() {
  vec3 d, n;
  float cover = pixelSurface(d, n);  // antialiasing: the shade pass mixes in the background
  if (cover <= 0.0) { outM = uvec4(0u); return; }
  vec3 v = -d;
  if (dot(n, v) < 0.0) n = -n;  // the sheet's back side
#ifdef SET
  vec3 P = toEnv(hitP);  // the surface point, in the set's frame
#endif
#ifdef HAIR
  n = hairTilt(n, d);  // a brushed finish's hairlines (view.js)
#endif
  float cv = dot(n, v);
  vec3 t = v - cv * n;
  float tl = length(t);
  if (tl < 1e-6) {  // along the normal: the tangent of swatch.render.builtin.env_shading.local_frame (environment frame)
    vec3 ne = toEnv(n);
    t = toPage(cross(ne, abs(ne.x) < 0.9 ? vec3(1, 0, 0) : vec3(0, 1, 0)));
    tl = length(t);
  }
  t /= tl;
  vec3 b = cross(n, t);
  float th = acos(clamp(cv, 0.0, 1.0));
  int j = bins - 1 - clamp(int(th * (float(bins) / 1.5707963267948966)), 0, bins - 1);
  vec4 m = vec4(0.0);
  for (int i = 0; i < NSAMPLES; i += stride) {
    vec4 s = texelFetch(samp, ivec2(i, j), 0);  // local direction (normal z, view in +x), level
    vec3 e = toEnv(s.x * t + s.y * b + s.z * n);
#ifdef SET
    float boxPart = 0.0, keep = 1.0;
    {  // the studio set is near: a soft box this sample's ray meets gives its own radiance; else the map (the set
       // without its boxes, seen from the object's centre) in the direction of the point the ray meets
      float hx, hs, k; int hb;
      float th = setHit(P, e, boxSoft * levels[int(s.w)].z, hx, hs, hb, k);
      if (hb >= 0) {
        float Lb = dot(e, boxN[hb]) < 0.0 ? boxL[hb] * setScale : 0.0;
        if (k >= 1.0) { m += texelFetch(wts, ivec2(i, j), 0) * Lb; continue; }
        boxPart = k * Lb; keep = 1.0 - k;
      }
      if (th > 1e29) {  // out of the set: the fill (the map's direction from the centre may still meet the floor)
        m += texelFetch(wts, ivec2(i, j), 0) * (boxPart + keep * fillL * setScale);
        continue;
      }
      e = normalize(P + th * e);
    }
#endif
    float inv = 1.0 / (abs(e.x) + abs(e.y) + abs(e.z));
    float px = e.x * inv, pz = e.z * inv;
    vec2 o = e.y < 0.0 ? vec2(sgn(px) * (1.0 - abs(pz)), sgn(pz) * (1.0 - abs(px))) : vec2(px, pz);
    vec4 L = levels[int(s.w)];  // x0 in the atlas, resolution (the map is padded by one texel)
    float h = 0.5 * L.y;
    vec2 f = clamp(o * h + h + 0.5, 0.0, L.y + 1.0 - 1e-3);  // as LevelMaps.bilinear
    float r = texture(atlas, (vec2(L.x, 0.0) + f + 0.5) / atlasSize).r;
#ifdef SET
    r = boxPart + keep * r;
#endif
    m += texelFetch(wts, ivec2(i, j), 0) * r;
  }
  m *= float(stride);
  // w: the fourth moment (half float, high 16 bits), bin + 1 (9 bits), coverage (7 bits)
  outM = uvec4(floatBitsToUint(m.x), floatBitsToUint(m.y), floatBitsToUint(m.z),
               (packHalf2x16(vec2(m.w, 0.0)) << 16u) | (uint(j + 1) << 7u) | uint(round(cover * 127.0)));
}`;

// The heroes' studio set (swatch.catalog.explorer_set), drawn where the object does not cover the pixel: the
// pixel's ray (page frame, turned into the set's world frame, y up) onto the cyclorama (floor, cove, back wall),
// its baked radiance there (shadow map plus the bounce map tinted by the film's albedo), or a soft box, or the fill.
const SET_GLSL = `
uniform int setOn;
uniform sampler2D setMap;  // R: the set with a black object, G: what a white metal object adds
uniform float floorY, setScale, fillL;
uniform vec3 bleed;  // the film's albedo (RGB): the bounce map's tint
uniform vec3 boxC[3], boxU[3], boxV[3], boxN[3];
uniform float boxL[3];
uniform vec4 cyc0;  // cove radius, wall z, front z, half width
uniform vec4 cyc1;  // wall height, floor length, cove length, warp k
uniform vec4 cyc2;  // s0, the profile's span in front of it and behind, sinh(k)
uniform float boxSoft;  // a box's edge blurred over this many times a sample's blur level (view.js: by the lobe)
vec3 toWorld(vec3 p) { return vec3(-p.y, p.z, -p.x); }
// what of the set a ray (world frame) meets: the distance to the cyclorama (1e30: none) and its (x, s) there; a
// soft box in front of it (box 0-2; -1: none) and how much of the ray's footprint it covers (cover: its edge blurred
// over soft × the distance, the width of the sample's cone, as the maps' blur levels blur everything else)
float setHit(vec3 o, vec3 d, float soft, out float x, out float s, out int box, out float cover) {
  float R = cyc0.x, wallZ = cyc0.y, frontZ = cyc0.z, halfW = cyc0.w;
  float zc = wallZ + R, yc = floorY + R, best = 1e30;
  x = 0.0; s = 0.0; box = -1; cover = 0.0;
  if (d.y < 0.0) {  // the floor
    float t = (floorY - o.y) / d.y; vec3 q = o + t * d;
    if (t > 0.0 && q.z >= zc && q.z <= frontZ && abs(q.x) <= halfW) { best = t; x = q.x; s = frontZ - q.z; }
  }
  if (d.z < 0.0) {  // the back wall
    float t = (wallZ - o.z) / d.z; vec3 q = o + t * d;
    if (t > 0.0 && t < best && q.y >= yc && q.y <= floorY + cyc1.x && abs(q.x) <= halfW) { best = t; x = q.x; s = cyc1.y + cyc1.z + q.y - yc; }
  }
  float a = d.y * d.y + d.z * d.z, b = (o.y - yc) * d.y + (o.z - zc) * d.z;
  float c = (o.y - yc) * (o.y - yc) + (o.z - zc) * (o.z - zc) - R * R, disc = b * b - a * c;
  if (disc >= 0.0 && a > 1e-12) {  // the cove (seen from inside: the far root)
    float t = (-b + sqrt(disc)) / a; vec3 q = o + t * d;
    if (t > 0.0 && t < best && q.y <= yc && q.z <= zc && abs(q.x) <= halfW) {
      best = t; x = q.x; s = cyc1.y + R * clamp(atan(zc - q.z, yc - q.y), 0.0, 1.5707963267948966);
    }
  }
  float near = best;
  for (int i = 0; i < 3; i++) {  // the soft boxes (both faces stop the ray)
    float dn = dot(d, boxN[i]);
    if (abs(dn) < 1e-9) continue;
    float t = dot(boxC[i] - o, boxN[i]) / dn;
    if (t <= 0.0 || t >= near) continue;
    vec3 p = o + t * d - boxC[i];
    float lu = length(boxU[i]), lv = length(boxV[i]);
    float e = min(lu - abs(dot(p, boxU[i])) / lu, lv - abs(dot(p, boxV[i])) / lv);  // > 0 inside, world units
    float w = max(t * soft, 1e-4), k = clamp(0.5 + e / w, 0.0, 1.0);
    if (k > 0.0) { near = t; box = i; cover = k * k * (3.0 - 2.0 * k); }
  }
  return best;
}
`;

// the set's radiance along a ray (world frame): a soft box (its radiance in front, black behind), the cyclorama's
// baked radiance (shadow map plus the bounce map tinted by the film's albedo), or the fill
// the backdrop pass (when the view changes, beside the gather): per pixel the set's radiance along the pixel's ray
// as A + B bleed, A and B as float bits (an RG32UI target): a soft box (its radiance in front, black behind), the
// cyclorama's baked radiance (the shadow map plus the bounce map, which the film's albedo "bleed" tints), or the fill
const BACKDROP_PASS = `
layout(location = 0) out uvec2 outB;
void main() {
  vec3 dPage = normalize(fwd + (win.x + uv.x * aspect * tanHalf) * right + (win.y + uv.y * tanHalf) * up);
  vec3 o = toWorld(eye), d = toWorld(dPage);
  float x, s, k; int box;
  float t = setHit(o, d, tanHalf * abs(dFdy(uv.y)), x, s, box, k);  // the boxes' edges over about a pixel
  vec2 L = vec2(fillL * setScale, 0.0);
  if (t < 1e29) {  // the lightmap's sinh warp (swatch.render.studio_set.lightmap_axes), inverted
    float u = (asinh(clamp(x / cyc0.w, -1.0, 1.0) * cyc2.w) / cyc1.w + 1.0) * 0.5;
    float v = (asinh(clamp((s - cyc2.x) / (s < cyc2.x ? cyc2.y : cyc2.z), -1.0, 1.0) * cyc2.w) / cyc1.w + 1.0) * 0.5;
    L = texture(setMap, vec2(u, v)).rg;
  }
  if (box >= 0) L = mix(L, vec2(dot(d, boxN[box]) < 0.0 ? boxL[box] * setScale : 0.0, 0.0), k);
  outB = uvec2(floatBitsToUint(L.x), floatBitsToUint(L.y));
}`;

const ENV_SHADE = `
uniform highp usampler2D mom;
uniform sampler2D coef;
uniform int lod;  // the moments at 1 / 2^lod of the resolution (while the view is dragged)
out vec4 outColor;
uniform int setOn;
uniform highp usampler2D bgTex;  // the backdrop pass's A, B
uniform vec3 bleed;  // the film's albedo (RGB): the bounce map's tint
void main() {
  uvec4 q = texelFetch(mom, ivec2(gl_FragCoord.xy) >> lod, 0);
  float cover = float(q.w & 127u) / 127.0;  // of the pixel covered by the object
  vec3 bg = vec3(BG);
  if (setOn == 1 && cover < 1.0) {
    uvec2 ab = texelFetch(bgTex, ivec2(gl_FragCoord.xy) >> lod, 0).xy;
    bg = vec3(uintBitsToFloat(ab.x)) + uintBitsToFloat(ab.y) * bleed;
  }
  if (q.w == 0u) {  // the background alone: the set, or the plain grey (no shading)
    if (setOn == 1) { vec3 b = tone3(bg); outColor = vec4(enc(b.r), enc(b.g), enc(b.b), 1.0); }
    else outColor = vec4(vec3(BG_ENC), 1.0);
    return;
  }
  float m3 = unpackHalf2x16(q.w >> 16u).x;
  int j = int((q.w >> 7u) & 511u) - 1;
  vec4 a = texelFetch(coef, ivec2(0, j), 0), b = texelFetch(coef, ivec2(1, j), 0), c = texelFetch(coef, ivec2(2, j), 0);
  vec3 rad = uintBitsToFloat(q.x) * a.xyz + uintBitsToFloat(q.y) * vec3(a.w, b.xy)
           + uintBitsToFloat(q.z) * vec3(b.zw, c.x) + m3 * c.yzw;
  // the object over its background, in radiance (as the path tracer's pixel filter), then the display transform
  vec3 lin = setOn == 1 ? tone3(mix(bg, rad, cover)) : mix(vec3(BG), tone3(rad), cover);
  outColor = vec4(enc(lin.r), enc(lin.g), enc(lin.b), 1.0);
}`;

function decodeEnvBlock(block) { // int16 / uint16 with a per-channel scale, uint8 integers
  const bin = atob(block.data);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
  if (block.type === "uint8") return Float32Array.from(bytes);
  if (block.type === "float16") return new Uint16Array(bytes.buffer);  // raw half-float bits, for the GPU
  const codes = block.type === "int16" ? new Int16Array(bytes.buffer) : new Uint16Array(bytes.buffer);
  const c = block.shape[block.shape.length - 1], out = new Float32Array(codes.length);
  for (let i = 0; i < codes.length; i++) out[i] = codes[i] * block.scale[i % c];
  return out;
}

function makeEnvLight(gl, E, C) {
  const S0 = E.samples, M = S0.bins, N = S0.samples, K = S0.basis, nc = S0.cos_theta_d_nodes;
  if (K !== 4 || nc !== C.cosNodes) throw new Error("environment data does not fit this page");
  // the sample set in use: the catalog's first finish, or another offered finish's (E.finish_samples), decoded
  // when first chosen
  let cd, w, u, H;
  const UNIT = {samp: 1, wts: 2, atlas: 3, mom: 4, coef: 5, set: 8, bg: 9};
  function texture(unit, filter) {
    gl.activeTexture(gl.TEXTURE0 + unit);
    const t = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, t);
    for (const [k, v] of [[gl.TEXTURE_MIN_FILTER, filter], [gl.TEXTURE_MAG_FILTER, filter],
      [gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE], [gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE]]) gl.texParameteri(gl.TEXTURE_2D, k, v);
    return t;
  }
  gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
  const sampTex = texture(UNIT.samp, gl.NEAREST), wtsTex = texture(UNIT.wts, gl.NEAREST);
  const decoded = new Map();
  function useSamples(S) {
    if (S.bins !== M || S.samples !== N || S.basis !== K || S.cos_theta_d_nodes !== nc) throw new Error("a finish's samples do not fit this page");
    if (!decoded.has(S)) {
      const dirs = decodeEnvBlock(S.directions), lev = decodeEnvBlock(S.level);
      const sd = new Float32Array(M * N * 4);
      for (let o = 0; o < M * N; o++) { sd.set(dirs.subarray(3 * o, 3 * o + 3), 4 * o); sd[4 * o + 3] = lev[o]; }
      decoded.set(S, {sd, cd: decodeEnvBlock(S.cos_theta_d), w: decodeEnvBlock(S.weight), u: decodeEnvBlock(S.moment_weights),
        H: decodeEnvBlock(S.albedo_matrix)});
    }
    const D = decoded.get(S);
    ({cd, w, u, H} = D);
    gl.activeTexture(gl.TEXTURE0 + UNIT.samp);
    gl.bindTexture(gl.TEXTURE_2D, sampTex);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, N, M, 0, gl.RGBA, gl.FLOAT, D.sd);
    gl.activeTexture(gl.TEXTURE0 + UNIT.wts);
    gl.bindTexture(gl.TEXTURE_2D, wtsTex);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, N, M, 0, gl.RGBA, gl.FLOAT, D.u);
    gl.activeTexture(gl.TEXTURE0);
  }
  useSamples(S0);
  let finishNow = null;
  // the sample set of an offered finish (false: unchanged or not offered)
  function setFinish(name) {
    const F = E.finish_samples || {};
    if (name === finishNow || !(name in F)) return false;
    useSamples(F[name]);
    finishNow = name;
    lastD = null;  // the coefficients of the thickness again
    return true;
  }
  const coefTex = texture(UNIT.coef, gl.NEAREST);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, 3, M, 0, gl.RGBA, gl.FLOAT, null);
  const maps = {};
  for (const [name, env] of Object.entries(E.environments)) {
    const bits = decodeEnvBlock(env.atlas), [h, wd] = env.atlas.shape;
    const tex = texture(UNIT.atlas, gl.LINEAR);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.R16F, wd, h, 0, gl.RED, gl.HALF_FLOAT, bits);
    const lv = new Float32Array(32);
    env.levels.forEach((l, k) => { lv[4 * k] = l.x0; lv[4 * k + 1] = l.res; });
    maps[name] = {tex, size: [wd, h], levels: lv};
  }
  // the heroes' studio set, per shape: the set seen from the object (an environment map like the others, named
  // "studio@<shape>") and the cyclorama's two lightmaps (RG half floats)
  const SET = E.set || null, setMaps = {};
  if (SET) {
    for (const [shape, v] of Object.entries(SET.shapes)) {
      const env = v.environment, bits = decodeEnvBlock(env.atlas), [h, wd] = env.atlas.shape;
      const tex = texture(UNIT.atlas, gl.LINEAR);
      gl.texImage2D(gl.TEXTURE_2D, 0, gl.R16F, wd, h, 0, gl.RED, gl.HALF_FLOAT, bits);
      const lv = new Float32Array(32);
      // z: the level's blur as the tangent of its width (level 0: about the map's texel)
      env.levels.forEach((l, k) => { lv[4 * k] = l.x0; lv[4 * k + 1] = l.res; lv[4 * k + 2] = Math.tan(Math.max(l.sigma_deg, 180 / l.res / 2) * Math.PI / 180); });
      maps["studio@" + shape] = {tex, size: [wd, h], levels: lv};
      const [nx, ns] = v.texels, sh = decodeEnvBlock(v.shadow), bo = decodeEnvBlock(v.bounce);
      if (sh.length !== nx * ns || bo.length !== nx * ns) throw new Error("the studio set's lightmaps do not fit");
      const rg = new Uint16Array(2 * nx * ns);
      for (let i = 0; i < nx * ns; i++) { rg[2 * i] = sh[i]; rg[2 * i + 1] = bo[i]; }
      const lm = texture(UNIT.set, gl.LINEAR);
      gl.texImage2D(gl.TEXTURE_2D, 0, gl.RG16F, nx, ns, 0, gl.RG, gl.HALF_FLOAT, rg);
      setMaps[shape] = {tex: lm, floorY: v.floor_y, scale: v.scale};
    }
  }
  gl.activeTexture(gl.TEXTURE0);
  // an integer render target on a texture unit, (re)made at a size: the moments' and the backdrop's
  function intTarget(unit, internal, format) {
    const t = {tex: null, fbo: null, size: [0, 0]};
    t.fit = (wd, h) => {
      if (t.size[0] === wd && t.size[1] === h) return;
      if (t.tex) gl.deleteTexture(t.tex);
      if (!t.fbo) t.fbo = gl.createFramebuffer();
      t.tex = texture(unit, gl.NEAREST);
      gl.texImage2D(gl.TEXTURE_2D, 0, internal, wd, h, 0, format, gl.UNSIGNED_INT, null);
      gl.bindFramebuffer(gl.FRAMEBUFFER, t.fbo);
      gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, t.tex, 0);
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
      gl.activeTexture(gl.TEXTURE0);
      t.size = [wd, h];
    };
    return t;
  }
  const momTarget = intTarget(UNIT.mom, gl.RGBA32UI, gl.RGBA_INTEGER), bgTarget = intTarget(UNIT.bg, gl.RG32UI, gl.RG_INTEGER);
  // the backdrop pass into its target (the caller has set the camera and the set's uniforms), at 1 / 2^lod
  function backdropPass(wd, h, lod) {
    wd = Math.max(1, wd >> lod); h = Math.max(1, h >> lod);
    bgTarget.fit(wd, h);
    gl.bindFramebuffer(gl.FRAMEBUFFER, bgTarget.fbo);
    gl.viewport(0, 0, wd, h);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  }
  // per thickness: p_jk + d_j q_jk for every bin (12 floats: four RGB coefficients), from the table's row
  function coefficients(row) {
    const out = new Float32Array(M * 12), kk = nc - 1, F = [0, 0, 0], p = new Float64Array(12), q = new Float64Array(4);
    for (let j = 0; j < M; j++) {
      let s0 = 0, s1 = 0, s2 = 0, W = 0;
      p.fill(0);
      q.fill(0);
      for (let i = 0; i < N; i++) {
        const o = j * N + i;
        const x = Math.min(Math.max(cd[o] * kk, 0), kk), a = Math.min(Math.floor(x), kk - 1), f = x - a;
        for (let ch = 0; ch < 3; ch++) F[ch] = row[4 * a + ch] * (1 - f) + row[4 * a + 4 + ch] * f;
        s0 += w[o] * F[0]; s1 += w[o] * F[1]; s2 += w[o] * F[2]; W += w[o];
        for (let k = 0; k < 4; k++) {
          const uk = u[4 * o + k];
          q[k] += uk;
          p[3 * k] += uk * F[0]; p[3 * k + 1] += uk * F[1]; p[3 * k + 2] += uk * F[2];
        }
      }
      let a0 = 0, a1 = 0, a2 = 0; // the dense directional albedo of this bin
      for (let m = 0; m < nc; m++) { const hm = H[j * nc + m]; a0 += hm * row[4 * m]; a1 += hm * row[4 * m + 1]; a2 += hm * row[4 * m + 2]; }
      // the level: (A - sum_i w_i F_i) / sum_i w_i added to F over the bin's samples (as the renderer's
      // band_weights); sum_i w_i E_i = sum_k q_k M_k with q_k = sum_i u_ik (the constants lie in the basis)
      const dl = W > 0 ? [(a0 - s0) / W, (a1 - s1) / W, (a2 - s2) / W] : [0, 0, 0];
      for (let k = 0; k < 12; k++) out[12 * j + k] = p[k] + dl[k % 3] * q[(k / 3) | 0];
    }
    return out;
  }
  // the directional albedo of each view bin (RGB; the radiance under uniform radiance 1): the point
  // light's fill
  function albedo(row) {
    const out = new Float32Array(M * 4);
    for (let j = 0; j < M; j++) {
      for (let m = 0; m < nc; m++) { const hm = H[j * nc + m]; for (let ch = 0; ch < 3; ch++) out[4 * j + ch] += hm * row[4 * m + ch]; }
      out[4 * j + 3] = 1;
    }
    return out;
  }
  let lastD = null, bleed = [0, 0, 0];
  function setThickness(d) {
    if (d === lastD) return;
    const row = C.rowLinearSrgb(d);
    gl.activeTexture(gl.TEXTURE0 + UNIT.coef);
    gl.bindTexture(gl.TEXTURE_2D, coefTex);
    gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, 3, M, gl.RGBA, gl.FLOAT, coefficients(row));
    gl.activeTexture(gl.TEXTURE0);
    if (SET) {  // the film's hemispherical albedo (the view bins' directional albedo, weighted by sin 2θ)
      const A = albedo(row);
      let wsum = 0;
      bleed = [0, 0, 0];
      for (let j = 0; j < M; j++) {
        const th = (M - 1 - j + 0.5) * (Math.PI / 2 / M), w = Math.sin(2 * th);
        for (let ch = 0; ch < 3; ch++) bleed[ch] += w * A[4 * j + ch];
        wsum += w;
      }
      bleed = bleed.map((x) => x / wsum);
    }
    lastD = d;
  }
  // the shade program's set uniforms for a shape (py name), or the set off (no set, another lighting)
  // (geometry: the set's geometry too, for the gather and backdrop passes; else the shade pass's part only)
  function setStudio(U, shape, on, geometry) {
    const m = on && SET ? setMaps[shape] : null;
    gl.uniform1i(U.setOn, m ? 1 : 0);
    // (the integer sampler on its own unit even when unused: on unit 0's float texture the draw is an error)
    gl.uniform1i(U.bgTex, UNIT.bg);
    if (!m) return;
    gl.uniform3fv(U.bleed, bleed);
    if (!geometry) return;
    const c = SET.cyclorama;
    gl.activeTexture(gl.TEXTURE0 + UNIT.set);
    gl.bindTexture(gl.TEXTURE_2D, m.tex);
    gl.activeTexture(gl.TEXTURE0);
    gl.uniform1i(U.setMap, UNIT.set);
    gl.uniform1f(U.floorY, m.floorY); gl.uniform1f(U.setScale, m.scale); gl.uniform1f(U.fillL, SET.fill);
    gl.uniform4f(U.cyc0, c.cove_radius, c.wall_z, c.front_z, c.half_width);
    gl.uniform4f(U.cyc1, c.wall_height, c.floor_length, c.cove_length, c.warp);
    gl.uniform4f(U.cyc2, c.s0, c.span_front, c.span_back, Math.sinh(c.warp));
    gl.uniform3fv(U.boxC, SET.boxes.flatMap((b) => b.centre)); gl.uniform3fv(U.boxU, SET.boxes.flatMap((b) => b.half_u));
    gl.uniform3fv(U.boxV, SET.boxes.flatMap((b) => b.half_v)); gl.uniform3fv(U.boxN, SET.boxes.flatMap((b) => b.normal));
    gl.uniform1fv(U.boxL, SET.boxes.map((b) => b.radiance));
  }
  // the map a lighting uses around a shape: the set's own where the page has it
  const mapName = (name, shape) => (name === "studio" && SET && setMaps[shape]) ? "studio@" + shape : name;
  function setupGather(prog, U) { // sampler units and constants of a gather program
    gl.uniform1i(U.samp, UNIT.samp); gl.uniform1i(U.wts, UNIT.wts); gl.uniform1i(U.atlas, UNIT.atlas);
    gl.uniform1i(U.bins, M);
  }
  function setupShade(prog, U) { gl.uniform1i(U.mom, UNIT.mom); gl.uniform1i(U.coef, UNIT.coef); }
  // the gather pass into the moments target (the caller has set the camera uniforms), at 1 / 2^lod of
  // the canvas resolution
  function gather(name, U, wd, h, lod, drawShape) {
    const env = maps[name] || maps[name.split("@")[0]];
    wd = Math.max(1, wd >> lod); h = Math.max(1, h >> lod);
    momTarget.fit(wd, h);
    gl.activeTexture(gl.TEXTURE0 + UNIT.atlas);
    gl.bindTexture(gl.TEXTURE_2D, env.tex);
    gl.activeTexture(gl.TEXTURE0);
    gl.uniform4fv(U.levels, env.levels);
    // while dragged (lod > 0) about 32 of the renderer's samples: a preview, refined when let go (issue 23 gave
    // the renderer 128 samples a bin, which made a drag step five times the work of the earlier 24)
    // (16 in the studio set, where each sample's ray also meets the set: the same time a drag step as 32 without)
    gl.uniform1i(U.stride, lod > 0 ? Math.max(1, Math.round(N / (name.includes("@") ? 16 : 32))) : 1);
    gl.uniform2f(U.atlasSize, env.size[0], env.size[1]);
    gl.bindFramebuffer(gl.FRAMEBUFFER, momTarget.fbo);
    gl.viewport(0, 0, wd, h);
    drawShape(wd, h);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  }
  return {gather, backdropPass, setThickness, setFinish, setupGather, setupShade, setStudio, mapName, albedo, bins: M, samples: N,
    names: E.lightings.filter((n) => n in maps), hasSet: !!SET,
    gatherSource: "#define NSAMPLES " + N + "\n" + ENV_GATHER, shadeSource: ENV_SHADE,
    gatherSetSource: "#define NSAMPLES " + N + "\n#define SET 1\n" + SET_GLSL + ENV_GATHER,
    backdropSource: SET_GLSL + BACKDROP_PASS,
    uniforms: ["samp", "wts", "atlas", "levels", "atlasSize", "mom", "coef", "lod", "stride", "setOn", "setMap", "floorY",
      "setScale", "fillL", "bleed", "boxC", "boxU", "boxV", "boxN", "boxL", "cyc0", "cyc1", "cyc2", "bgTex"]};
}
