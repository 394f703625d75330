// view.js — the live WebGL2 view: a plate, a bent sheet or a sphere (the scenes of swatch render, embedded by
// the build: swatch.catalog.explorer.scene_data) under one directional light or an environment (envlight.js).
// Point light, per pixel: cos(theta_d) = h.l picks the colour of the thin film from the embedded
// table (one thickness row, linear sRGB from 2-degree XYZ, interpolated on the GPU); the microfacet
// model multiplies it by pi D G / (4 cos_l cos_v) * cos_l (GGX, height-correlated Smith G:
// ggxReflectanceFactorCos of microfacet.js, as swatch.physics.microfacet.ggx_reflectance_factor_cos); then the
// display transform of swatch.render.display: exposure k, per-channel shoulder above 0.8, sRGB encoding,
// background linear grey 0.18. Two passes (POINT_GEOM when the geometry changes, POINT_SHADE every frame).

const VS = `#version 300 es
in vec2 p; out vec2 uv;
void main() { uv = p; gl_Position = vec4(p, 0.0, 1.0); }`;

// the designer's part (SHAPE 3): its triangles rasterised (page coordinates), the fragment's surface point and
// interpolated normal passed on; the same camera as the rays of the other shapes, a depth buffer for hidden faces
const MESH_VS = `#version 300 es
in vec3 pos; in vec3 nrm;
uniform vec3 eye, fwd, right, up;
uniform float tanHalf, aspect;
uniform vec2 win;
out vec3 vP; out vec3 vN; out vec2 uv;
void main() {
  vec3 q = pos - eye;
  float z = dot(q, fwd);
  vec2 ndc = vec2((dot(q, right) / z - win.x) / (aspect * tanHalf), (dot(q, up) / z - win.y) / tanHalf);
  const float zn = 0.05, zf = 60.0;
  gl_Position = vec4(ndc * z, (z * (zf + zn) - 2.0 * zf * zn) / (zf - zn), z);
  vP = pos; vN = nrm; uv = ndc;
}`;

