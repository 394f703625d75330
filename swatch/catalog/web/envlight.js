// envlight.js — the live view under an environment (the studio, uniform): the thin-film
// GGX BRDF integrated over the environment as swatch.render.env_shading does it. Everything physical
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
#ifdef HAIR
  n = hairTilt(n, d);  // a brushed finish's hairlines (view.js)
#endif
  float cv = dot(n, v);
  vec3 t = v - cv * n;
  float tl = length(t);
  if (tl < 1e-6) {  // along the normal: the tangent of swatch.render.env_shading.local_frame (environment frame)
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
    float inv = 1.0 / (abs(e.x) + abs(e.y) + abs(e.z));
    float px = e.x * inv, pz = e.z * inv;
    vec2 o = e.y < 0.0 ? vec2(sgn(px) * (1.0 - abs(pz)), sgn(pz) * (1.0 - abs(px))) : vec2(px, pz);
    vec4 L = levels[int(s.w)];  // x0 in the atlas, resolution (the map is padded by one texel)
    float h = 0.5 * L.y;
    vec2 f = clamp(o * h + h + 0.5, 0.0, L.y + 1.0 - 1e-3);  // as LevelMaps.bilinear
    float r = texture(atlas, (vec2(L.x, 0.0) + f + 0.5) / atlasSize).r;
    m += texelFetch(wts, ivec2(i, j), 0) * r;
  }
  m *= float(stride);
  // w: the fourth moment (half float, high 16 bits), bin + 1 (9 bits), coverage (7 bits)
  outM = uvec4(floatBitsToUint(m.x), floatBitsToUint(m.y), floatBitsToUint(m.z),
               (packHalf2x16(vec2(m.w, 0.0)) << 16u) | (uint(j + 1) << 7u) | uint(round(cover * 127.0)));
}`;

const ENV_SHADE = `
uniform highp usampler2D mom;
uniform sampler2D coef;
uniform int lod;  // the moments at 1 / 2^lod of the resolution (while the view is dragged)
out vec4 outColor;
void main() {
  uvec4 q = texelFetch(mom, ivec2(gl_FragCoord.xy) >> lod, 0);
  if (q.w == 0u) { outColor = vec4(vec3(BG_ENC), 1.0); return; }  // the background: no shading, no encoding
  float m3 = unpackHalf2x16(q.w >> 16u).x;
  int j = int((q.w >> 7u) & 511u) - 1;
  float cover = float(q.w & 127u) / 127.0;  // of the pixel covered by the object
  vec4 a = texelFetch(coef, ivec2(0, j), 0), b = texelFetch(coef, ivec2(1, j), 0), c = texelFetch(coef, ivec2(2, j), 0);
  vec3 rad = uintBitsToFloat(q.x) * a.xyz + uintBitsToFloat(q.y) * vec3(a.w, b.xy)
           + uintBitsToFloat(q.z) * vec3(b.zw, c.x) + m3 * c.yzw;
  vec3 lin = mix(vec3(BG), tone3(rad), cover);
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
  const S = E.samples, M = S.bins, N = S.samples, K = S.basis, nc = S.cos_theta_d_nodes;
  if (K !== 4 || nc !== C.cosNodes) throw new Error("environment data does not fit this page");
  const dirs = decodeEnvBlock(S.directions), lev = decodeEnvBlock(S.level), cd = decodeEnvBlock(S.cos_theta_d);
  const w = decodeEnvBlock(S.weight), u = decodeEnvBlock(S.moment_weights), H = decodeEnvBlock(S.albedo_matrix);
  const UNIT = {samp: 1, wts: 2, atlas: 3, mom: 4, coef: 5};
  function texture(unit, filter) {
    gl.activeTexture(gl.TEXTURE0 + unit);
    const t = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, t);
    for (const [k, v] of [[gl.TEXTURE_MIN_FILTER, filter], [gl.TEXTURE_MAG_FILTER, filter],
      [gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE], [gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE]]) gl.texParameteri(gl.TEXTURE_2D, k, v);
    return t;
  }
  gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
  const sd = new Float32Array(M * N * 4);
  for (let o = 0; o < M * N; o++) { sd.set(dirs.subarray(3 * o, 3 * o + 3), 4 * o); sd[4 * o + 3] = lev[o]; }
  texture(UNIT.samp, gl.NEAREST);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, N, M, 0, gl.RGBA, gl.FLOAT, sd);
  texture(UNIT.wts, gl.NEAREST);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, N, M, 0, gl.RGBA, gl.FLOAT, u);
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
  gl.activeTexture(gl.TEXTURE0);
  let momTex = null, fbo = null, size = [0, 0];
  function target(wd, h) {
    if (size[0] === wd && size[1] === h) return;
    if (momTex) gl.deleteTexture(momTex);
    if (!fbo) fbo = gl.createFramebuffer();
    momTex = texture(UNIT.mom, gl.NEAREST);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32UI, wd, h, 0, gl.RGBA_INTEGER, gl.UNSIGNED_INT, null);
    gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, momTex, 0);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.activeTexture(gl.TEXTURE0);
    size = [wd, h];
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
  let lastD = null;
  function setThickness(d) {
    if (d === lastD) return;
    gl.activeTexture(gl.TEXTURE0 + UNIT.coef);
    gl.bindTexture(gl.TEXTURE_2D, coefTex);
    gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, 3, M, gl.RGBA, gl.FLOAT, coefficients(C.rowLinearSrgb(d)));
    gl.activeTexture(gl.TEXTURE0);
    lastD = d;
  }
  function setupGather(prog, U) { // sampler units and constants of a gather program
    gl.uniform1i(U.samp, UNIT.samp); gl.uniform1i(U.wts, UNIT.wts); gl.uniform1i(U.atlas, UNIT.atlas);
    gl.uniform1i(U.bins, M);
  }
  function setupShade(prog, U) { gl.uniform1i(U.mom, UNIT.mom); gl.uniform1i(U.coef, UNIT.coef); }
  // the gather pass into the moments target (the caller has set the camera uniforms), at 1 / 2^lod of
  // the canvas resolution
  function gather(name, U, wd, h, lod) {
    const env = maps[name];
    wd = Math.max(1, wd >> lod); h = Math.max(1, h >> lod);
    target(wd, h);
    gl.activeTexture(gl.TEXTURE0 + UNIT.atlas);
    gl.bindTexture(gl.TEXTURE_2D, env.tex);
    gl.activeTexture(gl.TEXTURE0);
    gl.uniform4fv(U.levels, env.levels);
    // while dragged (lod > 0) about 32 of the renderer's samples: a preview, refined when let go (issue 23 gave
    // the renderer 128 samples a bin, which made a drag step five times the work of the earlier 24)
    gl.uniform1i(U.stride, lod > 0 ? Math.max(1, Math.round(N / 32)) : 1);
    gl.uniform2f(U.atlasSize, env.size[0], env.size[1]);
    gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
    gl.viewport(0, 0, wd, h);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  }
  return {gather, setThickness, setupGather, setupShade, albedo, bins: M, names: E.lightings.filter((n) => n in maps), samples: N,
    gatherSource: "#define NSAMPLES " + N + "\n" + ENV_GATHER, shadeSource: ENV_SHADE,
    uniforms: ["samp", "wts", "atlas", "levels", "atlasSize", "mom", "coef", "lod", "stride"]};
}
