// canopy's run report (docs/report.md): the map replayed view by view in three.js, the
// camera of every attempted view, the true fruits by coverage, the robot at the view shown, axes
// and a scale, the curves, the thumbnails, a table of the true fruits and the metrics.
// Reads the JSON block #canopy-data written by jobs/run_report.cpp; needs no network; the
// charts' axes from web/report_axes.js. Test hook: window.canopyReport (ready, setView, state).
(function () {
  'use strict';
  const marks = { start: performance.now() };  // ms from navigation start (docs/report.md#bounds)
  const data = JSON.parse(document.getElementById('canopy-data').textContent);
  const wall = JSON.parse(document.getElementById('canopy-wall').textContent);
  const app = document.getElementById('app');
  const el = (tag, attrs, html) => {
    const e = document.createElement(tag);
    for (const k in attrs || {}) e.setAttribute(k, attrs[k]);
    if (html !== undefined) e.innerHTML = html;
    return e;
  };
  const esc = (s) => String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]));
  const fmt = (x, d) => (typeof x === 'number' ? x.toFixed(d === undefined ? 3 : d) : x === null || x === undefined ? '–' : esc(x));

  // ---- Decoding the replay ------------------------------------------------------------
  function bytes(b64) {
    const s = atob(b64 || '');
    const out = new Uint8Array(s.length);
    for (let i = 0; i < s.length; ++i) out[i] = s.charCodeAt(i);
    return out;
  }
  const map = data.map || { counts: [], keys_b64: '', changes_b64: '', step: 1, resolution_m: 0.015 };
  const keyBytes = bytes(map.keys_b64), changeBytes = bytes(map.changes_b64);
  const nVox = keyBytes.length / 6;
  const res = map.resolution_m || data.resolution_m || 0.015;
  const origin = map.key_origin || 32768;
  const pos = new Float32Array(nVox * 3);
  {
    const dv = new DataView(keyBytes.buffer);
    for (let i = 0; i < nVox; ++i)
      for (let a = 0; a < 3; ++a) pos[3 * i + a] = (dv.getUint16(6 * i + 2 * a, true) - origin + 0.5) * res;
  }
  const nChanges = changeBytes.length / 6;
  const chVox = new Uint32Array(nChanges), chState = new Uint16Array(nChanges);
  {
    const dv = new DataView(changeBytes.buffer);
    for (let i = 0; i < nChanges; ++i) {
      chVox[i] = dv.getUint32(6 * i, true);
      chState[i] = dv.getUint16(6 * i + 4, true);
    }
  }
  const groupEnd = [];  // changes of map state g end here
  {
    let n = 0;
    for (const c of map.counts) groupEnd.push((n += c));
  }

  // ---- Views: successful index k, attempts up to it --------------------------------------
  // data.views holds each field of the views' schema (records::ViewRecord::visit) by its name,
  // one value per attempted view; here one object per view with the same names.
  const viewColumns = data.views || {};
  const views = [];
  for (const name of Object.keys(viewColumns))
    viewColumns[name].forEach((value, i) => { (views[i] = views[i] || {})[name] = value; });
  const okViews = views.filter((v) => v.success);
  okViews.forEach((v, k) => { v.k = k; });
  // The vocabularies (records::vocabulary_json): phase colours and legend words.
  const vocabulary = data.vocabulary || {};
  const phaseStyle = {};
  for (const p of vocabulary.view_phases || []) phaseStyle[p.name] = p;
  const hexColour = (c) => parseInt(String(c || '#1f77b4').slice(1), 16);
  const nK = okViews.length;
  const nStops = (data.stops || []).length;
  const stopsOf = nStops ? ' of ' + nStops : '';  // stops and attempts counted from 1, as the log does
  const attemptsUpTo = [];  // attempts shown at view k: up to and including its own
  views.forEach((v, i) => { if (v.success) attemptsUpTo.push(i + 1); });

  // ---- Page ---------------------------------------------------------------------------
  const s = data.summary || {};
  const method = s.method || {};
  app.innerHTML = '';
  const head = el('header');
  head.appendChild(el('h1', {}, 'canopy ' + esc(data.kind) + ' report'));
  head.appendChild(el('span', { class: 'sub' }, esc(method.name || '') + (method.gain ? ' (' + esc(method.gain) + ', rays ' + esc(method.rays) + ')' : '') +
    ' · world ' + esc((s.world || {}).name || '') + ' · seed ' + esc(s.seed === undefined ? '–' : s.seed) + ' · P_gt ' + esc(s.p_gt)));
  app.appendChild(head);
  if (!data.complete) {
    app.appendChild(el('div', { class: 'banner', id: 'incomplete' },
      'Incomplete run: ' + esc(data.end_reason) + ' after ' + nK + ' successful views; what it did before is shown.'));
  }
  if (map.note) app.appendChild(el('div', { class: 'note', id: 'decimated' }, 'Map decimated: ' + esc(map.note)));
  const thumbs = data.thumbs || {};
  if (thumbs.step > 1) app.appendChild(el('div', { class: 'note' }, 'Thumbnails of every ' + thumbs.step + 'th view.'));
  const main = el('main');
  const view3d = el('div', { id: 'view3d' });
  const tip = el('div', { id: 'tip' });
  const legend = el('div', { id: 'legend' });
  view3d.appendChild(tip);
  view3d.appendChild(legend);
  const side = el('div', { id: 'side' });
  main.appendChild(view3d);
  main.appendChild(side);
  app.appendChild(main);

  side.innerHTML =
    '<div class="controls"><button id="play">▶ play</button>' +
    '<input id="slider" type="range" min="0" max="' + Math.max(0, nK - 1) + '" value="' + Math.max(0, nK - 1) + '">' +
    '<span id="view-count"></span></div>' +
    '<div class="controls">colour <select id="colour"><option value="class">class</option>' +
    '<option value="occupancy">occupancy</option><option value="entropy">entropy</option></select>' +
    '<label><input id="show-frusta" type="checkbox" checked> cameras</label>' +
    '<label><input id="show-fruits" type="checkbox" checked> true fruits</label>' +
    (data.robot ? '<label><input id="show-robot" type="checkbox" checked> robot</label>' : '') + '</div>' +
    '<div id="view-info"></div>' +
    '<div class="thumbs"><figure><div id="thumb-rgb" class="thumb"></div><figcaption>wrist RGB</figcaption></figure>' +
    '<figure><div id="thumb-labels" class="thumb"></div><figcaption>true labels</figcaption></figure>' +
    '<figure id="fig-mapped"><div id="thumb-mapped" class="thumb"></div><figcaption>labels mapped' +
    (s.p_gt !== undefined && s.p_gt < 1 ? ' (after noise, P_gt ' + fmt(s.p_gt, 2) + ')' : '') + '</figcaption></figure></div>' +
    '<h2>Fruit surface coverage (SC)</h2><svg id="curve-sc" class="curve" width="396" height="130"></svg>' +
    '<h2>Fruit entropy [nats]</h2><svg id="curve-h" class="curve" width="396" height="130"></svg>' +
    '<div id="summary"></div><div id="fruits"></div>';

  // ---- Summary --------------------------------------------------------------------------
  (function summary() {
    const rows = [];
    const add = (k, v) => rows.push('<tr><th>' + esc(k) + '</th><td>' + v + '</td></tr>');
    add('method', esc(method.name || '') + (method.reads_ground_truth ? ' (reads the ground truth)' : ''));
    add('labels, P_gt', esc(s.labels || '') + ', ' + fmt(s.p_gt, 2));
    const w = s.world || {};
    add('world', esc(w.name || '') + (w.file ? ' (' + esc(w.file) + ')' : '') + ', ' + esc(w.plants) + ' plants, ' + esc(w.fruits) + ' fruits');
    add('views', esc(s.views_successful) + ' successful of ' + esc(s.views_attempted) + ' attempted');
    if (s.simulated_time_s !== undefined) add('simulated time', fmt(s.simulated_time_s, 1) + ' s');
    if (wall.wall_time_s !== undefined) add('wall time', fmt(wall.wall_time_s, 2) + ' s');
    if (wall.ms_per_insertion !== undefined) add('insertion', fmt(wall.ms_per_insertion, 1) + ' ms per view');
    add('end', esc(data.end_reason || ''));
    let html = '<h2>Summary</h2><table id="summary-table">' + rows.join('') + '</table>';
    // The final metrics, each a labelled number (a row data-metric="key", its value alone in the cell).
    const f = s.final || {}, det = f.detection || {}, vp = f.fruit_voxel_precision || {};
    const metrics = [
      ['fruit_coverage', 'fruit surface coverage (SC)', f.fruit_coverage, 3, ''],
      ['fruit_entropy', 'fruit entropy', f.fruit_entropy, 1, 'nats'],
      ['fruits_sc50', 'share of fruits with SC ≥ 0.5', f.fruits_sc50, 3, ''],
      ['fruits_sc80', 'share of fruits with SC ≥ 0.8', f.fruits_sc80, 3, ''],
      ['detection_precision', 'detection precision (fruit clusters on a true fruit)', det.precision, 3, ''],
      ['detection_recall', 'detection recall (true fruits found)', det.recall, 3, ''],
      ['detection_f1', 'detection F1', det.f1, 3, ''],
      ['fruits_matched', 'true fruits matched by a cluster', det.matched, 0, det.fruits !== undefined ? 'of ' + det.fruits : ''],
      ['fruit_clusters', 'fruit clusters in the map', det.clusters, 0, ''],
      ['centre_error', 'mean centre error of the matched fruits', typeof det.centre_error_m === 'number' ? det.centre_error_m * 1000 : undefined, 1, 'mm'],
      ['voxel_volume_error', 'mean voxel volume error (relative)', det.voxel_volume_error, 3, ''],
      ['ellipsoid_volume_error', 'mean ellipsoid volume error (relative)', det.ellipsoid_volume_error, 3, ''],
      ['fruit_voxel_precision', 'fruit voxel precision (' + esc(vp.rule || 'headline') + ' rule)', vp.precision, 3, ''],
      ['false_fruit_voxels', 'fruit voxels off every true fruit', vp.false_voxels, 0, vp.true_voxels !== undefined ? 'of ' + (vp.true_voxels + vp.false_voxels) : ''],
    ].filter((m) => typeof m[2] === 'number');
    html += '<h2>Final metrics</h2><table id="metrics">' + metrics.map(([key, label, v, d, unit]) =>
      '<tr data-metric="' + key + '"><th>' + label + '</th><td class="num">' + v.toFixed(d) + '</td><td>' + unit + '</td></tr>').join('') + '</table>';
    const fails = Object.entries(s.failures || {});
    html += '<h2>Failures by cause</h2>' + (fails.length
      ? '<table id="failures"><tr><th>cause</th><th>attempts</th></tr>' + fails.map(([k, n]) => '<tr><td>' + esc(k) + '</td><td>' + n + '</td></tr>').join('') + '</table>'
      : '<p>none</p>');
    const changed = s.settings_changed || [];
    html += '<h2>Settings that differ from the defaults</h2>' + (changed.length
      ? '<table id="settings"><tr><th>key</th><th>value</th><th>default</th></tr>' + changed.map((c) => '<tr><td>' + esc(c.key) + '</td><td>' + esc(c.value) + '</td><td>' + esc(c.default) + '</td></tr>').join('') + '</table>'
      : '<p>none</p>');
    if (wall.phases_s) {
      html += '<h2>Wall time by phase [s]</h2><table id="phases">' + Object.entries(wall.phases_s).map(([k, v]) => '<tr><td>' + esc(k) + '</td><td>' + fmt(v, 2) + '</td></tr>').join('') + '</table>';
      const sum = Object.values(wall.phases_s).reduce((a, b) => a + b, 0);
      if (wall.wall_time_s !== undefined && sum > wall.wall_time_s * 1.01)
        html += '<p id="phase-note">The phases add up to ' + fmt(sum, 1) + ' s against ' + fmt(wall.wall_time_s, 1) + ' s of wall time: ' +
          'the mission runs on two threads, and each scan\'s insertion, index and metrics (mapping, evaluation) run on the second ' +
          'beside the next move, so their times overlap the others\'.</p>';
    }
    document.getElementById('summary').innerHTML = html;
  })();

  // ---- The true fruits: one row each (tr data-fruit="ID"), sorted by a click on a heading ---
  const fruitTable = (function fruitTable() {
    const fruits = data.fruits || [];
    const pct = (x) => (typeof x === 'number' ? (100 * x).toFixed(0) + ' %' : '–');
    const columns = [
      ['id', 'fruit', (f) => f.id, (f) => esc(f.id)],
      ['plant', 'plant', (f) => f.plant, (f) => esc(f.plant)],
      ['cov', 'SC', (f) => f.cov, (f) => fmt(f.cov)],
      ['views', 'views', (f) => f.views_seen, (f) => fmt(f.views_seen, 0)],
      ['raised', 'raised', (f) => f.views_raised, (f) => fmt(f.views_raised, 0)],
      ['centre', 'centre err. [mm]', (f) => (typeof f.centre_error_m === 'number' ? f.centre_error_m * 1000 : undefined),
        (f) => (typeof f.centre_error_m === 'number' ? (f.centre_error_m * 1000).toFixed(1) : '–')],
      ['voxel_volume', 'voxel vol. err.', (f) => f.voxel_volume_error, (f) => pct(f.voxel_volume_error)],
      ['ellipsoid_volume', 'ellipsoid vol. err.', (f) => f.ellipsoid_volume_error, (f) => pct(f.ellipsoid_volume_error)],
      ['volume', 'volume [cm³]', (f) => f.true_volume_m3, (f) => (typeof f.true_volume_m3 === 'number' ? (f.true_volume_m3 * 1e6).toFixed(1) : '–')],
    ];
    const box = document.getElementById('fruits');
    box.innerHTML = '<h2>True fruits (' + fruits.length + '; click a heading to sort, hover a row to find the fruit)</h2>' +
      '<div class="table-wrap"><table id="fruit-table"><thead><tr>' +
      columns.map(([key, title]) => '<th data-sort="' + key + '">' + title + '</th>').join('') + '</tr></thead><tbody>' +
      fruits.map((f, i) => '<tr data-fruit="' + esc(f.id) + '" data-index="' + i + '">' + columns.map((c) => '<td>' + c[3](f) + '</td>').join('') + '</tr>').join('') +
      '</tbody></table></div>' +
      '<p class="small">SC at the end of the run; views: the successful views that saw it (any part of it in the view\'s ' +
      'true instance image, within the camera\'s range), raised: the views that raised its SC; errors of the fruit cluster matched to the fruit ' +
      '(– when none matched): its centre\'s distance from the true centre, its voxels\' and its fitted ellipsoid\'s volume against the ' +
      'true volume (relative); volume: the true one.</p>';
    const body = box.querySelector('tbody');
    let by = null, descending = false;
    function sort(key) {
      descending = by === key ? !descending : key !== 'id' && key !== 'plant';
      by = key;
      const get = columns.find((c) => c[0] === key)[2];
      const rows = [...body.rows];
      rows.sort((a, b) => {
        const va = get(fruits[+a.dataset.index]), vb = get(fruits[+b.dataset.index]);
        const na = typeof va !== 'number', nb = typeof vb !== 'number';
        if (na || nb) return na - nb;  // no value: last either way
        return descending ? vb - va : va - vb;
      });
      rows.forEach((r) => body.appendChild(r));
      box.querySelectorAll('th').forEach((th) => { th.dataset.order = th.dataset.sort === key ? (descending ? 'desc' : 'asc') : ''; });
    }
    box.querySelectorAll('th').forEach((th) => th.addEventListener('click', () => sort(th.dataset.sort)));
    body.addEventListener('mouseover', (ev) => { const r = ev.target.closest('tr'); if (r) highlightFruit(+r.dataset.index); });
    body.addEventListener('mouseleave', () => highlightFruit(-1));
    return { sort, order: () => [...body.rows].map((r) => r.dataset.fruit) };
  })();

  // ---- Curves ---------------------------------------------------------------------------
  function curve(svgId, values, label) {
    const svg = document.getElementById(svgId);
    const W = 396, H = 130, L = 46, R = 8, T = 8, B = 30;
    const max = Math.max(1e-9, ...values.map((v) => (isFinite(v) ? v : 0)));
    const yTicks = canopyAxes.ticks(label === 'SC' ? 1 : max, 4);
    const top = yTicks[yTicks.length - 1];
    const x = (i) => L + (values.length > 1 ? (i / (values.length - 1)) * (W - L - R) : 0);
    const y = (v) => T + (1 - v / top) * (H - T - B);
    let d = '';
    values.forEach((v, i) => { d += (i ? 'L' : 'M') + x(i).toFixed(1) + ',' + y(v).toFixed(1); });
    // The cursor's label sits inside the plot, right of the cursor (left of it near the right
    // edge), clear of the tick labels left of the y axis.
    svg.innerHTML = canopyAxes.svg({ L, R, T, B, W, H, x, y, yTicks, n: values.length }) +
      '<path d="' + d + '" fill="none" stroke="#1f77b4" stroke-width="1.5"/>' +
      '<line class="cursor" x1="0" y1="' + T + '" x2="0" y2="' + (H - B) + '" stroke="#d62728"/>' +
      '<text class="cursor-label" x="0" y="' + (T + 10) + '"></text>';
    svg.addEventListener('click', (ev) => {
      const r = svg.getBoundingClientRect();
      const i = Math.round(((ev.clientX - r.left - L) / (W - L - R)) * (values.length - 1));
      setView(Math.max(0, Math.min(values.length - 1, i)));
    });
    return { svg, x, y, values };
  }
  const curves = [curve('curve-sc', okViews.map((v) => v.coverage), 'SC'), curve('curve-h', okViews.map((v) => v.entropy), 'H')];

  // ---- 3D scene ---------------------------------------------------------------------------
  let renderer = null, scene, camera, controls, points, fruitMeshes = [], frusta = null, pickPoints, targetLine, robot = null, highlighted = -1;
  const labels3d = [];  // the axes' and the scale's text, by name
  // Class colours of the label images; black (background) drawn dark grey to show on white.
  const classColours = (data.classes || []).map((c) => (c.color[0] + c.color[1] + c.color[2] === 0
    ? new THREE.Color(0.33, 0.33, 0.33) : new THREE.Color(c.color[0] / 255, c.color[1] / 255, c.color[2] / 255)));
  // Occupancy and entropy: saturated green from light (low) to dark (high), apart from the true
  // fruits' blue, amber and grey (a hue ramp through orange once hid the partly seen fruits).
  const ramp = (t) => new THREE.Color().setHSL(0.33, 1.0, 0.75 - 0.55 * t);
  const phaseColour = (phase) => hexColour((phaseStyle[phase] || {}).colour);
  const failedColour = hexColour(vocabulary.failed_view_colour);
  const fruitColours = { seen: 0x2b8cff, partly: 0xffb000, unseen: 0x777777, highlighted: 0xff00cc };
  const fruitColour = (c) => (c >= 0.8 ? fruitColours.seen : c > 0.05 ? fruitColours.partly : fruitColours.unseen);
  const at = (object, x, y, z) => { object.position.set(x, y, z); return object; };
  // A text label in the scene, `height_m` high, always facing the viewer.
  function textSprite(name, text, colour, height_m) {
    const c = document.createElement('canvas'), g = c.getContext('2d');
    g.font = '28px sans-serif';
    c.width = Math.ceil(g.measureText(text).width) + 8;
    c.height = 36;
    g.font = '28px sans-serif';
    g.fillStyle = colour;
    g.textBaseline = 'middle';
    g.fillText(text, 4, 18);
    const sprite = new THREE.Sprite(new THREE.SpriteMaterial({ map: new THREE.CanvasTexture(c), depthTest: false }));
    sprite.scale.set((height_m * c.width) / c.height, height_m, 1);
    sprite.name = name;
    sprite.userData.text = text;
    labels3d.push(sprite);
    return sprite;
  }

  // One shape of a link (data.robot.shapes[i][j]) in the link's frame: boxes, spheres, cylinders
  // and capsules along their z axis (three.js's cylinders run along y), shaded in the URDF's colour.
  function robotShape(sh) {
    const colour = new THREE.Color(sh.rgba[0], sh.rgba[1], sh.rgba[2]);
    const material = new THREE.MeshLambertMaterial({ color: colour, transparent: sh.rgba[3] < 1, opacity: sh.rgba[3] });
    const g = new THREE.Group();
    const alongZ = (mesh) => { mesh.rotation.x = Math.PI / 2; return mesh; };
    if (sh.type === 'box') g.add(new THREE.Mesh(new THREE.BoxGeometry(sh.size[0], sh.size[1], sh.size[2]), material));
    else if (sh.type === 'sphere') g.add(new THREE.Mesh(new THREE.SphereGeometry(sh.radius, 16, 10), material));
    else if (sh.type === 'cylinder') g.add(alongZ(new THREE.Mesh(new THREE.CylinderGeometry(sh.radius, sh.radius, sh.length, 20), material)));
    else if (sh.type === 'capsule') {
      g.add(alongZ(new THREE.Mesh(new THREE.CylinderGeometry(sh.radius, sh.radius, sh.length, 20, 1, true), material)));
      for (const z of [-sh.length / 2, sh.length / 2]) g.add(at(new THREE.Mesh(new THREE.SphereGeometry(sh.radius, 16, 10), material), 0, 0, z));
    }
    g.position.set(sh.pose[0], sh.pose[1], sh.pose[2]);
    g.quaternion.set(sh.pose[4], sh.pose[5], sh.pose[6], sh.pose[3]);
    g.userData.type = sh.type;
    return g;
  }

  function setupScene() {
    try {
      renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });  // no MSAA: software GL stays fast
    } catch (e) {
      view3d.appendChild(el('p', { id: 'no-webgl' }, 'No WebGL in this browser: the 3D view is off (' + esc(e.message) + ').'));
      return;
    }
    marks.webgl = performance.now();
    renderer.setPixelRatio(1);
    renderer.setClearColor(0xffffff);
    view3d.insertBefore(renderer.domElement, tip);
    scene = new THREE.Scene();
    camera = new THREE.PerspectiveCamera(45, 1, 0.01, 100);
    camera.up.set(0, 0, 1);
    // The map's voxels: one point each, sized as a voxel.
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(Math.max(1, nVox) * 3), 3));
    g.setAttribute('color', new THREE.BufferAttribute(new Float32Array(Math.max(1, nVox) * 3), 3));
    points = new THREE.Points(g, new THREE.PointsMaterial({ size: res * 1.1, vertexColors: THREE.VertexColors }));
    scene.add(points);
    // Bounds of the scene: voxels, fruits and cameras.
    const box = new THREE.Box3();
    for (let i = 0; i < nVox; ++i) box.expandByPoint(new THREE.Vector3(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]));
    // True fruits: ellipsoids in their boxes, coloured by coverage.
    for (const f of data.fruits || []) {
      const c = [0, 1, 2].map((a) => (f.min[a] + f.max[a]) / 2), r = [0, 1, 2].map((a) => Math.max(0.005, (f.max[a] - f.min[a]) / 2));
      const m = new THREE.Mesh(new THREE.SphereGeometry(1, 12, 8), new THREE.MeshBasicMaterial({ color: fruitColour(f.cov || 0), wireframe: true }));
      m.position.set(c[0], c[1], c[2]);
      m.scale.set(r[0], r[1], r[2]);
      m.userData = f;
      scene.add(m);
      fruitMeshes.push(m);
      box.expandByPoint(new THREE.Vector3(f.min[0], f.min[1], f.min[2]));
      box.expandByPoint(new THREE.Vector3(f.max[0], f.max[1], f.max[2]));
    }
    // Cameras: a small frustum per attempted view (16 line vertices each, in attempt order, so
    // that the views up to k are a draw range of one object), and a pick point at its centre.
    const pick = new Float32Array(Math.max(1, views.length) * 3);
    const fv = new Float32Array(Math.max(1, views.length) * 48), fc = new Float32Array(Math.max(1, views.length) * 48);
    const corner = new THREE.Vector3(), q = new THREE.Quaternion();
    views.forEach((v, i) => {
      const p = v.goal_pose.position, w = v.goal_pose.quaternion_wxyz;
      q.set(w[1], w[2], w[3], w[0]);
      const s = 0.04, h = 0.03;
      const corners = [[-s, -h, 0.06], [s, -h, 0.06], [s, h, 0.06], [-s, h, 0.06]];
      const local = [];
      for (let c = 0; c < 4; ++c) local.push([0, 0, 0], corners[c], corners[c], corners[(c + 1) % 4]);
      const colour = new THREE.Color(v.success ? phaseColour(v.phase) : failedColour);
      local.forEach((l, j) => {
        corner.set(l[0], l[1], l[2]).applyQuaternion(q);
        fv[48 * i + 3 * j] = p[0] + corner.x; fv[48 * i + 3 * j + 1] = p[1] + corner.y; fv[48 * i + 3 * j + 2] = p[2] + corner.z;
        fc[48 * i + 3 * j] = colour.r; fc[48 * i + 3 * j + 1] = colour.g; fc[48 * i + 3 * j + 2] = colour.b;
      });
      pick[3 * i] = p[0]; pick[3 * i + 1] = p[1]; pick[3 * i + 2] = p[2];
      box.expandByPoint(new THREE.Vector3(p[0], p[1], p[2]));
    });
    const fg = new THREE.BufferGeometry();
    fg.setAttribute('position', new THREE.BufferAttribute(fv, 3));
    fg.setAttribute('color', new THREE.BufferAttribute(fc, 3));
    frusta = new THREE.LineSegments(fg, new THREE.LineBasicMaterial({ vertexColors: THREE.VertexColors }));
    scene.add(frusta);
    const pg = new THREE.BufferGeometry();
    pg.setAttribute('position', new THREE.BufferAttribute(pick, 3));
    pickPoints = new THREE.Points(pg, new THREE.PointsMaterial({ size: 0.015, color: 0x333333 }));
    scene.add(pickPoints);
    // Base stops: the footprint reached, and the goal as a cross.
    for (const st of data.stops || []) {
      const b = new THREE.Mesh(new THREE.PlaneGeometry(0.5, 0.4), new THREE.MeshBasicMaterial({ color: st.reached_goal ? 0xb0b0b0 : 0xf08080, transparent: true, opacity: 0.5 }));
      b.position.set(st.reached[0], st.reached[1], 0.002);
      b.rotation.z = st.reached[2];
      scene.add(b);
      box.expandByPoint(b.position);
    }
    const grid = new THREE.GridHelper(10, 20, 0xdddddd, 0xeeeeee);
    grid.rotation.x = Math.PI / 2;
    scene.add(grid);
    // The world frame's axes (x red, y green, z blue, 0.5 m) and the grid's metres along x and y
    // at the scene's near edges, as RViz draws its fixed frame.
    const axes = new THREE.AxesHelper(0.5);
    axes.name = 'axes';
    scene.add(axes);
    scene.add(at(textSprite('axis-x', 'x', '#d00000', 0.06), 0.56, 0, 0));
    scene.add(at(textSprite('axis-y', 'y', '#00a000', 0.06), 0, 0.56, 0));
    scene.add(at(textSprite('axis-z', 'z', '#0000d0', 0.06), 0, 0, 0.56));
    if (!box.isEmpty()) {
      const y0 = Math.floor(box.min.y * 2) / 2 - 0.25, x0 = Math.floor(box.min.x * 2) / 2 - 0.25;
      for (let m = Math.floor(box.min.x); m <= Math.ceil(box.max.x); ++m)
        scene.add(at(textSprite('scale-x' + m, (m ? 'x ' + m + ' m' : '0'), '#666', 0.07), m, y0, 0));
      for (let m = Math.floor(box.min.y); m <= Math.ceil(box.max.y); ++m)
        if (m) scene.add(at(textSprite('scale-y' + m, 'y ' + m + ' m', '#666', 0.07), x0, m, 0));
    }
    // The robot at the view shown: each link's shapes (the URDF's boxes, cylinders, spheres and
    // capsules, data.robot.shapes) in its frame; without shapes, the links' frames joined parent
    // to child and the base a box.
    if (data.robot && (data.robot.links || []).length && (data.robot.poses || []).length) {
      const R = data.robot, shaped = (R.shapes || []).some((l) => l.length);
      robot = new THREE.Group();
      robot.name = 'robot';
      const material = new THREE.MeshBasicMaterial({ color: 0x4a5a70 });
      robot.userData.joints = R.links.map(() => {
        const m = new THREE.Mesh(new THREE.SphereGeometry(0.022, 10, 6), material);
        m.visible = !shaped;  // kept as the links' origins (state().robot) when the shapes are drawn
        robot.add(m);
        return m;
      });
      robot.userData.bones = R.links.map((l, i) => {
        const parent = R.links.indexOf(R.parents[i]);
        if (parent < 0 || shaped) return null;
        const m = new THREE.Mesh(new THREE.CylinderGeometry(0.016, 0.016, 1, 8), material);
        m.userData.parent = parent;
        robot.add(m);
        return m;
      });
      robot.userData.frames = R.links.map((l, i) => {  // a group per link, posed per view
        const g = new THREE.Group();
        for (const sh of (R.shapes || [])[i] || []) g.add(robotShape(sh));
        robot.add(g);
        return g;
      });
      if (!shaped) {
        const base = new THREE.Mesh(new THREE.BoxGeometry(0.5, 0.4, 0.3), new THREE.MeshBasicMaterial({ color: 0x8090a0, transparent: true, opacity: 0.35 }));
        robot.userData.base = base;
        robot.add(base);
      }
      scene.add(robot);
      scene.add(new THREE.AmbientLight(0xffffff, 0.55));
      const sun = new THREE.DirectionalLight(0xffffff, 0.6);
      sun.position.set(1, -2, 3);
      scene.add(sun);
    }
    targetLine = new THREE.Line(new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]), new THREE.LineBasicMaterial({ color: 0x000000 }));
    targetLine.visible = false;
    scene.add(targetLine);
    if (box.isEmpty()) box.set(new THREE.Vector3(-1, -1, 0), new THREE.Vector3(1, 1, 1));
    const centre = box.getCenter(new THREE.Vector3()), size = box.getSize(new THREE.Vector3()).length();
    camera.position.set(centre.x - 0.3 * size, centre.y - 0.75 * size, centre.z + 0.75 * size);
    controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.target.copy(centre);
    controls.addEventListener('change', draw);
    controls.update();
    controls.saveState();  // what the reset button returns to
    const hint = el('div', { id: 'orbit-hint' }, 'drag: orbit · right-drag or shift-drag: pan · wheel: zoom ' +
      '<button id="reset-view" title="back to the first view of the scene">reset view</button>');
    view3d.appendChild(hint);
    document.getElementById('reset-view').addEventListener('click', () => { controls.reset(); draw(); });
    renderer.domElement.addEventListener('mousemove', hover);
    window.addEventListener('resize', resize);
    marks.objects = performance.now();
    resize();
  }
  function resize() {
    if (!renderer) return;
    const w = view3d.clientWidth || 640, h = view3d.clientHeight || 480;
    renderer.setSize(w, h, false);
    renderer.domElement.style.width = w + 'px';
    renderer.domElement.style.height = h + 'px';
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    draw();
  }
  // Draws at the next animation frame, once however many changes asked for it; the first frame
  // makes the page ready (window.canopyReport.ready).
  let pending = false, onFirstFrame = null;
  function draw() {
    if (!renderer || pending) return;
    pending = true;
    requestAnimationFrame(() => {
      pending = false;
      renderer.render(scene, camera);
      if (onFirstFrame) { const f = onFirstFrame; onFirstFrame = null; f(); }
    });
  }

  function hover(ev) {
    const r = renderer.domElement.getBoundingClientRect();
    const mouse = new THREE.Vector2(((ev.clientX - r.left) / r.width) * 2 - 1, -((ev.clientY - r.top) / r.height) * 2 + 1);
    const ray = new THREE.Raycaster();
    ray.params.Points.threshold = 0.02;
    ray.setFromCamera(mouse, camera);
    const shown = attemptsUpTo[current] || 0;
    const hit = ray.intersectObject(pickPoints).find((h) => h.index < shown);
    let text = '';
    targetLine.visible = false;
    if (hit) {
      const v = views[hit.index];
      text = 'attempt ' + (v.attempt + 1) + ', stop ' + (v.stop + 1) + stopsOf + ', ' + v.phase + ' (' + v.source + ')\n' +
        (v.success ? 'view ' + (v.k + 1) + ': SC ' + fmt(v.coverage) + ', entropy ' + fmt(v.entropy, 1) : 'failed: ' + v.failure + (v.message ? '\n' + v.message : '')) +
        '\ngain ' + fmt(v.gain, 4) + (v.cluster >= 0 ? ', cluster ' + v.cluster : '');
      if (v.target && (v.target[0] || v.target[1] || v.target[2])) {
        text += '\ntarget ' + v.target.map((t) => t.toFixed(3)).join(', ');
        targetLine.geometry.setFromPoints([new THREE.Vector3(...v.goal_pose.position), new THREE.Vector3(...v.target)]);
        targetLine.visible = true;
      }
    } else {
      const f = ray.intersectObjects(fruitMeshes)[0];
      if (f) text = 'fruit ' + f.object.userData.id + ' (plant ' + f.object.userData.plant + '): SC ' + fmt(fruitCoverage(f.object.userData, fruitIndex(f.object)));
    }
    tip.style.display = text ? 'block' : 'none';
    tip.textContent = text;
    tip.style.left = ev.clientX - r.left + 12 + 'px';
    tip.style.top = ev.clientY - r.top + 12 + 'px';
    draw();
  }
  const fruitIndex = (m) => fruitMeshes.indexOf(m);
  // A fruit picked in the table, drawn magenta (-1: none).
  function highlightFruit(i) {
    highlighted = i;
    fruitMeshes.forEach((m, j) => m.material.color.setHex(j === i ? fruitColours.highlighted : fruitColour(fruitCoverage(m.userData, j))));
    draw();
  }
  function fruitCoverage(f, i) {
    const fc = map.fruit_coverage || [];
    const g = Math.floor(current / (map.step || 1));
    if (fc.length && fc[Math.min(g, fc.length - 1)]) return fc[Math.min(g, fc.length - 1)][i] || 0;
    return f.cov || 0;
  }

  // ---- Replay --------------------------------------------------------------------------
  const state = new Uint16Array(nVox);
  let applied = 0;  // map states applied (groups)
  let current = Math.max(0, nK - 1), drawnVoxels = 0, mode = 'class';
  function colourOf(st) {
    if (mode === 'occupancy') return ramp(((st >> 6) & 3) / 3);
    if (mode === 'entropy') return ramp(((st >> 8) & 7) / 7);
    return classColours[st & 63] || new THREE.Color(0.5, 0.5, 0.5);
  }
  function applyMap(k) {
    const want = nK ? Math.min(map.counts.length, Math.floor(k / (map.step || 1)) + 1) : 0;
    if (want < applied) { state.fill(0); applied = 0; }
    for (let i = applied ? groupEnd[applied - 1] : 0; i < (want ? groupEnd[want - 1] : 0); ++i) state[chVox[i]] = chState[i];
    applied = want;
    if (!points) {
      drawnVoxels = state.reduce((n, st) => n + (st ? 1 : 0), 0);
      return;
    }
    const P = points.geometry.attributes.position, C = points.geometry.attributes.color;
    let n = 0;
    for (let i = 0; i < nVox; ++i) {
      const st = state[i];
      if (!st) continue;
      P.array[3 * n] = pos[3 * i]; P.array[3 * n + 1] = pos[3 * i + 1]; P.array[3 * n + 2] = pos[3 * i + 2];
      const c = colourOf(st);
      C.array[3 * n] = c.r; C.array[3 * n + 1] = c.g; C.array[3 * n + 2] = c.b;
      ++n;
    }
    drawnVoxels = n;
    points.geometry.setDrawRange(0, n);
    P.needsUpdate = true;
    C.needsUpdate = true;
  }
  function setView(k) {
    current = Math.max(0, Math.min(Math.max(0, nK - 1), k | 0));
    document.getElementById('slider').value = current;
    applyMap(current);
    const shown = nK ? attemptsUpTo[current] : views.length;
    if (frusta) {
      frusta.visible = document.getElementById('show-frusta').checked;
      frusta.geometry.setDrawRange(0, 16 * shown);
      pickPoints.geometry.setDrawRange(0, shown);
    }
    fruitMeshes.forEach((m, i) => {
      m.material.color.setHex(i === highlighted ? fruitColours.highlighted : fruitColour(fruitCoverage(m.userData, i)));
      m.visible = document.getElementById('show-fruits').checked;
    });
    const v = okViews[current];
    document.getElementById('view-count').textContent = nK ? 'view ' + (current + 1) + ' / ' + nK : 'no successful view';
    document.getElementById('view-info').innerHTML = v
      ? 'stop ' + (v.stop + 1) + stopsOf + ', ' + esc(v.phase) + ' (' + esc(v.source) + '), attempt ' + (v.attempt + 1) + '; SC ' + fmt(v.coverage) + ', entropy ' + fmt(v.entropy, 1) +
        '; ' + shown + ' attempts shown, ' + drawnVoxels + ' voxels'
      : '';
    for (const c of curves) {
      const cx = c.values.length ? c.x(current) : 0;
      const line = c.svg.querySelector('.cursor');
      line.setAttribute('x1', cx.toFixed(1));
      line.setAttribute('x2', cx.toFixed(1));
      const lab = c.svg.querySelector('.cursor-label');
      const right = cx > 396 - 70;  // near the right edge: the label goes left of the cursor
      lab.setAttribute('x', (right ? cx - 3 : cx + 3).toFixed(1));
      lab.setAttribute('text-anchor', right ? 'end' : 'start');
      lab.textContent = c.values.length ? fmt(c.values[current]) : '';
    }
    thumb('thumb-rgb', 'rgb');
    thumb('thumb-labels', 'labels');
    thumb('thumb-mapped', 'mapped');
    document.getElementById('fig-mapped').style.display = (thumbs.mapped || []).length ? '' : 'none';
    poseRobot();
    document.body.dataset.view = String(current);
    document.body.dataset.shownAttempts = String(shown);
    draw();
  }
  // The robot's links as recorded at successful view `current` (data.robot.poses[k]: x y z qw qx
  // qy qz per link, in the order of data.robot.links).
  function poseRobot() {
    if (!robot) return;
    const p = data.robot.poses[Math.min(current, data.robot.poses.length - 1)] || [];
    const at = (i) => new THREE.Vector3(p[7 * i], p[7 * i + 1], p[7 * i + 2]);
    robot.userData.joints.forEach((m, i) => m.position.copy(at(i)));
    const up = new THREE.Vector3(0, 1, 0);
    robot.userData.bones.forEach((m, i) => {
      if (!m) return;
      const a = at(m.userData.parent), b = at(i), d = b.clone().sub(a), len = d.length();
      m.visible = len > 1e-4;
      if (!m.visible) return;
      m.position.copy(a).add(b).multiplyScalar(0.5);
      m.scale.set(1, len, 1);
      m.quaternion.setFromUnitVectors(up, d.normalize());
    });
    robot.userData.frames.forEach((g, i) => {
      g.position.copy(at(i));
      g.quaternion.set(p[7 * i + 4], p[7 * i + 5], p[7 * i + 6], p[7 * i + 3]);
    });
    const base = robot.userData.base;  // without shapes: under the first link (the base's), turned with it
    if (base) {
      base.position.set(p[0], p[1], 0.15);
      base.quaternion.set(p[4], p[5], p[6], p[3]);
    }
    robot.visible = document.getElementById('show-robot').checked;
  }
  function thumb(id, kind) {
    const e = document.getElementById(id);
    const sheets = thumbs[kind] || [];
    const t = Math.floor(current / (thumbs.step || 1));
    const sheet = Math.floor(t / (thumbs.per_sheet || 100)), i = t % (thumbs.per_sheet || 100);
    if (!sheets.length || sheet >= sheets.length) { e.style.display = 'none'; return; }
    e.style.display = 'block';
    e.style.width = thumbs.w + 'px';
    e.style.height = thumbs.h + 'px';
    e.style.backgroundImage = 'url("' + sheets[sheet] + '")';
    e.style.backgroundPosition = -(i % thumbs.cols) * thumbs.w + 'px ' + -Math.floor(i / thumbs.cols) * thumbs.h + 'px';
  }
  function updateLegend() {
    let html = '';
    if (mode === 'class') html = (data.classes || []).map((c, i) => '<span class="sw" style="background:#' + classColours[i].getHexString() + '"></span>' + esc(c.name)).join('');
    else html = mode + ': <span class="sw" style="background:#' + ramp(0).getHexString() + '"></span>low<span class="sw" style="background:#' +
      ramp(0.5).getHexString() + '"></span><span class="sw" style="background:#' + ramp(1).getHexString() + '"></span>high';
    const shown = new Set(views.map((v) => v.phase));
    html += '<br>cameras: ' + (vocabulary.view_phases || []).filter((p) => shown.has(p.name))
      .map((p) => '<span class="sw" style="background:' + esc(p.colour) + '"></span>' + esc(p.legend)).join('') +
      '<span class="sw" style="background:' + esc(vocabulary.failed_view_colour) + '"></span>failed' +
      '<br>true fruits: <span class="sw" style="background:#2b8cff"></span>seen (SC ≥ 0.8)<span class="sw" style="background:#ffb000"></span>partly<span class="sw" style="background:#777"></span>unseen' +
      (robot ? (robot.userData.frames.some((g) => g.children.length) ? '<br>robot: its URDF\'s shapes at the view shown'
        : '<br>robot: <span class="sw" style="background:#4a5a70"></span>at the view shown') : '') +
      '<br><span id="scale-note">grid: 0.5 m squares; axes x red, y green, z blue, 0.5 m long</span>';
    legend.innerHTML = html;
  }

  // ---- Controls ------------------------------------------------------------------------
  let timer = null;
  document.getElementById('slider').addEventListener('input', (e) => setView(+e.target.value));
  document.getElementById('colour').addEventListener('change', (e) => { mode = e.target.value; applied = 0; state.fill(0); updateLegend(); setView(current); });
  document.getElementById('show-frusta').addEventListener('change', () => setView(current));
  document.getElementById('show-fruits').addEventListener('change', () => setView(current));
  if (data.robot) document.getElementById('show-robot').addEventListener('change', () => setView(current));
  document.getElementById('play').addEventListener('click', () => {
    const b = document.getElementById('play');
    if (timer) { clearInterval(timer); timer = null; b.textContent = '▶ play'; return; }
    if (current >= nK - 1) setView(0);
    b.textContent = '❚❚ pause';
    timer = setInterval(() => {
      if (current >= nK - 1) { clearInterval(timer); timer = null; b.textContent = '▶ play'; return; }
      setView(current + 1);
    }, 150);
  });

  marks.decoded = performance.now();
  setupScene();
  marks.scene = performance.now();
  updateLegend();
  setView(current);
  const hook = {
    ready: false,
    views: nK,
    setView,
    marks,
    state: () => ({ view: current, shownAttempts: nK ? attemptsUpTo[current] : views.length, drawnVoxels,
                    cursor: +document.querySelector('#curve-sc .cursor').getAttribute('x1'), webgl: !!renderer,
                    complete: !!data.complete,
                    camera: camera ? camera.position.toArray() : null,
                    // The robot's drawn link origins, in the order of data.robot.links.
                    robot: robot && robot.visible ? robot.userData.joints.map((m) => m.position.toArray()) : null,
                    // The robot's drawn shapes: type and centre in the world.
                    robotShapes: robot && robot.visible ? robot.userData.frames.flatMap((g) => g.children.map((c) => {
                      c.updateWorldMatrix(true, false);
                      return { type: c.userData.type, at: new THREE.Vector3().setFromMatrixPosition(c.matrixWorld).toArray() };
                    })) : null,
                    labels3d: labels3d.map((l) => ({ name: l.name, text: l.userData.text, at: l.position.toArray() })),
                    axes: !!(scene && scene.getObjectByName('axes')) }),
    // Colours of the occupancy and entropy levels and of the true fruits' states, as RGB 0-255.
    colours: () => {
      const rgb = (c) => [Math.round(c.r * 255), Math.round(c.g * 255), Math.round(c.b * 255)];
      return { entropy: [0, 1, 2, 3, 4, 5, 6, 7].map((l) => rgb(ramp(l / 7))), occupancy: [0, 1, 2, 3].map((l) => rgb(ramp(l / 3))),
               fruits: Object.fromEntries(Object.entries(fruitColours).map(([k, v]) => [k, rgb(new THREE.Color(v))])) };
    },
    fruitTable,
  };
  window.canopyReport = hook;
  const ready = () => {
    marks.ready = performance.now();
    hook.readyMs = marks.ready;
    hook.ready = true;
    document.body.dataset.ready = '1';
  };
  if (renderer) onFirstFrame = ready;
  else ready();
})();