// the scene (camera ray, plate / bent sheet / sphere) and the display transform, shared by the passes
const GEOM = `#version 300 es
precision highp float;
precision highp int;
in vec2 uv;
uniform vec3 eye, fwd, right, up;
uniform float tanHalf, aspect, bendR, bendPhi, bendH;
uniform vec2 win;  // the window's centre (swatch.render.camera.Camera.fitted: cx, cy); tanHalf its half height
uniform vec3 bendX, bendY, bendZ;  // the sheet's frame: across, its axis, towards its middle (page coordinates)
const float BG = 0.18, BG_ENC = ${srgbEncodeFast(0.18).toFixed(9)};  // the background and its sRGB
// Each shape gives, for the pixel's ray d, a signed distance e to its outline (world units; > 0 on the
// object) and the normal n of the nearest surface point, defined on both sides of the outline: the pass
// turns e into the pixel's coverage with its screen-space derivative (analytic antialiasing: one ray a
// pixel, no supersampling) and shades the edge pixels with n, turned analytically to the normal at the
// middle of the pixel's covered part (tilt: no second ray, which cost a third of the frame in software GL).
const float FAR = -1e3;
// what the outline distance e was measured to, for tilt(): SIL a silhouette (the ray's closest approach
// sil to a sphere or to the sheet's axis: radius silR, ray direction silD in that plane), END the sheet's
// curved end (the hit at angle endPhi about the axis), else nothing that turns the normal (a straight edge)
const int NONE = 0, SIL = 1, END = 2;
int kind; vec3 sil, silD; float silR, endPhi;
vec3 hitP;  // the surface point the pixel's ray meets (page coordinates; for the studio set's parallax)
float edgePlate(vec3 o, vec3 d, out vec3 n) {
  n = vec3(0, 0, 1); kind = NONE;
  float t = abs(d.z) < 1e-6 ? -1.0 : -o.z / d.z;
  if (t <= 0.0) return FAR;
  vec3 q = o + t * d;
  hitP = q;
  return 1.0 - max(abs(q.x), abs(q.y));
}
float edgeBend(vec3 o, vec3 d, out vec3 n) {
  vec3 c = vec3(0, 0, -bendR); vec2 oc = (o - c).xz; vec2 dd = d.xz;
  float a = max(dot(dd, dd), 1e-9), b = dot(oc, dd), k = dot(oc, oc) - bendR * bendR, disc = b * b - a * k;
  // beyond the tangent (the outline of the curved side): the distance of the ray from the axis, less R
  vec2 near = oc - (b / a) * dd;
  float tangent = bendR - length(near);
  n = normalize(vec3(near.x, 0, near.y));
  sil = n; silD = normalize(vec3(dd.x, 0, dd.y)); silR = bendR;
  if (disc < 0.0) {  // the ray passes the cylinder: how far from the sheet's outline there
    vec3 q = o - (b / a) * d;
    float ey = bendH - abs(q.y), ep = (bendPhi - abs(atan(near.x, near.y))) * bendR, e = min(min(tangent, ey), ep);
    kind = e == tangent ? SIL : NONE;
    return e;
  }
  float s = sqrt(disc), best = FAR;
  kind = NONE;
  for (int i = 0; i < 2; i++) {
    float t = (i == 0 ? (-b - s) : (-b + s)) / a;
    if (t <= 0.0) continue;
    vec3 q = o + t * d; vec3 r = q - c;
    float phi = atan(r.x, r.z), ey = bendH - abs(q.y), ep = (bendPhi - abs(phi)) * bendR;
    float et = i == 0 ? tangent : 1e3, e = min(min(ey, ep), et);
    if (e > best) {
      best = e; n = normalize(vec3(r.x, 0, r.z)); hitP = q;
      kind = e == et ? SIL : e == ep ? END : NONE; endPhi = phi;
    }
    if (e >= 0.0) break;  // the front layer where it is there, else the back one
  }
  return best;
}
float edgeSphere(vec3 o, vec3 d, out vec3 n) {
  float b = dot(o, d);
  vec3 near = o - b * d;  // the ray's closest point to the centre
  float r = length(near);
  kind = SIL; sil = near / max(r, 1e-9); silD = d; silR = 1.0;
  if (b >= 0.0) { n = vec3(0, 0, 1); kind = NONE; return FAR; }
  n = r < 1.0 ? normalize(o - (b + sqrt(1.0 - r * r)) * d) : near / r;
  hitP = n;  // the unit sphere about the origin
  return 1.0 - r;
}
vec3 bendToPage(vec3 v) { return v.x * bendX + v.y * bendY + v.z * bendZ; }
float edge(vec2 p, out vec3 d, out vec3 n) {  // the pixel's ray d, the outline distance and the normal
  d = normalize(fwd + (win.x + p.x * aspect * tanHalf) * right + (win.y + p.y * tanHalf) * up);
#if SHAPE == 0
  return edgePlate(eye, d, n);
#elif SHAPE == 1
  // edgeBend works in the sheet's frame (axis y, the middle of the sheet at the origin, its axis at z = -R)
  vec3 nl;
  float e = edgeBend(vec3(dot(eye, bendX), dot(eye, bendY), dot(eye, bendZ) - bendR),
                     vec3(dot(d, bendX), dot(d, bendY), dot(d, bendZ)), nl);
  n = bendToPage(nl);
  hitP = bendToPage(hitP + vec3(0.0, 0.0, bendR));  // from the sheet's frame (its middle at the origin)
  return e;
#else
  return edgeSphere(eye, d, n);
#endif
}
// the normal where the outline distance is e2 > 0 along the same measure (the last edge() call's outline):
// on a silhouette of radius R, the front point at distance R - e2 from the centre (or axis) in the plane
// of the ray; at the sheet's curved end, e2 / R further round; a straight edge does not turn the normal
vec3 tilt(vec3 n, float e2) {
  vec3 r;
  if (kind == SIL) {
    float rho = clamp(silR - e2, 0.0, silR);
    r = normalize(sil * rho - silD * sqrt(silR * silR - rho * rho));
  } else if (kind == END) {
    float phi = sign(endPhi) * max(bendPhi - e2 / bendR, 0.0);
    r = vec3(sin(phi), 0, cos(phi));
  } else return n;
#if SHAPE == 1
  r = bendToPage(r);  // from the sheet's frame
#endif
  return r;
}
// the pixel's coverage by the object (0 to 1) from e and its change across the pixel (derivatives: in
// uniform control flow), and the ray and normal to shade it with: the pixel's centre, or on the outline
// the normal at the middle of the covered part (the silhouette itself is grazing: its shading is not the
// pixel's)
#if SHAPE == 3
in vec3 vP; in vec3 vN;
float pixelSurface(out vec3 d, out vec3 n) {  // a rasterised fragment of the part: all of it covered
  d = normalize(vP - eye); n = normalize(vN); hitP = vP;
  return 1.0;
}
#else
float pixelSurface(out vec3 d, out vec3 n) {
  float e = edge(uv, d, n);
  vec2 g = vec2(dFdx(e), dFdy(e)), du = vec2(dFdx(uv.x), dFdy(uv.y));
  // the change of e across the pixel, at most 20 pixels' width at the object's distance: e jumps where the
  // bent sheet's front layer gives way to the back one, which is no outline
  float w = min(abs(g.x) + abs(g.y), 20.0 * tanHalf * abs(du.y) * length(eye));
  float cover = e <= FAR * 0.5 ? 0.0 : clamp(0.5 + e / max(w, 1e-7), 0.0, 1.0);
  float e2 = e + (0.5 * (1.0 - cover) + 0.05) * min(length(g), w);  // the middle of the covered part
  if (cover > 0.0 && cover < 1.0 && e2 > 0.0) n = tilt(n, e2);
  return cover;
}
#endif
float tone(float x) { return x <= 0.8 ? x : 0.8 + 0.2 * (1.0 - exp(-(x - 0.8) / 0.2)); }
// the shoulder on three channels: a branch, so pixels below it (most) skip the exponentials
vec3 tone3(vec3 x) {
  if (max(max(x.r, x.g), x.b) <= 0.8) return x;
  return vec3(tone(x.r), tone(x.g), tone(x.b));
}
${SRGB_ENCODE_GLSL}`;

