// Find by colour (match) and the process window of the page (swatch/catalog/web/colour.js) under node --test,
// against what the Python side computes on the same colour table (issue 17 item 6): the fixture
// tests/catalog/test_page_js.py writes and names in SWATCH_JS_FIXTURE holds a small catalog's explorer table
// (swatch.catalog.explorer.explorer_data), the candidates of swatch.fit.matching.match_colour for a few targets
// (L*a*b* in the catalog's observer; hex brought into it, as swatch match --hex) with the flags of
// judge_candidates, and swatch.catalog.records.process_window in each tolerance's own metric (ΔE*ab or ΔE2000).
import {test} from "node:test";
import assert from "node:assert/strict";
import {readFileSync} from "node:fs";
import vm from "node:vm";

const here = new URL(".", import.meta.url);
const ctx = {atob};  // colour.js is a classic script: its top-level functions become this context's globals
vm.runInNewContext(readFileSync(new URL("../../swatch/catalog/web/colour.js", here), "utf8"), ctx);
const skip = !process.env.SWATCH_JS_FIXTURE;
const fx = skip ? null : JSON.parse(readFileSync(process.env.SWATCH_JS_FIXTURE, "utf8"));
const C = skip ? null : ctx.makeColour(fx.table);
const near = (got, want, tol, what) => assert.ok(Math.abs(got - want) <= tol, `${what}: ${got} against ${want} (±${tol})`);

test("match gives the candidates of swatch match over the catalog's range, Lab and hex targets", {skip}, () => {
  assert.equal(fx.match.length, 6);
  for (const m of fx.match) {
    const got = C.match(m.target, 5), what = JSON.stringify(m.target);
    assert.equal(got.length, m.candidates.length, what);
    got[0].target_Lab.forEach((v, k) => near(v, m.target_Lab[k], 1e-6, what + " target L*a*b*"));
    got.forEach((g, i) => {
      const c = m.candidates[i];
      // within one search step (0.1 nm): the page samples a uint16 table, Python the spectra
      near(g.thickness_nm, c.thickness_nm, 0.1, `${what} #${i} thickness`);
      near(g.voltage_V, c.voltage_V, 0.1 / fx.table.nm_per_V, `${what} #${i} voltage`);
      // 0.02, or 0.05 % of a far candidate's ΔE (the uint16 table: #00ff00 is 65 ΔE00 from every film colour)
      near(g.delta_E_00, c.delta_E_00, Math.max(0.02, 5e-4 * c.delta_E_00), `${what} #${i} dE00`);
      // ΔE*ab is not the minimised metric: within the 0.1 nm step it moves 0.1 % of a far candidate's 180
      near(g.delta_E_ab, c.delta_E_ab, Math.max(0.05, 1e-3 * c.delta_E_ab), `${what} #${i} dEab`);
    });
  }
});

test("a target outside what the film shows still gets candidates, none within any tolerance", {skip}, () => {
  for (const target of [{hex: "#00ff00"}, {Lab: [50, -90, 60]}]) {
    const m = fx.match.find((x) => JSON.stringify(x.target) === JSON.stringify(target));
    const got = C.match(target, 5);
    assert.ok(got.length >= 1 && got[0].delta_E_00 > 10, JSON.stringify(got[0]));
    for (const flags of Object.values(m.within)) assert.deepEqual(flags, flags.map(() => false));
    for (const [metric, bound] of [["dEab", 4], ["dE00", 2]]) assert.ok(got.every((h) => !ctx.withinTolerance(h, metric, bound)));
  }
});

test("a candidate is within tolerance as judge_candidates says, in the tolerance's own metric", {skip}, () => {
  let judged = 0, differ = 0;
  for (const m of fx.match) {
    const got = C.match(m.target, 5);
    for (const [key, flags] of Object.entries(m.within)) {
      const [metric, b] = key.split("<="), bound = Number(b);
      got.forEach((h, i) => {
        const dE = metric === "dEab" ? h.delta_E_ab : h.delta_E_00;
        if (Math.abs(dE - bound) < 0.05) return;  // on the bound the two samplings may fall either side
        assert.equal(ctx.withinTolerance(h, metric, bound), flags[i], `${JSON.stringify(m.target)} #${i} ${key}: ${dE}`);
        judged++;
      });
    }
    // the same bound in the two metrics says different things of some candidate: the metric is honoured
    got.forEach((h) => { if (ctx.withinTolerance(h, "dEab", 2) !== ctx.withinTolerance(h, "dE00", 2)) differ++; });
  }
  assert.ok(judged >= 60, String(judged));
  assert.ok(differ >= 1, "no candidate where ΔE*ab ≤ 2 and ΔE00 ≤ 2 disagree");
  assert.throws(() => ctx.withinTolerance({delta_E_ab: 1, delta_E_00: 1}, "dE94", 2), /metric must be dEab or dE00/);
});

test("the process window is swatch.catalog.records.process_window, judged in its own metric", {skip}, () => {
  const [lo, hi] = fx.range_nm;
  let compared = 0, ends = 0;
  for (const w of fx.window) {
    w.thickness_nm.forEach((d, i) => {
      const got = C.windowAt(d, w.bound, w.search_nm, w.metric), what = `${w.metric} <= ${w.bound} at ${d} nm`;
      for (const [side, room] of [["minus", d - lo], ["plus", hi - d]]) {
        if (w[side + "_nm"][i] <= room - 0.1) {
          near(got[side].nm, w[side + "_nm"][i], 0.01, `${what} ${side}`);
          assert.equal(got[side].capped, w[side + "_capped"][i], `${what} ${side} capped`);
        } else {  // the page's table ends at the catalog's range: its window stops there, and says so
          assert.ok(got[side].capped, `${what} ${side} capped at the range`);
          near(got[side].nm, room, 0.1 + 1e-9, `${what} ${side} at the range's end`);
          ends++;
        }
      }
      compared++;
    });
  }
  assert.equal(compared, 28);
  assert.ok(ends >= 4, String(ends));
  // the same bound in ΔE*ab and in ΔE2000 gives windows far apart (Python's and the page's alike)
  const ab = fx.window.find((w) => w.metric === "dEab" && w.bound === 2), e00 = fx.window.find((w) => w.metric === "dE00" && w.bound === 2);
  ab.thickness_nm.forEach((d, i) => {
    if (d - lo < 3 || hi - d < 3) return;
    const gap = Math.abs(ab.plus_nm[i] - e00.plus_nm[i]) + Math.abs(ab.minus_nm[i] - e00.minus_nm[i]);
    assert.ok(gap > 0.3, `at ${d} nm the dEab and dE00 windows differ by only ${gap} nm`);
    const a = C.windowAt(d, 2, ab.search_nm, "dEab"), b = C.windowAt(d, 2, ab.search_nm, "dE00");
    assert.ok(Math.abs(a.plus.nm - b.plus.nm) + Math.abs(a.minus.nm - b.minus.nm) > 0.3, String(d));
  });
});

test("match refuses a bad target or count with a message saying what is allowed", {skip}, () => {
  assert.throws(() => C.match({Lab: [120, 0, 0]}), /L in \[0, 100\]/);
  assert.throws(() => C.match({Lab: [50, 0]}), /three numbers/);
  assert.throws(() => C.match({hex: "#12345"}), /six hex digits/);
  assert.throws(() => C.match({}), /give \{Lab/);
  assert.throws(() => C.match({Lab: [50, 0, 0]}, 0), /n must be from 1 to 100/);
  assert.equal(C.match({Lab: [50, 0, 0]}, 1).length, 1);
});
