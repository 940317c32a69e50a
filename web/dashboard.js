// The juggle dashboard (docs/dashboard.md): polls the learner's JSON API (api/status,
// api/history, api/evals) every few seconds and draws it with Chart.js and d3; or, in a file
// written by `juggle dashboard`, draws window.JUGGLE_DATA once.
'use strict';

(function () {
  const REFRESH_MS = 3000;
  const embedded = window.JUGGLE_DATA || null;
  const errors = [];

  // Every uncaught error shows on the page (and the browser test reads #js-errors).
  function reportError(message) {
    errors.push(String(message));
    const box = document.getElementById('js-errors');
    box.hidden = false;
    box.textContent = 'JavaScript error: ' + errors.join('\n');
  }
  window.addEventListener('error', (e) => reportError(e.message + ' (' + e.filename + ':' + e.lineno + ')'));
  window.addEventListener('unhandledrejection', (e) => reportError(e.reason));

  // ---- formatting ----
  const $ = (id) => document.getElementById(id);
  function num(v, digits) {
    if (v === null || v === undefined || Number.isNaN(v)) return '–';
    if (digits === undefined) return Math.round(v).toLocaleString('en-US');
    return Number(v).toLocaleString('en-US', { minimumFractionDigits: digits, maximumFractionDigits: digits });
  }
  function duration(s) {
    if (s === null || s === undefined) return '–';
    if (s < 90) return num(s, 0) + ' s';
    if (s < 5400) return num(s / 60, 1) + ' min';
    return num(s / 3600, 1) + ' h';
  }
  function pct(v) { return v === null || v === undefined ? '–' : num(100 * v, 0) + ' %'; }
  function text(id, value) { const el = $(id); if (el.textContent !== value) el.textContent = value; }

  // ---- charts (Chart.js) ----
  Chart.defaults.animation = false;
  Chart.defaults.font.size = 11;
  Chart.defaults.plugins.legend.labels.boxWidth = 12;
  const PALETTE = ['#1565c0', '#c62828', '#2e7d32', '#ef6c00', '#6a1b9a', '#00838f', '#5d4037', '#ad1457', '#9e9d24', '#37474f'];
  const charts = {};
  function lineChart(id, series, opts) {
    opts = opts || {};
    const datasets = series.map((s, i) => ({
      label: s.label, data: [], parsing: false, borderColor: s.color || PALETTE[i % PALETTE.length],
      backgroundColor: s.fill || s.color || PALETTE[i % PALETTE.length], borderWidth: 1.5, pointRadius: 0,
      fill: s.fillTo === undefined ? false : s.fillTo, yAxisID: s.axis || 'y', stack: s.stack,
      showLine: true,
    }));
    const scales = {
      x: { type: 'linear', title: { display: true, text: opts.xLabel || 'iteration' }, ticks: { maxTicksLimit: 8 } },
      y: { type: opts.logY ? 'logarithmic' : 'linear', stacked: !!opts.stacked, min: opts.minY, max: opts.maxY,
           beginAtZero: !opts.logY && opts.minY === undefined },
    };
    if (series.some((s) => s.axis === 'y2')) {
      scales.y2 = { type: opts.logY2 ? 'logarithmic' : 'linear', position: 'right', grid: { drawOnChartArea: false } };
    }
    charts[id] = new Chart($(id), {
      type: 'line', data: { datasets },
      options: { responsive: true, maintainAspectRatio: false, normalized: true, scales,
                 interaction: { mode: 'nearest', axis: 'x', intersect: false },
                 plugins: { decimation: { enabled: false } } },
    });
  }
  function barChart(id, label, color) {
    charts[id] = new Chart($(id), {
      type: 'bar', data: { labels: [], datasets: [{ label, data: [], backgroundColor: color }] },
      options: { responsive: true, maintainAspectRatio: false, plugins: { legend: { display: false } },
                 scales: { y: { beginAtZero: true } } },
    });
  }

  lineChart('chart-return', [{ label: 'mean return' }]);
  lineChart('chart-juggles', [{ label: 'juggles / episode' }, { label: 'completions / episode' }]);
  lineChart('chart-length', [{ label: 'episode length' }]);
  lineChart('chart-outcomes', [], { stacked: true, minY: 0, maxY: 1 });
  lineChart('chart-eval', [{ label: 'p90', color: '#90caf9', fillTo: '+2' }, { label: 'median', color: '#1565c0' },
                           { label: 'p10', color: '#90caf9' }], { xLabel: 'iteration' });
  barChart('chart-eval-hist', 'episodes', '#1565c0');
  lineChart('chart-ppo', [{ label: 'value loss' }, { label: 'approx KL', axis: 'y2' }, { label: 'learning rate', axis: 'y2' }],
            { logY: true, logY2: true });
  lineChart('chart-gates', [{ label: 'specialization' }, { label: 'utilization', axis: 'y2' }]);
  lineChart('chart-teacher', [{ label: 'expert juggles / episode', color: '#2e7d32' },
                              { label: 'student juggles / episode', color: '#1565c0' },
                              { label: 'imitation loss', axis: 'y2', color: '#c62828' }]);
  lineChart('chart-loop', [{ label: 'planner rollout steps / label', color: '#6a1b9a' },
                           { label: 'policy chosen (share of re-plans)', axis: 'y2', color: '#2e7d32' },
                           { label: 'rescues (share of re-plans)', axis: 'y2', color: '#ef6c00' },
                           { label: 'student error, fresh labels', axis: 'y2', color: '#c62828' },
                           { label: 'policy weight in chosen plans (mean)', axis: 'y2', color: '#00838f' }]);
  lineChart('chart-rate', [{ label: 'samples/s' }, { label: 'sim-s/s', axis: 'y2' }]);
  lineChart('chart-split', [{ label: 'wait', color: '#ef6c00', fillTo: 'origin', stack: 's' },
                            { label: 'update', color: '#1565c0', fillTo: '-1', stack: 's' }], { stacked: true });
  barChart('chart-lag', 'unrolls', '#6a1b9a');

  // ---- state ----
  const history = { stride: 0, last: 0, points: [] };
  let evaluations = [];
  let lastStatus = null;
  let graphDrawn = null;  // the graph's structure key once drawn

  function setSeries(chart, index, points) { chart.data.datasets[index].data = points; }
  function positive(v) { return v !== null && v !== undefined && v > 0 ? v : null; }

  function renderHistory(status) {
    const p = history.points;
    const xy = (f) => p.map((r) => ({ x: r.iteration, y: f(r) }));
    setSeries(charts['chart-return'], 0, xy((r) => r.mean_return));
    setSeries(charts['chart-juggles'], 0, xy((r) => r.juggles_per_episode));
    setSeries(charts['chart-juggles'], 1, xy((r) => r.completions_per_episode));
    setSeries(charts['chart-length'], 0, xy((r) => r.mean_episode_len));
    setSeries(charts['chart-ppo'], 0, xy((r) => positive(r.value_loss)));
    setSeries(charts['chart-ppo'], 1, xy((r) => positive(r.approx_kl)));
    setSeries(charts['chart-ppo'], 2, xy((r) => positive(r.actor_lr)));
    const gated = p.filter((r) => r.gate_specialization !== undefined);
    setSeries(charts['chart-gates'], 0, gated.map((r) => ({ x: r.iteration, y: r.gate_specialization })));
    setSeries(charts['chart-gates'], 1, gated.map((r) => ({ x: r.iteration, y: r.gate_utilization })));
    // Planner-guided training: teacher and student side by side (points without expert episodes skipped).
    setSeries(charts['chart-teacher'], 0, p.filter((r) => r.expert_episodes > 0)
      .map((r) => ({ x: r.iteration, y: r.expert_juggles_per_episode })));
    setSeries(charts['chart-teacher'], 1, p.filter((r) => r.demo_buffer > 0)
      .map((r) => ({ x: r.iteration, y: r.juggles_per_episode })));
    setSeries(charts['chart-teacher'], 2, xy((r) => positive(r.imitation_loss)));
    document.getElementById('teacher-figure').hidden = !p.some((r) => r.demo_buffer > 0);
    // The expert-iteration loop (issue 48): the planner's cost and the policy's share.
    const labelled = p.filter((r) => r.expert_labels > 0);
    const share = (num, den) => labelled.map((r) => ({ x: r.iteration, y: r[den] > 0 ? (r[num] || 0) / r[den] : null }));
    setSeries(charts['chart-loop'], 0, labelled.map((r) => ({ x: r.iteration, y: (r.expert_rollout_steps || 0) / r.expert_labels })));
    setSeries(charts['chart-loop'], 1, share('expert_proposal_chosen', 'expert_proposal_tried'));
    setSeries(charts['chart-loop'], 2, share('expert_rescues', 'expert_replans'));
    setSeries(charts['chart-loop'], 3, labelled.map((r) => ({ x: r.iteration, y: positive(r.imitation_fresh_error) })));
    setSeries(charts['chart-loop'], 4, share('expert_proposal_weight_sum', 'expert_proposal_tried'));
    document.getElementById('loop-figure').hidden = labelled.length === 0;
    setSeries(charts['chart-rate'], 0, xy((r) => r.samples_per_s));
    setSeries(charts['chart-rate'], 1, xy((r) => r.sim_s_per_s));
    setSeries(charts['chart-split'], 0, xy((r) => r.wait_s));
    setSeries(charts['chart-split'], 1, xy((r) => r.update_s));
    // Outcomes: the family's names in order, as fractions of the iteration's episodes.
    const names = (status && status.run.outcome_names || []).filter((n) => p.some((r) => r.outcomes && r.outcomes[n]));
    const oc = charts['chart-outcomes'];
    oc.data.datasets = names.map((name, i) => ({
      label: name, parsing: false, pointRadius: 0, borderWidth: 1, fill: i === 0 ? 'origin' : '-1',
      borderColor: PALETTE[i % PALETTE.length], backgroundColor: PALETTE[i % PALETTE.length] + '99',
      data: p.map((r) => {
        const total = Object.values(r.outcomes || {}).reduce((a, b) => a + b, 0);
        return { x: r.iteration, y: total ? (r.outcomes[name] || 0) / total : 0 };
      }),
    }));
    for (const id of ['chart-return', 'chart-juggles', 'chart-length', 'chart-outcomes', 'chart-ppo',
                      'chart-gates', 'chart-teacher', 'chart-loop', 'chart-rate', 'chart-split']) charts[id].update('none');
  }

  function renderEvaluations() {
    const e = evaluations;
    const c = charts['chart-eval'];
    setSeries(c, 0, e.map((v) => ({ x: v.iteration, y: v.p90_juggles })));
    setSeries(c, 1, e.map((v) => ({ x: v.iteration, y: v.median_juggles })));
    setSeries(c, 2, e.map((v) => ({ x: v.iteration, y: v.p10_juggles })));
    c.update('none');
    const latest = e.length ? e[e.length - 1] : null;
    const h = charts['chart-eval-hist'];
    if (latest && latest.juggles && latest.juggles.length) {
      const max = Math.max(...latest.juggles);
      const width = Math.max(1, Math.ceil((max + 1) / 20));
      const bins = new Array(Math.floor(max / width) + 1).fill(0);
      for (const j of latest.juggles) bins[Math.floor(j / width)] += 1;
      h.data.labels = bins.map((_, i) => (width === 1 ? String(i) : (i * width) + '–' + (i * width + width - 1)));
      h.data.datasets[0].data = bins;
      text('eval-hist-caption', 'Latest evaluation (iteration ' + latest.iteration + ', ' + latest.episodes +
           ' episodes): juggles per episode — median ' + num(latest.median_juggles, 1) + ', ≥10: ' + pct(latest.frac_juggles_ge_10));
    } else {
      h.data.labels = [];
      h.data.datasets[0].data = [];
      text('eval-hist-caption', latest
        ? 'Latest evaluation (iteration ' + latest.iteration + '): median ' + num(latest.median_juggles, 1) +
          ' juggles, ≥10: ' + pct(latest.frac_juggles_ge_10) + ' (per-episode counts not recorded)'
        : 'No in-run evaluation yet (evaluation.every_minutes)');
    }
    h.update('none');
  }

  function renderStatus(s) {
    lastStatus = s;
    document.title = 'juggle · ' + s.run.config + ' · ' + s.state.state;
    text('config-name', s.run.config || '(unnamed)');
    const badge = $('state');
    badge.dataset.state = s.state.state;
    text('state', s.state.state);
    text('state-reason', s.state.reason ? '— ' + s.state.reason : '');
    text('family', s.run.family);
    text('seed', String(s.run.seed));
    text('mode', s.run.mode + (s.run.mode === 'asynchronous' ? ' (lag ≤ ' + s.run.max_policy_lag + ')' : ''));
    text('iteration', num(s.progress.iteration));
    text('policy-version', num(s.progress.policy_version));
    text('samples', num(s.progress.samples));
    text('train-time', duration(s.progress.train_s));
    text('uptime', s.live ? duration(s.progress.uptime_s) : '–');
    text('checkpoint-age', s.progress.checkpoint_age_s === null ? (s.live ? 'none yet' : '–')
                                                                 : duration(s.progress.checkpoint_age_s) + ' ago');
    text('workers-live', s.live ? s.workers.live + ' / ' + s.workers.needed + ' needed' : (s.latest ? String(s.latest.workers) : '–'));
    text('samples-per-s', s.latest ? num(s.latest.samples_per_s) : '–');
    text('sim-per-s', s.latest ? num(s.latest.sim_s_per_s, 1) : '–');
    document.body.dataset.iteration = String(s.progress.iteration);
    document.body.dataset.samples = String(s.progress.samples);
    document.body.dataset.policyVersion = String(s.progress.policy_version);
    renderThroughput(s.throughput);
    renderWorkers(s);
    renderGraph(s.graph);
  }

  function renderThroughput(t) {
    text('queue-depth', String(t.queue_depth));
    text('queue-capacity', String(t.queue_capacity));
    const rows = [];
    for (const [reason, n] of Object.entries(t.rejected)) rows.push(['chunks rejected', reason, n]);
    for (const [reason, n] of Object.entries(t.dropped)) rows.push(['unrolls dropped', reason, n]);
    if (t.reconnects) rows.push(['worker reconnects', 'all slots', t.reconnects]);
    const body = $('rejections').tBodies[0];
    body.innerHTML = '';
    if (!rows.length) rows.push(['none', '', '']);
    for (const r of rows) {
      const tr = body.insertRow();
      r.forEach((v) => { tr.insertCell().textContent = typeof v === 'number' ? num(v) : v; });
    }
    const lag = charts['chart-lag'];
    lag.data.labels = t.policy_lag.le.map((b, i) => (i === 0 ? '≤' + b : b === '+Inf' ? '>' + t.policy_lag.le[i - 1] : '≤' + b));
    lag.data.datasets[0].data = t.policy_lag.count;
    lag.update('none');
  }

  function renderWorkers(s) {
    const body = $('workers').tBodies[0];
    body.innerHTML = '';
    const rows = s.workers.rows;
    $('no-workers').hidden = rows.length > 0 || !s.live;
    if (!s.live) text('no-workers', 'recorded run: no live workers');
    for (const w of rows) {
      const tr = body.insertRow();
      tr.dataset.slot = String(w.slot);
      tr.className = 'status-' + w.status.split(' ')[0];
      const cells = [w.slot, w.host, w.incarnation, w.envs, num(w.env_steps_per_s), num(w.heartbeat_age_s, 1) + ' s ago',
                     w.policy_version, num(w.chunks_accepted), num(w.chunks_rejected), num(w.sessions || 1), w.status];
      for (const c of cells) tr.insertCell().textContent = String(c);
    }
  }

  // ---- the control graph (d3 v3 force layout, computed once; styles follow the data) ----
  function successColor(v) {
    if (v === null || v === undefined) return '#bdbdbd';
    return d3.interpolateHsl('#c62828', '#2e7d32')(Math.max(0, Math.min(1, v)));
  }
  function renderGraph(g) {
    text('recent-window', String(g.recent_iterations));
    const container = d3.select('#graph');
    if (!g.nodes.length) {
      if (graphDrawn !== 'none') container.html('<p class="muted" style="padding:8px">this family has no control graph</p>');
      graphDrawn = 'none';
      renderEdgeTable(g);
      return;
    }
    const key = g.nodes.map((n) => n.name).join(',') + '|' + g.edges.map((e) => e.from + '>' + e.to).join(',');
    // Larger graphs (the full one has 23 nodes) get more room and more repulsion.
    const width = Math.min(1100, Math.max(360, 180 * Math.sqrt(g.nodes.length) + 200));
    const height = Math.max(260, width * 0.7);
    const charge = g.nodes.length > 12 ? -2200 : -900;
    if (graphDrawn !== key) {
      container.html('');
      const nodes = g.nodes.map((n, i) => ({ id: i, name: n.name,
        x: width / 2 + 0.35 * width * Math.cos(2 * Math.PI * i / g.nodes.length),
        y: height / 2 + 0.35 * height * Math.sin(2 * Math.PI * i / g.nodes.length) }));
      const links = g.edges.map((e) => ({ source: e.from, target: e.to }));
      const force = d3.layout.force().nodes(nodes).links(links).size([width, height])
        .charge(charge).linkDistance(Math.min(180, width / 3)).gravity(0.08);
      force.start();
      for (let i = 0; i < 300; ++i) force.tick();
      force.stop();
      // Every node inside the drawing, its name and stage included.
      for (const n of nodes) {
        n.x = Math.max(60, Math.min(width - 60, n.x));
        n.y = Math.max(40, Math.min(height - 40, n.y));
      }
      const svg = container.append('svg').attr('width', width).attr('height', height)
        .attr('viewBox', '0 0 ' + width + ' ' + height);
      // Arrowheads in pixels, not scaled by the edge's width.
      svg.append('defs').append('marker').attr('id', 'arrow').attr('viewBox', '0 -5 10 10')
        .attr('refX', 9).attr('refY', 0).attr('markerUnits', 'userSpaceOnUse')
        .attr('markerWidth', 12).attr('markerHeight', 12)
        .attr('orient', 'auto').append('path').attr('d', 'M0,-5L10,0L0,5').attr('fill', '#555');
      const R = 22;
      svg.append('g').attr('class', 'edges').selectAll('path').data(g.edges).enter().append('path')
        .attr('class', 'edge').attr('marker-end', 'url(#arrow)')
        .attr('d', (e) => {
          const a = nodes[e.from], b = nodes[e.to];
          const dx = b.x - a.x, dy = b.y - a.y, d = Math.sqrt(dx * dx + dy * dy) || 1;
          // Curved, so that a->b and b->a are both visible; trimmed to the circles.
          const sx = a.x + dx * R / d, sy = a.y + dy * R / d, tx = b.x - dx * (R + 4) / d, ty = b.y - dy * (R + 4) / d;
          return 'M' + sx + ',' + sy + 'A' + (d * 0.8) + ',' + (d * 0.8) + ' 0 0,1 ' + tx + ',' + ty;
        })
        .append('title');
      const node = svg.append('g').attr('class', 'nodes').selectAll('g').data(g.nodes).enter().append('g')
        .attr('class', (n) => 'node' + (n.initial ? ' initial' : ''))
        .attr('data-name', (n) => n.name)
        .attr('transform', (n, i) => 'translate(' + nodes[i].x + ',' + nodes[i].y + ')');
      node.append('circle').attr('r', R);
      node.append('text').attr('class', 'name').attr('text-anchor', 'middle').attr('dy', -R - 6).text((n) => n.name);
      node.append('text').attr('class', 'rate').attr('text-anchor', 'middle').attr('dy', 4);
      node.append('text').attr('class', 'stage muted').attr('text-anchor', 'middle').attr('dy', R + 14)
        .text((n) => n.stage + (n.initial ? ' · start' : ''));
      node.append('title');
      graphDrawn = key;
    }
    const maxP = d3.max(g.edges, (e) => e.probability) || 1;
    const svg = container.select('svg');
    svg.selectAll('path.edge').data(g.edges)
      .attr('stroke-width', (e) => 1.5 + 8 * e.probability / maxP)
      .attr('stroke', (e) => successColor(e.recent_success !== null ? e.recent_success : e.success))
      .select('title').text((e) => g.nodes[e.from].name + ' → ' + g.nodes[e.to].name + ': weight ' + num(e.weight, 2) +
        ' (w0 ' + num(e.w0, 2) + '), P ' + pct(e.probability) + ', chosen ' + e.chosen + ', completed ' + e.completed +
        ', failed ' + e.failed);
    const node = svg.selectAll('g.node').data(g.nodes);
    node.select('circle').attr('fill', (n) => successColor(n.recent_success !== null ? n.recent_success : n.success));
    node.select('text.rate').text((n) => (n.recent_success !== null ? pct(n.recent_success) : n.success !== null ? pct(n.success) : ''));
    node.select('title').text((n) => n.name + ' (' + n.stage + '): entered ' + n.entered + ', completed ' + n.completed +
      ', failed ' + n.failed + ', success ' + pct(n.success) + ' (recent ' + pct(n.recent_success) + ')');
    renderEdgeTable(g);
  }

  function renderEdgeTable(g) {
    const body = $('edges').tBodies[0];
    body.innerHTML = '';
    for (const e of g.edges) {
      const tr = body.insertRow();
      const cells = [g.nodes[e.from].name + ' → ' + g.nodes[e.to].name, num(e.weight, 2), pct(e.probability),
                     num(e.chosen), num(e.completed), num(e.failed), pct(e.success), pct(e.recent_success)];
      for (const c of cells) tr.insertCell().textContent = c;
    }
  }

  // ---- data ----
  function mergeHistory(h) {
    if (h.stride !== history.stride || h.points.length && history.points.length &&
        h.points[0].seq <= history.last) {
      history.points = [];
    }
    history.points = history.points.concat(h.points);
    history.stride = h.stride;
    history.last = h.last;
  }

  async function getJson(path) {
    const r = await fetch(path, { cache: 'no-store' });
    if (!r.ok) throw new Error(path + ': HTTP ' + r.status);
    return r.json();
  }

  function rendered(status) {
    renderStatus(status);
    renderHistory(status);
    renderEvaluations();
    document.body.dataset.loaded = '1';
  }

  async function refresh() {
    try {
      const [status, h, e] = await Promise.all([
        getJson('api/status'),
        getJson('api/history?since=' + history.last + '&stride=' + history.stride),
        getJson('api/evals'),
      ]);
      mergeHistory(h);
      evaluations = e.evaluations;
      $('fetch-error').hidden = true;
      rendered(status);
      text('updated', 'updated ' + new Date().toLocaleTimeString());
    } catch (err) {
      $('fetch-error').hidden = false;
      $('fetch-error').textContent = 'Cannot reach the learner (' + err.message + '); showing the last data, retrying.';
      $('state').dataset.state = 'unreachable';
      text('state', 'unreachable');
    }
  }

  // An evaluation's page (`juggle dashboard --eval`): its summary and the graph, nothing of
  // training.
  function renderEvaluation(e) {
    document.body.dataset.kind = 'evaluation';
    $('evaluation-section').hidden = false;
    $('graph-evaluation-caption').hidden = false;
    text('evaluation-source', e.source);
    text('eval-episodes', num(e.episodes));
    text('eval-median', num(e.median_juggles, 1));
    text('eval-p10-p90', num(e.p10_juggles, 1) + ' – ' + num(e.p90_juggles, 1));
    text('eval-mean', num(e.mean_juggles, 2));
    text('eval-ge20', pct(e.frac_juggles_ge_20));
    text('eval-length', num(e.mean_episode_s, 1) + ' s');
    text('eval-endings', Object.entries(e.outcomes || {}).map(([k, v]) => k + ' ' + v).join(', ') || '–');
  }

  if (embedded) {
    if (embedded.evaluation) renderEvaluation(embedded.evaluation);
    mergeHistory(embedded.history);
    evaluations = embedded.evals.evaluations;
    rendered(embedded.status);
    text('updated', 'rendered ' + new Date(embedded.status.generated_unix * 1000).toLocaleString());
    document.querySelector('footer').textContent = 'juggle dashboard · recorded from ' + embedded.status.source;
  } else {
    refresh();
    setInterval(() => { if (!document.hidden) refresh(); }, REFRESH_MS);
  }
})();