// The point light in two passes, as the environment (envlight.js): the geometry pass, when the view, the light,
// the shape or the model changes, writes per pixel what does not depend on the film (cos theta_d, the GGX
// factor, the view bin of the fill and the coverage) into an RGBA32UI target; the shade pass, every frame
// (the thickness slider), only looks the film's colour up in the table row and applies the display transform.
const POINT_GEOM = `
uniform vec3 light;
uniform float alpha;
uniform int bins;  // view bins of the fill's directional albedo (0: the fill uses F(theta_v) instead)
layout(location = 0) out uvec4 outG;
${GGX_GLSL}
void main() {
  vec3 d, n;
  float cover = pixelSurface(d, n);
  if (cover <= 0.0) { outG = uvec4(0u); return; }
  vec3 v = -d;
  if (dot(n, v) < 0.0) n = -n;  // the sheet's back side
#ifdef HAIR
  n = hairTilt(n, d);  // a brushed finish's hairlines
#endif
  float cl = dot(n, light), cv = max(dot(n, v), 0.0);
  float lv = dot(light, v); float cd = sqrt(max((lv + 1.0) * 0.5, 1e-12));
  float ch = (cl + cv) * (0.5 / cd);
#if MODEL == 1
  float s = (cl > 0.0 && cv > 0.0) ? 1.0 : 0.0;
#else
  float s = ggxReflectanceFactorCos(cl, cv, ch, alpha);
#endif
  int j = bins > 0 ? bins - 1 - clamp(int(acos(clamp(cv, 0.0, 1.0)) * (float(bins) / 1.5707963267948966)), 0, bins - 1) : 0;
  // w: the view bin (above bit 8) and the coverage (8 bits, at least 1 on the object)
  outG = uvec4(floatBitsToUint(cd), floatBitsToUint(s), floatBitsToUint(cv),
               (uint(j) << 8u) | uint(max(round(cover * 255.0), 1.0)));
}`;

const POINT_SHADE = `
out vec4 outColor;
uniform highp usampler2D geo;
uniform int lod;  // the geometry at 1 / 2^lod of the resolution (while the view is dragged)
uniform sampler2D row; uniform int nodes;
uniform float exposure, fill;
uniform sampler2D alb;  // directional albedo per view bin (RGB), for the fill; bins = 0: F(theta_v) instead
uniform int bins;
vec3 tableAt(float c) {
  float x = clamp(c, 0.0, 1.0) * float(nodes - 1);
  int i = min(int(x), nodes - 2); float f = x - float(i);
  return mix(texelFetch(row, ivec2(i, 0), 0).rgb, texelFetch(row, ivec2(i + 1, 0), 0).rgb, f);
}
void main() {
  uvec4 q = texelFetch(geo, ivec2(gl_FragCoord.xy) >> lod, 0);
  if (q.w == 0u) { outColor = vec4(vec3(BG_ENC), 1.0); return; }  // the background: no shading, no encoding
  vec3 col = tableAt(uintBitsToFloat(q.x)) * (uintBitsToFloat(q.y) * exposure);
  if (fill > 0.0) {  // a uniform white surround of radiance fill: the directional albedo of the view bin
    col += fill * (bins > 0 ? texelFetch(alb, ivec2(0, int(q.w >> 8u)), 0).rgb : tableAt(uintBitsToFloat(q.z)));
  }
  vec3 lin = mix(vec3(BG), tone3(col), float(q.w & 255u) / 255.0);
  outColor = vec4(enc(lin.r), enc(lin.g), enc(lin.b), 1.0);
}`;

