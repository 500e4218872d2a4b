// Axes of the report pages' SVG charts (docs/report.md): round tick values and their labelled
// ticks, shared by web/report.js and web/experiment_report.js (inlined before them).
window.canopyAxes = (function () {
  'use strict';
  // Round tick values from 0 to at least `max`, about `count` of them: steps of 1, 2, 2.5 or 5
  // times a power of ten. The last tick is the axis' top.
  function ticks(max, count) {
    const span = Math.max(1e-9, max);
    const raw = span / Math.max(1, count || 4);
    const p = Math.pow(10, Math.floor(Math.log10(raw)));
    const step = [1, 2, 2.5, 5, 10].map((m) => m * p).find((s) => s >= raw - 1e-12);
    const out = [];
    for (let i = 0; i * step < span + step - 1e-9; ++i) out.push(+(i * step).toPrecision(6));
    return out;
  }
  // Text of a tick value: no more digits than its step needs.
  function label(v, step) {
    let d = 0;
    while (d < 4 && Math.abs(Math.round(step * Math.pow(10, d)) - step * Math.pow(10, d)) > 1e-6) ++d;
    return Math.abs(v) >= 1e4 ? v.toExponential(1) : v.toFixed(d);
  }
  // Whole-number view ticks from 1 to n: 1, then round steps.
  function viewTicks(n) {
    if (n <= 1) return [1];
    const t = ticks(n, 5).filter((v) => v >= 1 && v <= n && v === Math.round(v));
    if (t[0] !== 1) t.unshift(1);
    return t;
  }
  // SVG of a chart's axes: the frame, y ticks left of `L`, view ticks under the plot and the
  // x axis' title. `x(i)` places view i (0-based), `y(v)` a value; `yTicks` from ticks().
  function svg(o) {
    const { L, R, T, B, W, H, x, y, yTicks, n, xTitle } = o;
    const step = yTicks.length > 1 ? yTicks[1] - yTicks[0] : 1;
    let s = '<line x1="' + L + '" y1="' + (H - B) + '" x2="' + (W - R) + '" y2="' + (H - B) + '" stroke="#999"/>' +
      '<line x1="' + L + '" y1="' + T + '" x2="' + L + '" y2="' + (H - B) + '" stroke="#999"/>';
    for (const v of yTicks) {
      const yy = y(v).toFixed(1);
      s += '<line x1="' + (L - 3) + '" y1="' + yy + '" x2="' + L + '" y2="' + yy + '" stroke="#999"/>' +
        (v > 0 ? '<line x1="' + L + '" y1="' + yy + '" x2="' + (W - R) + '" y2="' + yy + '" stroke="#eee"/>' : '') +
        '<text class="tick-y" x="' + (L - 5) + '" y="' + (+yy + 3.5).toFixed(1) + '" text-anchor="end">' + label(v, step) + '</text>';
    }
    for (const v of viewTicks(n)) {
      const xx = x(v - 1).toFixed(1);
      s += '<line x1="' + xx + '" y1="' + (H - B) + '" x2="' + xx + '" y2="' + (H - B + 3) + '" stroke="#999"/>' +
        '<text class="tick-x" x="' + xx + '" y="' + (H - B + 13) + '" text-anchor="middle">' + v + '</text>';
    }
    s += '<text class="axis-title" x="' + (W - R) + '" y="' + (H - 2) + '" text-anchor="end">' + (xTitle || 'successful view') + '</text>';
    return s;
  }
  return { ticks, label, viewTicks, svg };
})();
