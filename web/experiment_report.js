// canopy's experiment report (docs/report.md): the findings, every table of `canopy report`,
// each trial's SC and entropy curves (hover: method, P_gt, world, value) with their means,
// and each trial linked to its own report.html. Reads the JSON block #canopy-data written by
// jobs/experiment_page.cpp; needs no network. Test hook: window.canopyReport.
(function () {
  'use strict';
  const data = JSON.parse(document.getElementById('canopy-data').textContent);
  const app = document.getElementById('app');
  document.body.classList.add('exp-page');  // a long page, not a full-window view
  const esc = (s) => String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]));
  const palette = ['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd', '#8c564b', '#e377c2', '#7f7f7f', '#bcbd22', '#17becf'];
  const trials = data.trials || [];
  const groups = [];  // one per method label and P_gt
  const groupOf = {};
  for (const t of trials) {
    const key = t.label + ' P_gt ' + t.p_gt;
    if (!(key in groupOf)) { groupOf[key] = groups.length; groups.push({ key, label: t.label, p_gt: t.p_gt, trials: [] }); }
    groups[groupOf[key]].trials.push(t);
  }

  // The findings as HTML, from their blocks (ExperimentReport::findings: heading, paragraph, table, list).
  function findings(blocks) {
    return blocks.map((b) => {
      if (b.kind === 'heading') { const n = Math.min(6, b.level + 2); return '<h' + n + '>' + esc(b.text) + '</h' + n + '>'; }
      if (b.kind === 'paragraph') return '<p>' + (b.strong ? '<b>' + esc(b.text) + '</b>' : esc(b.text)) + '</p>';
      if (b.kind === 'table') {
        return '<table><tr>' + b.header.map((c) => '<th>' + esc(c) + '</th>').join('') + '</tr>' +
          b.rows.map((r) => '<tr>' + r.map((c) => '<td>' + esc(c) + '</td>').join('') + '</tr>').join('') + '</table>';
      }
      if (b.kind === 'list') return '<ul>' + b.items.map((i) => '<li>' + esc(i) + '</li>').join('') + '</ul>';
      return '';
    }).join('\n');
  }

  let html = '<header><h1>canopy experiment report</h1><span class="sub">' + esc((data.names || []).join(', ')) + ' · ' +
    trials.length + ' trials</span></header><div class="exp">';
  if ((data.missing || []).length) html += '<div class="banner">Missing trials: ' + esc(data.missing.join(', ')) + '</div>';
  if ((data.incomplete || []).length) html += '<div class="note">Ignored folders: ' + data.incomplete.map((f) => esc(f.path) + ' (' + esc(f.reason) + ')').join('; ') + '</div>';
  html += '<h2>Curves (hover a line; thick: mean of the trials)</h2><div id="legend-exp"></div>' +
    '<svg id="exp-sc" class="curve" width="720" height="260"></svg><div id="exp-tip" class="note">&nbsp;</div>' +
    '<svg id="exp-h" class="curve" width="720" height="260"></svg>';
  html += '<h2>Findings</h2><div class="findings" id="findings">' + findings(data.findings || []) + '</div>';
  html += '<h2>Trials</h2><div class="table-wrap"><table id="trials"><tr><th>trial</th><th>method</th><th>P_gt</th><th>world</th><th>seed</th>' +
    '<th>status</th><th>views</th><th>final SC</th><th>report</th></tr>' +
    trials.map((t) => '<tr><td>' + esc(t.id) + '</td><td>' + esc(t.label) + '</td><td>' + t.p_gt + '</td><td>' + esc(t.world) + '</td><td>' + t.seed +
      '</td><td>' + esc(t.status) + (t.message ? ': ' + esc(t.message) : '') + '</td><td>' + t.views_ok + '</td><td>' +
      (t.sc.length ? t.sc[t.sc.length - 1].toFixed(3) : '–') + '</td><td>' +
      (t.link ? '<a class="trial-link" href="' + esc(t.link) + '">report</a>' : '–') + '</td></tr>').join('') + '</table></div>';
  for (const t of data.tables || []) {
    html += '<h2>' + esc(t.name) + '</h2><div class="table-wrap"><table class="csv"><tr>' + t.header.map((h) => '<th>' + esc(h) + '</th>').join('') + '</tr>' +
      t.rows.map((r) => '<tr>' + r.map((c) => '<td>' + esc(c) + '</td>').join('') + '</tr>').join('') + '</table></div>';
  }
  html += '</div>';
  app.innerHTML = html;
  document.getElementById('legend-exp').innerHTML = groups.map((g, i) =>
    '<span class="sw" style="display:inline-block;width:10px;height:10px;margin:0 4px 0 10px;background:' + palette[i % palette.length] + '"></span>' + esc(g.key)).join('');

  function plot(id, field, title) {
    const svg = document.getElementById(id);
    const W = 720, H = 260, L = 44, R = 10, T = 16, B = 24;
    let n = 1, top = 1e-9;
    for (const t of trials) { n = Math.max(n, t[field].length); for (const v of t[field]) top = Math.max(top, v); }
    if (field === 'sc') top = 1;
    const x = (i) => L + (n > 1 ? (i / (n - 1)) * (W - L - R) : 0), y = (v) => T + (1 - v / top) * (H - T - B);
    const path = (vals) => vals.map((v, i) => (i ? 'L' : 'M') + x(i).toFixed(1) + ',' + y(v).toFixed(1)).join('');
    let s = '<text x="' + L + '" y="11">' + esc(title) + '</text>' +
      '<line x1="' + L + '" y1="' + (H - B) + '" x2="' + (W - R) + '" y2="' + (H - B) + '" stroke="#999"/>' +
      '<line x1="' + L + '" y1="' + T + '" x2="' + L + '" y2="' + (H - B) + '" stroke="#999"/>' +
      '<text x="2" y="' + (T + 4) + '">' + top.toFixed(2) + '</text><text x="2" y="' + (H - B) + '">0</text>' +
      '<text x="' + (W - R - 60) + '" y="' + (H - 6) + '">view ' + n + '</text>';
    groups.forEach((g, gi) => {
      const colour = palette[gi % palette.length];
      g.trials.forEach((t) => {
        s += '<path class="trial-line" data-trial="' + esc(t.id) + '" d="' + path(t[field]) + '" fill="none" stroke="' + colour + '" stroke-opacity="0.35" stroke-width="1"/>';
      });
      const mean = [];
      for (let i = 0; i < n; ++i) {
        const vals = g.trials.filter((t) => i < t[field].length).map((t) => t[field][i]);
        if (vals.length) mean.push(vals.reduce((a, b) => a + b, 0) / vals.length);
      }
      s += '<path d="' + path(mean) + '" fill="none" stroke="' + colour + '" stroke-width="2.5" pointer-events="none"/>';
    });
    s += '<circle class="hover-dot" r="3" fill="#000" visibility="hidden"/>';
    svg.innerHTML = s;
    const tip = document.getElementById('exp-tip'), dot = svg.querySelector('.hover-dot');
    svg.addEventListener('mousemove', (ev) => {
      const r = svg.getBoundingClientRect(), mx = ev.clientX - r.left, my = ev.clientY - r.top;
      const i = Math.round(((mx - L) / (W - L - R)) * (n - 1));
      let best = null, bd = 12;
      for (const t of trials) {
        if (i < 0 || i >= t[field].length) continue;
        const d = Math.abs(y(t[field][i]) - my);
        if (d < bd) { bd = d; best = t; }
      }
      if (!best) { dot.setAttribute('visibility', 'hidden'); return; }
      dot.setAttribute('cx', x(i)); dot.setAttribute('cy', y(best[field][i])); dot.setAttribute('visibility', 'visible');
      tip.textContent = best.label + ', P_gt ' + best.p_gt + ', ' + best.world + ', seed ' + best.seed + ': view ' + (i + 1) + ', ' +
        (field === 'sc' ? 'SC ' : 'entropy ') + best[field][i];
    });
  }
  plot('exp-sc', 'sc', 'fruit surface coverage (SC) after each successful view');
  plot('exp-h', 'entropy', 'fruit entropy [nats] after each successful view');
  window.canopyReport = { ready: true, trials: trials.length, links: trials.filter((t) => t.link).map((t) => t.link) };
  document.body.dataset.ready = '1';
})();