// The hairlines of a brushed finish (swatch.physics.finishes.hairline_slope, brush_coordinates, tilt_normals; the
// build embeds their constants): the facet normal tilted across the grain by a procedural slope, a sum of smooth
// value-noise octaves over an integer hash (the same uint32 arithmetic as the Python), on the surface coordinates
// across and along the grain (page coordinates: the render's x is -y here, its y is z, its z is -x).
function hairSource(h) {
  const f = (x) => Number(x).toFixed(6);
  const octaves = h.octaves.map(([freq, w], k) =>
    `  s += ${f(w)} * hairNoise(vec2(across * ${f(freq)} + ${f(17 * k)}, along * ${f(freq / h.stretch)} + ${f(31 * k)}));`).join("\n");
  return `
float hairHash(int i, int j) {
  uint h = uint(i) * 0x27D4EB2Du ^ uint(j) * 0x165667B1u;
  h = (h ^ (h >> 15u)) * 0x2C1B3C6Du;
  h = (h ^ (h >> 12u)) * 0x297A2D39u;
  h ^= h >> 15u;
  return float(h >> 8u) * (2.0 / 16777216.0) - 1.0;
}
float hairNoise(vec2 q) {
  vec2 i0 = floor(q), fr = q - i0, w = fr * fr * (3.0 - 2.0 * fr);
  int i = int(i0.x), j = int(i0.y);
  float a = hairHash(i, j) + w.x * (hairHash(i + 1, j) - hairHash(i, j));
  float b = hairHash(i, j + 1) + w.x * (hairHash(i + 1, j + 1) - hairHash(i, j + 1));
  return a + w.y * (b - a);
}
// n: the shading normal facing the viewer, d: the pixel's ray
vec3 hairTilt(vec3 n, vec3 d) {
  float across, along; vec3 axis;
#if SHAPE == 0
  vec3 p = eye + (-eye.z / (abs(d.z) < 1e-6 ? -1e-6 : d.z)) * d;
  across = -p.x; along = -p.y; axis = vec3(0.0, -1.0, 0.0);
#elif SHAPE == 1
  vec2 dd = d.xy; float a2 = max(dot(dd, dd), 1e-12);
  float tp = dot(n.xy - eye.xy, dd) / a2, tm = dot(-n.xy - eye.xy, dd) / a2;
  float rp = length(eye.xy + tp * dd - n.xy), rm = length(eye.xy + tm * dd + n.xy);
  vec3 p = eye + (rp <= rm ? tp : tm) * d;
  across = atan(-p.y, -p.x); along = p.z; axis = vec3(0.0, 0.0, 1.0);
#else
  across = atan(-n.y, -n.x); along = n.z; axis = vec3(0.0, 0.0, 1.0);
#endif
  float s = 0.0;
${octaves}
  s *= ${f(h.slope)};
  vec3 t = axis - dot(n, axis) * n;
  if (length(t) < 0.02) { t = vec3(0.0, -1.0, 0.0) - dot(n, vec3(0.0, -1.0, 0.0)) * n; }
  t = normalize(t);
  return normalize(n + s * cross(n, t));
}
`;
}

