// juggle's live page (docs/play.md): draws the frames `juggle play` streams (server-sent
// events from /api/stream) with web/scene.js and sends the user's commands to /api/command.
// URL fragment: #token=T (when the server asks for one), &follow=0, and for tests
// &selftest=1[&skill=NODE][&seed=S]: a scripted run that clicks the page's own controls and
// logs "juggle play selftest: {json}" to the console.
(function () {
  'use strict';
  const hash = new URLSearchParams(window.location.hash.replace(/^#/, ''));
  const token = hash.get('token') || '';
  const withToken = (url) => (token ? `${url}${url.includes('?') ? '&' : '?'}token=${encodeURIComponent(token)}` : url);
  const $ = (id) => document.getElementById(id);

  const state = {
    viewer: 0, controller: 0, follow: hash.get('follow') !== '0', strength: 0.3,
    status: {}, frames: 0, frameTimes: [], lastFrame: null, scene: null, world: null,
    choices: [], listeners: [],
  };

  // ---- Messages and commands.
  function showMessage(text, error) {
    const m = $('message');
    m.textContent = text;
    m.className = error ? 'error' : '';
  }
  async function sendCommand(command) {
    if (!state.viewer) {
      showMessage('not connected yet', true);
      return { ok: false, error: 'not connected yet' };
    }
    let answer;
    try {
      const response = await fetch(withToken(`/api/command?viewer=${state.viewer}`), {
        method: 'POST', headers: { 'Content-Type': 'application/json' },
        body: JSON.stringify(command),
      });
      answer = await response.json();
    } catch (e) {
      answer = { ok: false, error: `the server did not answer: ${e}` };
    }
    if (answer.ok) {
      state.controller = answer.controller;
      showMessage(answer.message, false);
    } else {
      showMessage(answer.error, true);
    }
    updateControlButton();
    return answer;
  }
  function updateControlButton() {
    const mine = state.controller === state.viewer && state.viewer > 0;
    $('claim').textContent = mine ? 'Release control' : 'Take control';
  }

  // ---- Poke directions in the camera's frame: away = the view direction on the ground.
  function pokeDirection(kind) {
    const camera = state.world.camera;
    const forward = new THREE.Vector3();
    camera.getWorldDirection(forward);
    forward.z = 0;
    if (forward.lengthSq() < 1e-9) forward.set(1, 0, 0);
    forward.normalize();
    const right = new THREE.Vector3(forward.y, -forward.x, 0);
    switch (kind) {
      case 'up': return new THREE.Vector3(0, 0, 1);
      case 'down': return new THREE.Vector3(0, 0, -1);
      case 'away': return forward;
      case 'toward': return forward.clone().negate();
      case 'left': return right.clone().negate();
      case 'right': return right;
    }
    return null;
  }
  function poke(direction) {
    const j = direction.clone().normalize().multiplyScalar(state.strength);
    return sendCommand({ cmd: 'poke', impulse: [j.x, j.y, j.z].map((v) => Math.round(v * 1e4) / 1e4) });
  }
  function ballBody() {
    const names = state.scene.bodies;
    const i = names.findIndex((n) => n === 'ball' || n.startsWith('ball'));
    return i;
  }

  // ---- Choices: graph nodes (soccer) or siteswaps (toss).
  function buildChoices(options) {
    const box = $('skills');
    box.innerHTML = '';
    let names = [];
    if (options.kind === 'graph') {
      names = options.steerable;
      $('choice-title').textContent = 'Next skill';
    } else if (options.kind === 'siteswap') {
      names = options.patterns;
      $('choice-title').textContent = 'Next pattern';
      $('wind-row').hidden = false;
      $('siteswap-row').hidden = false;
      $('wind').max = options.max_wind;
      $('wind').min = -options.max_wind;
      $('siteswap-go').addEventListener('click', () =>
        sendCommand({ cmd: 'pattern', siteswap: $('siteswap').value.trim() }));
    }
    state.choices = names;
    const command = (name) => (options.kind === 'graph' ? { cmd: 'skill', node: name }
                                                         : { cmd: 'pattern', siteswap: name });
    names.forEach((name, i) => {
      const b = document.createElement('button');
      b.id = `skill-${name}`;
      b.textContent = i < 9 ? `${i + 1} ${name}` : name;
      b.addEventListener('click', () => sendCommand(command(name)));
      box.appendChild(b);
    });
    if (options.kind === 'graph') {
      const b = document.createElement('button');
      b.id = 'skill-walk';
      b.textContent = '0 walk';
      b.title = 'the adaptive walk chooses';
      b.addEventListener('click', () => sendCommand({ cmd: 'skill', node: 'walk' }));
      box.appendChild(b);
    }
    state.chooseIndex = (i) => (i < names.length ? sendCommand(command(names[i])) : null);
  }

  // The control graph: nodes on a circle, edges as arrows; the current node filled, the
  // chosen one outlined. Clicking a node chooses it.
  function buildGraph(options) {
    const svg = $('graph');
    if (options.kind !== 'graph' || !options.nodes.length) {
      svg.style.display = 'none';
      return;
    }
    const ns = 'http://www.w3.org/2000/svg';
    // An ellipse that leaves room for the names left and right.
    const n = options.nodes.length, w = 284, h = 220, rx = w / 2 - 80, ry = h / 2 - 28;
    const at = (i) => [w / 2 + rx * Math.cos((2 * Math.PI * i) / n - Math.PI / 2),
                       h / 2 + ry * Math.sin((2 * Math.PI * i) / n - Math.PI / 2)];
    svg.innerHTML = '<defs><marker id="arrow" viewBox="0 0 6 6" refX="6" refY="3" ' +
        'markerWidth="6" markerHeight="6" orient="auto"><path d="M0,0L6,3L0,6z" fill="#888"/>' +
        '</marker></defs>';
    for (const [from, to] of options.edges) {
      const [x1, y1] = at(from), [x2, y2] = at(to);
      const line = document.createElementNS(ns, 'line');
      const dx = x2 - x1, dy = y2 - y1, len = Math.hypot(dx, dy) || 1;
      line.setAttribute('x1', x1 + (dx / len) * 9);
      line.setAttribute('y1', y1 + (dy / len) * 9);
      line.setAttribute('x2', x2 - (dx / len) * 9);
      line.setAttribute('y2', y2 - (dy / len) * 9);
      line.setAttribute('stroke', '#888');
      line.setAttribute('marker-end', 'url(#arrow)');
      svg.appendChild(line);
    }
    state.graphNodes = options.nodes.map((node, i) => {
      const [x, y] = at(i);
      const c = document.createElementNS(ns, 'circle');
      c.setAttribute('cx', x);
      c.setAttribute('cy', y);
      c.setAttribute('r', 8);
      c.setAttribute('fill', '#fff');
      c.setAttribute('stroke', '#555');
      c.style.cursor = 'pointer';
      c.addEventListener('click', () => sendCommand({ cmd: 'skill', node: node.name }));
      const title = document.createElementNS(ns, 'title');
      title.textContent = `${node.name} (${node.stage})`;
      c.appendChild(title);
      svg.appendChild(c);
      const t = document.createElementNS(ns, 'text');
      t.setAttribute('x', x + (x < w / 2 ? -10 : 10));
      t.setAttribute('y', y + (y < h / 2 ? -10 : 16));
      t.setAttribute('text-anchor', x < w / 2 ? 'end' : 'start');
      t.textContent = node.name;
      svg.appendChild(t);
      return c;
    });
  }
  function updateGraph(status) {
    if (!state.graphNodes) return;
    const names = state.scene.options.nodes.map((node) => node.name);
    state.graphNodes.forEach((c, i) => {
      c.setAttribute('fill', names[i] === status.node ? '#2a7' : '#fff');
      c.setAttribute('stroke-width', names[i] === status.chosen ? 3 : 1);
    });
    for (const b of $('skills').children) {
      b.classList.toggle('chosen', b.id === `skill-${status.chosen || status.pattern}`);
    }
  }

  // ---- Frames.
  function applyFrame(frame) {
    const S = state.scene.scale;
    const bodies = state.world.bodies;
    for (let b = 0; b < bodies.length; ++b) {
      bodies[b].position.set(frame.x[3 * b] / S, frame.x[3 * b + 1] / S, frame.x[3 * b + 2] / S);
      bodies[b].quaternion.set(frame.q[4 * b + 1] / S, frame.q[4 * b + 2] / S, frame.q[4 * b + 3] / S,
                               frame.q[4 * b] / S).normalize();
    }
  }
  function describe(s) {
    const lines = [
      `t ${(s.t || 0).toFixed(2)} s   episode ${s.episode}   seed ${s.seed}`,
      `speed ${s.speed}x asked, ${(s.achieved || 0).toFixed(2)}x achieved${s.paused ? '   PAUSED' : ''}`,
      `frames ${state.fps.toFixed(1)} per s`,
    ];
    if (s.node !== undefined) lines.push(`node ${s.node}   next skill ${s.chosen}`);
    if (s.pattern !== undefined) {
      lines.push(`pattern ${s.pattern} (${s.schedule})   wind ${(s.wind || 0).toFixed(2)} N`);
      lines.push(`throws ${s.throws}   catches ${s.catches}`);
    }
    if (s.planner) {
      lines.push(`planner: ${s.planner.rollouts} rollouts in the last re-plan` +
                 `${s.planner.rescued ? ' (rescue)' : ''}, cost ${s.planner.cost.toFixed(2)}` +
                 `${state.scene.options.budget ? `, budget ${state.scene.options.budget}` : ''}`);
    }
    if (s.outcome) lines.push(`episode over: ${s.outcome}; a new start follows`);
    lines.push(state.controller === state.viewer ? 'you have control'
               : state.controller ? `viewer ${state.controller} has control` : 'nobody has control');
    return lines.join('\n');
  }
  state.fps = 0;
  function onFrame(frame) {
    frame.status.t = frame.t;
    const now = performance.now();
    state.frames += 1;
    state.frameTimes.push(now);
    while (state.frameTimes.length && now - state.frameTimes[0] > 2000) state.frameTimes.shift();
    state.fps = state.frameTimes.length / 2;
    state.lastFrame = frame;
    state.status = frame.status;
    applyFrame(frame);
    state.dirty = true;
    $('status').textContent = describe(frame.status);
    $('juggles').textContent = String(frame.status.juggles || 0);
    $('pause').textContent = frame.status.paused ? 'Resume' : 'Pause';
    updateGraph(frame.status);
    for (const f of state.listeners.slice()) f(frame);
  }

  function connect() {
    const source = new EventSource(withToken('/api/stream'));
    source.onmessage = (e) => {
      const message = JSON.parse(e.data);
      if (message.type === 'hello') {
        state.viewer = message.viewer;
        state.controller = message.controller;
        updateControlButton();
      } else if (message.type === 'frame') {
        onFrame(message);
      }
    };
    source.onerror = () => { $('status').textContent = 'connection lost; retrying…'; };
  }

  // ---- Controls.
  function setStrength(v) {
    state.strength = Math.min(1, Math.max(0.05, v));
    $('strength').value = String(state.strength);
    $('strength-value').textContent = `${state.strength.toFixed(2)} N·s`;
  }
  function wireControls() {
    $('pause').addEventListener('click', () => sendCommand({ cmd: state.status.paused ? 'resume' : 'pause' }));
    $('restart').addEventListener('click', () => sendCommand({ cmd: 'restart' }));
    $('speed').addEventListener('change', () => sendCommand({ cmd: 'speed', factor: parseFloat($('speed').value) }));
    $('follow').checked = state.follow;
    $('follow').addEventListener('change', () => { state.follow = $('follow').checked; });
    $('claim').addEventListener('click', () => sendCommand({
      cmd: state.controller === state.viewer ? 'release' : 'claim' }));
    $('strength').addEventListener('input', () => setStrength(parseFloat($('strength').value)));
    for (const kind of ['up', 'left', 'away', 'toward', 'right']) {
      $(`poke-${kind}`).addEventListener('click', () => poke(pokeDirection(kind)));
    }
    $('wind').addEventListener('change', () => {
      $('wind-value').textContent = `${parseFloat($('wind').value).toFixed(2)} N`;
      sendCommand({ cmd: 'wind', newtons: parseFloat($('wind').value) });
    });
    const speeds = ['0.1', '0.25', '0.5', '1', '2'];
    window.addEventListener('keydown', (e) => {
      if (e.target && e.target.tagName === 'INPUT' && e.target.type === 'text') return;
      const keyPokes = { ArrowLeft: 'left', ArrowRight: 'right', ArrowUp: 'away',
                         ArrowDown: 'toward', w: 'up', s: 'down' };
      if (e.code === 'Space') sendCommand({ cmd: state.status.paused ? 'resume' : 'pause' });
      else if (e.key === 'r') sendCommand({ cmd: 'restart' });
      else if (keyPokes[e.key]) poke(pokeDirection(keyPokes[e.key]));
      else if (e.key >= '1' && e.key <= '9') state.chooseIndex(Number(e.key) - 1);
      else if (e.key === '0' && state.scene.options.kind === 'graph') sendCommand({ cmd: 'skill', node: 'walk' });
      else if (e.key === '+' || e.key === '=') setStrength(state.strength + 0.05);
      else if (e.key === '-') setStrength(state.strength - 0.05);
      else if (e.key === '[' || e.key === ']') {
        const i = Math.max(0, Math.min(speeds.length - 1,
                           speeds.indexOf($('speed').value) + (e.key === ']' ? 1 : -1)));
        $('speed').value = speeds[i];
        sendCommand({ cmd: 'speed', factor: parseFloat(speeds[i]) });
      } else if (e.key === 'f') { state.follow = !state.follow; $('follow').checked = state.follow; }
      else if (e.key === 'c') $('claim').click();
      else return;
      e.preventDefault();
    });
    // Shift-click: a poke from the ball toward the clicked point (on the plane through the
    // ball that faces the camera).
    state.world.renderer.domElement.addEventListener('click', (e) => {
      if (!e.shiftKey) return;
      const b = ballBody();
      if (b < 0) return;
      const rect = e.target.getBoundingClientRect();
      const ndc = new THREE.Vector2(((e.clientX - rect.left) / rect.width) * 2 - 1,
                                    -((e.clientY - rect.top) / rect.height) * 2 + 1);
      const ray = new THREE.Raycaster();
      ray.setFromCamera(ndc, state.world.camera);
      const ball = state.world.bodies[b].position.clone();
      const normal = new THREE.Vector3();
      state.world.camera.getWorldDirection(normal);
      const plane = new THREE.Plane().setFromNormalAndCoplanarPoint(normal, ball);
      const point = new THREE.Vector3();
      if (ray.ray.intersectPlane(plane, point)) poke(point.sub(ball));
    });
    setStrength(state.strength);
  }

  // ---- Self-test (tests/play_browser_test.cc): the page's own buttons, clicked in order.
  const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
  async function until(predicate, ms) {
    const end = performance.now() + ms;
    while (performance.now() < end) {
      if (predicate()) return true;
      await sleep(20);
    }
    return false;
  }
  // Toss: a pattern chosen by its button and juggled on, the wind set by its slider, and a
  // typed invalid siteswap refused on the page.
  async function siteswapSelftest(report) {
    const pattern = hash.get('pattern') || '531';
    $(`skill-${pattern}`).click();
    report.pattern_acknowledged = await until(() => state.status.pattern === pattern, 3000);
    report.schedule = state.status.schedule;
    const throws0 = state.status.throws;
    await sleep(4000);
    report.throws_after_choice = state.status.throws - throws0;
    report.outcome = state.status.outcome || '';
    report.schedule_after = state.status.schedule;
    $('wind').value = '0.3';
    $('wind').dispatchEvent(new Event('change'));
    report.wind_set = await until(() => Math.abs((state.status.wind || 0) - 0.3) < 1e-9, 3000);
    $('siteswap').value = '543';
    $('siteswap-go').click();
    await until(() => $('message').className === 'error', 3000);
    report.refusal = { text: $('message').textContent, error: $('message').className === 'error' };
  }

  async function selftest() {
    const report = {};
    const fail = (e) => console.log(`juggle play selftest: ${JSON.stringify({ error: String(e), report })}`);
    try {
      await until(() => state.viewer > 0 && state.frames > 5, 10000);
      // 1. Frames per wall second over 3 s.
      const f0 = state.frames, t0 = performance.now();
      await sleep(3000);
      report.fps = (state.frames - f0) / ((performance.now() - t0) / 1000);
      if (state.scene.options.kind === 'siteswap') {
        await siteswapSelftest(report);
        console.log(`juggle play selftest: ${JSON.stringify(report)}`);
        return;
      }
      // 2. A skill choice: chosen at a fresh start, then the node sequence.
      if (hash.has('skill')) {
        // Paused around the choice, so that the start's first steps are the same every run.
        const skill = hash.get('skill');
        await sendCommand({ cmd: 'pause' });
        await sendCommand({ cmd: 'restart', seed: Number(hash.get('seed') || 0) });
        $(`skill-${skill}`).click();
        report.skill_acknowledged = await until(() => state.status.chosen === skill, 3000);
        report.start_node = state.status.node;
        await sendCommand({ cmd: 'resume' });
        const nodes = [];
        const listen = (frame) => {
          if (nodes[nodes.length - 1] !== frame.status.node) nodes.push(frame.status.node);
        };
        state.listeners.push(listen);
        report.skill_reached = await until(() => state.status.node === skill, 8000);
        state.listeners.splice(state.listeners.indexOf(listen), 1);
        report.nodes = nodes;
        report.skill_outcome = state.status.outcome || '';
      }
      // 3. A poke: paused with the ball in flight, an upward poke, then the ball's vertical
      // speed from the frames just before the pause and just after the resume.
      const b = ballBody();
      // The start holds the ball at its apex: poke while it falls, far above the foot (its
      // contact comes at 0.43 s). A busy machine may pause it too late: then again.
      const track = [];
      const record = (frame) => {  // one entry per simulated time
        if (!track.length || track[track.length - 1][0] !== frame.status.t) {
          track.push([frame.status.t, frame.x[3 * b + 2] / state.scene.scale]);
        }
      };
      // Paused and stepped one control step at a time: the same steps however busy the machine.
      await sendCommand({ cmd: 'pause' });
      await sendCommand({ cmd: 'restart', seed: Number(hash.get('seed') || 0) });
      state.listeners.push(record);
      for (let i = 0; i < 8; ++i) {
        const n = track.length;
        await sendCommand({ cmd: 'step' });
        await until(() => track.length > n && /stepped/.test(state.status.message), 2000);
      }
      const before = track.slice(-3);
      $('strength').value = '0.4';
      $('strength').dispatchEvent(new Event('input'));
      $('poke-up').click();
      await until(() => /poked/.test($('message').textContent), 3000);
      report.poke_message = $('message').textContent;
      const mark = track.length;
      for (let i = 0; i < 3; ++i) {
        const n = track.length;
        await sendCommand({ cmd: 'step' });
        await until(() => track.length > n, 2000);
      }
      state.listeners.splice(state.listeners.indexOf(record), 1);
      const after = track.slice(mark, mark + 3);
      await sendCommand({ cmd: 'resume' });
      const v = (a, c) => (c[1] - a[1]) / (c[0] - a[0]);
      report.poke = {
        strength: state.strength,
        vz_before: v(before[0], before[before.length - 1]),
        vz_after: v(after[0], after[after.length - 1]),
        t_before: (before[0][0] + before[before.length - 1][0]) / 2,
        t_after: (after[0][0] + after[after.length - 1][0]) / 2,
        ball_mass: state.scene.ball_mass,
      };
      // 4. A refused command shows its message.
      await sendCommand({ cmd: 'skill', node: 'no_such_node' });
      report.refusal = { text: $('message').textContent, error: $('message').className === 'error' };
      console.log(`juggle play selftest: ${JSON.stringify(report)}`);
    } catch (e) {
      fail(e);
    }
  }

  // ---- Start.
  fetch(withToken('/api/scene')).then((r) => r.json()).then((scene) => {
    state.scene = scene;
    // A little further and higher than the replay's: the ball flies up to 2 m.
    state.world = JuggleScene.create($('view'), scene, { targetZ: 1.05, offset: [1.9, -3.4, 0.45] });
    // Nothing is drawn until the first frame places the bodies.
    for (const b of state.world.bodies) b.visible = false;
    buildChoices(scene.options);
    buildGraph(scene.options);
    wireControls();
    connect();
    // Drawn only when something changed (a frame, the camera, the window): a slow controller
    // streams a few frames a second, and the browser shares the machine's cores with it.
    let placed = false;
    state.dirty = true;
    state.world.controls.addEventListener('change', () => { state.dirty = true; });
    window.addEventListener('resize', () => { state.dirty = true; });
    function tick() {
      if (!placed && state.lastFrame) {
        for (const b of state.world.bodies) b.visible = true;
        state.world.placeCamera();
        placed = true;
      }
      if (state.dirty) {
        state.dirty = false;
        state.world.draw(state.follow);
      }
      requestAnimationFrame(tick);
    }
    requestAnimationFrame(tick);
    document.body.dataset.ready = '1';
    console.log(`juggle play ready: ${scene.family}, ${scene.bodies.length} bodies`);
    if (hash.get('selftest') === '1') selftest();
  }).catch((e) => { $('status').textContent = `cannot load the scene: ${e}`; });
})();