function makeView(canvas, C, settings, envData) {
  const DEG = Math.PI / 180;
  const gl = canvas.getContext("webgl2", {antialias: false, preserveDrawingBuffer: true});
  if (!gl) return null;
  function compile(type, src) {
    const s = gl.createShader(type); gl.shaderSource(s, src); gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  }
  // one program per pass, shape and shading model (no branching on them per pixel: software GL is faster)
  const programs = new Map();
  const vs = compile(gl.VERTEX_SHADER, VS);
  let meshVsShader = null;
  const meshVs = () => meshVsShader || (meshVsShader = compile(gl.VERTEX_SHADER, MESH_VS));
  const UNIFORMS = ["row", "nodes", "eye", "fwd", "right", "up", "light", "tanHalf", "aspect", "alpha", "exposure",
    "bendR", "bendPhi", "bendH", "bendX", "bendY", "bendZ", "win", "fill", "alb", "bins", "geo", "lod", "boxSoft"];
  let env = null;  // the environment passes (envlight.js), when the page embeds them
  // the finish in use: its GGX alpha and, brushed, its hairlines (settings.finishes: each offered finish; without
  // them the catalog's one finish, settings.roughness and settings.hairlines)
  const FIN = settings.finishes || {};
  let roughness = settings.roughness, hairlines = settings.hairlines, finishNow = null;
  function useFinish(name) {
    if (!name || name === finishNow || !(name in FIN)) return false;
    roughness = FIN[name].roughness_alpha;
    hairlines = FIN[name].anisotropic ? settings.hairlines : null;
    if (env) env.setFinish(name);
    finishNow = name;
    lastGather = null; lastGeom = null; lastKey = null;
    return true;
  }
  function program(pass, shape, model) {
    const key = pass + "/" + shape + "/" + model + (hairlines ? "/hair" : "");
    if (programs.has(key)) return programs.get(key);
    const body = {pgeom: POINT_GEOM, pshade: POINT_SHADE}[pass] ||
      (pass === "gather" ? env.gatherSource : pass === "gatherset" ? env.gatherSetSource :
        pass === "backdrop" ? env.backdropSource : env.shadeSource);
    const hair = hairlines ? "\n#define HAIR 1" : "";
    const src = GEOM.replace("precision highp float;", "precision highp float;\n#define SHAPE " + shape + "\n#define MODEL " + model + hair) +
      (hairlines ? hairSource(hairlines) : "") + body;
    const prog = gl.createProgram();
    const rasterised = shape === MESH && pass !== "pshade" && pass !== "shade" && pass !== "backdrop";
    gl.attachShader(prog, rasterised ? meshVs() : vs);
    gl.attachShader(prog, compile(gl.FRAGMENT_SHADER, src));
    gl.bindAttribLocation(prog, 0, "p");
    gl.bindAttribLocation(prog, 1, "pos");
    gl.bindAttribLocation(prog, 2, "nrm");
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
    const U = {};
    for (const name of UNIFORMS.concat(env ? env.uniforms : [])) U[name] = gl.getUniformLocation(prog, name);
    gl.useProgram(prog);
    if (pass === "pgeom") gl.uniform1i(U.bins, env ? env.bins : 0);
    else if (pass === "pshade") {
      gl.uniform1i(U.row, 0); gl.uniform1i(U.nodes, C.cosNodes); gl.uniform1i(U.alb, ALB_UNIT);
      gl.uniform1i(U.bins, env ? env.bins : 0); gl.uniform1i(U.geo, GEO_UNIT);
    }
    else if (pass === "gather" || pass === "gatherset") env.setupGather(prog, U);
    else env.setupShade(prog, U);
    const entry = {prog, U};
    programs.set(key, entry);
    return entry;
  }
  const buf = gl.createBuffer();
  gl.bindBuffer(gl.ARRAY_BUFFER, buf);
  gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 3, -1, -1, 3]), gl.STATIC_DRAW);
  gl.enableVertexAttribArray(0);
  gl.vertexAttribPointer(0, 2, gl.FLOAT, false, 0, 0);
  const tex = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, tex);
  for (const [k, v] of [[gl.TEXTURE_MIN_FILTER, gl.NEAREST], [gl.TEXTURE_MAG_FILTER, gl.NEAREST],
    [gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE], [gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE]]) gl.texParameteri(gl.TEXTURE_2D, k, v);
  gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, C.cosNodes, 1);  // the thickness row, rewritten per thickness
  // the scene of swatch render (swatch.render.scene.make_scene), embedded by the build (swatch.catalog.explorer.
  // scene_data) in page coordinates: per shape the camera distance, the framing and the light's axes; the
  // bent sheet is --shape cylinder's half cylinder
  const SC = settings.scene, PY_SHAPES = ["flat", "cylinder", "sphere"].concat(SC.mesh ? ["mesh"] : []);
  const MESH = 3;  // the part's shape index (SHAPE 3 in the shaders)
  // the part's triangles (page coordinates): a vertex array of corners and normals, drawn with a depth buffer
  let meshVao = null, meshCount = 0;
  if (SC.mesh) {
    const corners = decodeBlock(SC.mesh.corners), normals = decodeBlock(SC.mesh.normals);
    meshCount = corners.length / 3;
    meshVao = gl.createVertexArray();
    gl.bindVertexArray(meshVao);
    for (const [loc, data] of [[1, corners], [2, normals]]) {
      const b = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, b);
      gl.bufferData(gl.ARRAY_BUFFER, Float32Array.from(data), gl.STATIC_DRAW);
      gl.enableVertexAttribArray(loc);
      gl.vertexAttribPointer(loc, 3, gl.FLOAT, false, 0, 0);
    }
    gl.bindVertexArray(null);
    gl.bindBuffer(gl.ARRAY_BUFFER, buf);
  }
  // draw the bound program over the target: the full-screen triangle, or the part's triangles (the target cleared
  // to "nothing here" first, hidden faces by depth)
  let depthRb = null, depthSize = [0, 0];
  function drawShape(shape, wd, h) {
    if (shape !== MESH) { gl.drawArrays(gl.TRIANGLES, 0, 3); return; }
    if (!depthRb) depthRb = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, depthRb);
    if (depthSize[0] !== wd || depthSize[1] !== h) {
      gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT24, wd, h);
      depthSize = [wd, h];
    }
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depthRb);
    gl.clearBufferuiv(gl.COLOR, 0, new Uint32Array(4));
    gl.clearBufferfv(gl.DEPTH, 0, new Float32Array([1]));
    gl.enable(gl.DEPTH_TEST);
    gl.bindVertexArray(meshVao);
    gl.drawArrays(gl.TRIANGLES, 0, meshCount);
    gl.bindVertexArray(null);
    gl.disable(gl.DEPTH_TEST);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, null);
  }
  const CYL = SC.cylinder, BEND_R = CYL.radius, BEND_H = CYL.half_height, BEND_PHI = CYL.half_angle_deg * DEG;
  const BZ = CYL.middle, BY = CYL.axis;
  const BX = [BY[1] * BZ[2] - BY[2] * BZ[1], BY[2] * BZ[0] - BY[0] * BZ[2], BY[0] * BZ[1] - BY[1] * BZ[0]];
  const POINTS = PY_SHAPES.map((k) => SC[k].points ? decodeBlock(SC[k].points) : null);
  let lastRowD = null, lastKey = null, lastK = 1, lastCam = null, lastCamKey = null;

  function dir(polar, az) { const t = polar * DEG, p = az * DEG; return [Math.sin(t) * Math.cos(p), Math.sin(t) * Math.sin(p), Math.cos(t)]; }
  function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  function norm(a) { const l = Math.hypot(...a); return a.map((x) => x / l); }
  // as swatch.render.scene: the camera at the shape's distance, view_deg from the vertical (the plate's normal),
  // looking at the origin (Camera.look_at; straight down, the image's up points away from the azimuth's side),
  // its square window fitted to the shape's points (Camera.fitted), the canvas wider by its aspect
  function camera(st, shape) {
    const S = SC[PY_SHAPES[shape]];
    const eye = dir(st.view_deg, st.view_azimuth_deg).map((x) => x * S.distance);
    const az = st.view_azimuth_deg * DEG;
    const worldUp = Math.sin(st.view_deg * DEG) > 1e-6 ? [0, 0, 1] : [-Math.cos(az), -Math.sin(az), 0];
    const fwd = norm(eye.map((x) => -x)), right = norm(cross(fwd, worldUp)), up = cross(right, fwd);
    let cx = 0, cy = 0, half = S.window_half;
    const P = POINTS[shape];
    if (P) {
      let u0 = Infinity, u1 = -Infinity, w0 = Infinity, w1 = -Infinity;
      for (let i = 0; i < P.length; i += 3) {
        const q = [P[i] - eye[0], P[i + 1] - eye[1], P[i + 2] - eye[2]], z = dot(q, fwd);
        const u = dot(q, right) / z, w = dot(q, up) / z;
        u0 = Math.min(u0, u); u1 = Math.max(u1, u); w0 = Math.min(w0, w); w1 = Math.max(w1, w);
      }
      half = 0.5 * Math.max(u1 - u0, w1 - w0) / SC.fill; cx = 0.5 * (u0 + u1); cy = 0.5 * (w0 + w1);
    }
    return {eye, fwd, right, up, cx, cy, half};
  }
  // the point light as swatch render's: light_deg from the axis c towards w (the plate: from its normal, on
  // the far side; the sheet and the sphere: from the default camera's direction, from the upper left), turned
  // about the vertical by light_azimuth_deg
  function lightOf(st, shape) {
    const [c, w] = SC[PY_SHAPES[shape]].light_axes, t = st.light_deg * DEG, a = st.light_azimuth_deg * DEG;
    const l = c.map((x, i) => Math.cos(t) * x + Math.sin(t) * w[i]);
    return norm([l[0] * Math.cos(a) - l[1] * Math.sin(a), l[0] * Math.sin(a) + l[1] * Math.cos(a), l[2]]);
  }
  function ray(cam, u, w, aspect) {
    return norm(cam.fwd.map((f, i) => f + (cam.cx + u * aspect * cam.half) * cam.right[i] + (cam.cy + w * cam.half) * cam.up[i]));
  }
  // JS twin of the shader's geometry on a coarse grid: the exposure rule of swatch.render
  // (k = 1 / median F=1 intensity over the off-mirror pixels, D(h) < D(n)/2)
  function hit(shape, o, d) {
    if (shape === 0) {
      if (Math.abs(d[2]) < 1e-6) return null;
      const t = -o[2] / d[2]; const q = [o[0] + t * d[0], o[1] + t * d[1]];
      return (t > 0 && Math.abs(q[0]) <= 1 && Math.abs(q[1]) <= 1) ? [0, 0, 1] : null;
    }
    if (shape === 1) {  // in the sheet's frame (as the shader's edgeBend), the normal back in page coordinates
      const ol = [dot(o, BX), dot(o, BY), dot(o, BZ) - BEND_R], dl = [dot(d, BX), dot(d, BY), dot(d, BZ)];
      const oc = [ol[0], ol[2] + BEND_R], dd = [dl[0], dl[2]];
      const a = dd[0] * dd[0] + dd[1] * dd[1], b = oc[0] * dd[0] + oc[1] * dd[1], k = oc[0] * oc[0] + oc[1] * oc[1] - BEND_R * BEND_R;
      const disc = b * b - a * k; if (a < 1e-9 || disc < 0) return null;
      for (const t of [(-b - Math.sqrt(disc)) / a, (-b + Math.sqrt(disc)) / a]) {
        const q = ol.map((x, i) => x + t * dl[i]); const r = norm([q[0], 0, q[2] + BEND_R]);
        if (t > 0 && Math.abs(q[1]) <= BEND_H && Math.abs(Math.atan2(r[0], r[2])) <= BEND_PHI) {
          return [0, 1, 2].map((i) => r[0] * BX[i] + r[1] * BY[i] + r[2] * BZ[i]);
        }
      }
      return null;
    }
    const b = dot(o, d), k = dot(o, o) - 1, disc = b * b - k;
    if (disc < 0) return null;
    const t = -b - Math.sqrt(disc);
    return t > 0 ? norm(o.map((x, i) => x + t * d[i])) : null;
  }
  function exposure(st, cam, light, aspect) {
    if (st.model === "paper") return 1;
    const alpha = roughness, off = [], all = [];
    const N = 28;
    for (let yi = 0; yi < N; yi++) for (let xi = 0; xi < N; xi++) {
      const d = ray(cam, (xi + 0.5) / N * 2 - 1, (yi + 0.5) / N * 2 - 1, aspect);
      let n = hit(SHAPES.indexOf(st.shape), cam.eye, d); if (!n) continue;
      const v = d.map((x) => -x); if (dot(n, v) < 0) n = n.map((x) => -x);
      const cl = dot(n, light), cv = Math.max(dot(n, v), 0); if (cl <= 0 || cv <= 0) continue;
      const cd = Math.sqrt(Math.max((dot(light, v) + 1) / 2, 1e-12)), ch = (cl + cv) * (0.5 / cd);
      const s = ggxReflectanceFactorCos(cl, cv, ch, alpha);
      all.push(s);
      if (ggxDRatio(ch, alpha) < 0.5) off.push(s);
    }
    const pick = off.length >= Math.max(16, 0.01 * all.length) ? off : all;
    if (!pick.length) return 1;
    pick.sort((a, b) => a - b);
    const m = pick[pick.length >> 1];
    return m > 0 ? 1 / m : 1;
  }
  const SHAPES = ["plate", "bent sheet", "sphere"].concat(SC.mesh ? ["part"] : []);
  if (envData) {
    try { env = makeEnvLight(gl, envData, C); } catch (e) { env = null; console.warn("environment lighting is off: " + String(e)); }
  }
  let lastGather = null, lastGeom = null;
  // the point light's geometry target (RGBA32UI, the size of the canvas at 1 / 2^lod)
  const GEO_UNIT = 7;
  let geoTex = null, geoFbo = null, geoSize = [0, 0];
  function geoTarget(wd, h) {
    if (geoSize[0] === wd && geoSize[1] === h) return;
    if (geoTex) gl.deleteTexture(geoTex);
    if (!geoFbo) geoFbo = gl.createFramebuffer();
    gl.activeTexture(gl.TEXTURE0 + GEO_UNIT);
    geoTex = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, geoTex);
    for (const [k, v] of [[gl.TEXTURE_MIN_FILTER, gl.NEAREST], [gl.TEXTURE_MAG_FILTER, gl.NEAREST],
      [gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE], [gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE]]) gl.texParameteri(gl.TEXTURE_2D, k, v);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32UI, wd, h, 0, gl.RGBA_INTEGER, gl.UNSIGNED_INT, null);
    gl.bindFramebuffer(gl.FRAMEBUFFER, geoFbo);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, geoTex, 0);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.activeTexture(gl.TEXTURE0);
    geoSize = [wd, h];
  }
  const ALB_UNIT = 6, albTex = gl.createTexture();  // the fill's directional albedo per view bin
  gl.activeTexture(gl.TEXTURE0 + ALB_UNIT);
  gl.bindTexture(gl.TEXTURE_2D, albTex);
  for (const [k, v] of [[gl.TEXTURE_MIN_FILTER, gl.NEAREST], [gl.TEXTURE_MAG_FILTER, gl.NEAREST],
    [gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE], [gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE]]) gl.texParameteri(gl.TEXTURE_2D, k, v);
  if (env) gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, 1, env.bins);
  gl.activeTexture(gl.TEXTURE0);
  function setCamera(U, cam, aspect) {
    gl.uniform3fv(U.eye, cam.eye); gl.uniform3fv(U.fwd, cam.fwd); gl.uniform3fv(U.right, cam.right);
    gl.uniform3fv(U.up, cam.up);
    gl.uniform1f(U.tanHalf, cam.half); gl.uniform2f(U.win, cam.cx, cam.cy); gl.uniform1f(U.aspect, aspect);
    gl.uniform1f(U.bendR, BEND_R); gl.uniform1f(U.bendPhi, BEND_PHI); gl.uniform1f(U.bendH, BEND_H);
    gl.uniform3fv(U.bendX, BX); gl.uniform3fv(U.bendY, BY); gl.uniform3fv(U.bendZ, BZ);
  }
  // under an environment: the gather pass when the geometry or the lighting changed (at half the
  // resolution while the view is dragged: a quarter of the work), then the shade pass
  function drawEnvironment(st, cam, shape, w, h) {
    const lod = st.coarse ? 1 : 0;
    const key = [shape, st.view_deg, st.view_azimuth_deg, st.lighting, w, h, lod].join();
    if (key !== lastGather) {
      // in the studio set, each sample's direction corrected for where the surface point is (the set is near)
      const inSet = st.lighting === "studio" && env.hasSet;
      const g = program(inSet ? "gatherset" : "gather", shape, 0);
      gl.useProgram(g.prog);
      setCamera(g.U, cam, w / h);
      if (inSet) {
        env.setStudio(g.U, PY_SHAPES[shape], true, true);
        // the boxes' edges over twice a sample's blur level on a polished lobe, wider on a rough one (where the
        // renderer's fixed samples would show the edges as blotches): 2 + 8 alpha
        gl.uniform1f(g.U.boxSoft, 2 + 8 * roughness);
      }
      env.gather(env.mapName(st.lighting, PY_SHAPES[shape]), g.U, w, h, lod, (gw, gh) => drawShape(shape, gw, gh));
      if (inSet) {  // the set behind the object, along each pixel's ray
        const bp = program("backdrop", 0, 0);
        gl.useProgram(bp.prog);
        setCamera(bp.U, cam, w / h);
        env.setStudio(bp.U, PY_SHAPES[shape], true, true);
        env.backdropPass(w, h, lod);
      }
      lastGather = key;
    }
    env.setThickness(st.thickness_nm);
    const {prog, U} = program("shade", 0, 0);
    gl.useProgram(prog);
    env.setStudio(U, PY_SHAPES[shape], st.lighting === "studio", false);
    gl.uniform1i(U.lod, lod);
    gl.viewport(0, 0, w, h);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    return 1;  // exposure 1: the white diffuser under the same environment is display white
  }
  function draw(st) {
    useFinish(st.finish);
    const w = canvas.width, h = canvas.height;
    const shape = Math.max(0, SHAPES.indexOf(st.shape));
    const ckey = [shape, st.view_deg, st.view_azimuth_deg].join();
    if (ckey !== lastCamKey) { lastCam = camera(st, shape); lastCamKey = ckey; }
    const cam = lastCam;
    if (env && st.lighting !== "point" && env.names.includes(st.lighting)) return drawEnvironment(st, cam, shape, w, h);
    gl.viewport(0, 0, w, h);
    if (lastRowD !== st.thickness_nm) {
      const row = C.rowLinearSrgb(st.thickness_nm);
      gl.activeTexture(gl.TEXTURE0);
      gl.bindTexture(gl.TEXTURE_2D, tex);
      gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, C.cosNodes, 1, gl.RGBA, gl.FLOAT, row);  // (storage made once)
      if (env) {
        gl.activeTexture(gl.TEXTURE0 + ALB_UNIT);
        gl.bindTexture(gl.TEXTURE_2D, albTex);
        gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, 1, env.bins, gl.RGBA, gl.FLOAT, env.albedo(row));
        gl.activeTexture(gl.TEXTURE0);
      }
      lastRowD = st.thickness_nm;
    }
    const light = lightOf(st, shape);
    const aspect = w / h;
    // the exposure depends on the geometry only (as in swatch.render): cached across thicknesses
    const key = [st.shape, st.model, st.view_deg, st.view_azimuth_deg, st.light_deg, st.light_azimuth_deg, aspect].join();
    if (key !== lastKey) { lastK = exposure(st, cam, light, aspect); lastKey = key; }
    const k = lastK;
    // the geometry pass when the geometry changed (at half the resolution while the view is dragged)
    const lod = st.coarse ? 1 : 0, gw = Math.max(1, w >> lod), gh = Math.max(1, h >> lod);
    const gkey = key + "," + [w, h, lod].join();
    if (gkey !== lastGeom) {
      const g = program("pgeom", shape, st.model === "paper" ? 1 : 0);
      gl.useProgram(g.prog);
      setCamera(g.U, cam, aspect);
      gl.uniform3fv(g.U.light, light);
      gl.uniform1f(g.U.alpha, roughness);
      geoTarget(gw, gh);
      gl.bindFramebuffer(gl.FRAMEBUFFER, geoFbo);
      gl.viewport(0, 0, gw, gh);
      drawShape(shape, gw, gh);
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
      lastGeom = gkey;
    }
    const {prog, U} = program("pshade", 0, 0);
    gl.useProgram(prog);
    gl.activeTexture(gl.TEXTURE0 + GEO_UNIT);
    gl.bindTexture(gl.TEXTURE_2D, geoTex);
    gl.activeTexture(gl.TEXTURE0);
    gl.uniform1i(U.lod, lod);
    gl.uniform1f(U.exposure, k);
    gl.uniform1f(U.fill, st.model === "paper" ? 0 : Math.max(0, Number(st.fill) || 0));
    gl.viewport(0, 0, w, h);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    return k;
  }
  // the displayed sRGB (0-255) at a canvas pixel (x right, y down from the top-left corner)
  function pixel(x, y) {
    const p = new Uint8Array(4);
    gl.readPixels(Math.floor(x), canvas.height - 1 - Math.floor(y), 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, p);
    return [p[0], p[1], p[2]];
  }
  return {draw, pixel, gl, SHAPES, lightings: ["point"].concat(env ? env.names : [])};
}
