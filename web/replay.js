// juggle's browser replay (docs/replay_and_export.md), drawn by web/scene.js. Plays the recording embedded
// in the page's #replay-data JSON (export/replay.cc): per-frame world transforms of the bodies,
// the geoms to draw on them, annotation channels, ball contacts and channel changes. No physics
// here. URL fragment: #t=SECONDS (show that time, paused), &speed=X, &follow=0|1.
(function () {
  'use strict';
  const data = JSON.parse(document.getElementById('replay-data').textContent);
  const S = data.scale;
  const nb = data.bodies.length;
  const nf = data.time.length;
  const nc = data.channels.length;
  const times = data.time.map((v) => v / S);
  const duration = times[nf - 1];
  const episodeChannel = data.channels.findIndex((c) => c.name === 'episode');
  const episodeOf = (f) => (episodeChannel >= 0 ? data.values[f * nc + episodeChannel] : 0);

  // ---- Scene (web/scene.js): MuJoCo's z-up world as is; the camera's up is +z.
  const view = document.getElementById('view');
  const world = JuggleScene.create(view, data);
  const bodies = world.bodies;

  // ---- Poses: interpolated between the two frames around t (positions linearly, orientations
  // spherically) within an episode; a reset frame shares its time with the episode's end and
  // wins at that time.
  function frameAt(t) {
    let lo = 0, hi = nf - 1;
    if (t <= times[0]) return 0;
    while (lo < hi) {  // last frame with time <= t
      const mid = (lo + hi + 1) >> 1;
      if (times[mid] <= t) lo = mid; else hi = mid - 1;
    }
    return lo;
  }
  const qa = new THREE.Quaternion(), qb = new THREE.Quaternion();
  function bodyPosition(f, b, out) {
    const k = 3 * (f * nb + b);
    return out.set(data.xpos[k] / S, data.xpos[k + 1] / S, data.xpos[k + 2] / S);
  }
  function bodyQuaternion(f, b, out) {
    const k = 4 * (f * nb + b);
    return out.set(data.xquat[k + 1], data.xquat[k + 2], data.xquat[k + 3], data.xquat[k]).normalize();
  }
  const pa = new THREE.Vector3(), pb = new THREE.Vector3();
  function pose(t) {
    const f = frameAt(t);
    const g = f + 1 < nf && episodeOf(f + 1) === episodeOf(f) && times[f + 1] > times[f] ? f + 1 : f;
    const alpha = g > f ? Math.min(1, Math.max(0, (t - times[f]) / (times[g] - times[f]))) : 0;
    for (let b = 0; b < nb; ++b) {
      bodyPosition(f, b, pa);
      bodyPosition(g, b, pb);
      bodies[b].position.copy(pa.lerp(pb, alpha));
      bodyQuaternion(f, b, qa);
      bodyQuaternion(g, b, qb);
      THREE.Quaternion.slerp(qa, qb, bodies[b].quaternion, alpha);
    }
    return f;
  }

  // ---- Camera: front-right of the character, 3.2 m away, orbiting its root.
  pose(0);
  world.placeCamera();

  // ---- Text: every channel of the current frame.
  const info = document.getElementById('info');
  function describe(f, t) {
    const lines = [`t ${t.toFixed(2)} s   frame ${f}`];
    for (let c = 0; c < nc; ++c) {
      const ch = data.channels[c];
      const v = data.values[f * nc + c];
      let text;
      if (ch.labels.length) text = ch.labels[v] !== undefined ? ch.labels[v] : String(v);
      else text = Number.isInteger(v) ? String(v) : v.toFixed(3);
      lines.push(`${ch.name.padEnd(14)} ${text}`);
    }
    const touching = contactsByFrame.get(f);
    lines.push(`contacts       ${touching ? touching.join(', ') : '-'}`);
    return lines.join('\n');
  }
  const contactsByFrame = new Map();
  for (const [f, ball, other] of data.contacts) {
    if (!contactsByFrame.has(f)) contactsByFrame.set(f, []);
    contactsByFrame.get(f).push(`${ball}-${other}`);
  }

  // ---- Timeline: a row of ball contacts, then one row per categorical channel (a colour per
  // label, the label written where it fits), each row named on the left; episode starts as
  // black lines, endings other than "running" as red ones, the current time as a red bar.
  const timeline = document.getElementById('timeline');
  const rows = data.channels.map((c, i) => i).filter((i) => data.channels[i].labels.length &&
                                                           data.channels[i].name !== 'outcome');
  const rowHeight = 13;
  const margin = 92;  // px for the row names
  timeline.style.height = `${rowHeight * (rows.length + 1) + 2}px`;
  const palette = ['#4e79a7', '#f28e2b', '#59a14f', '#e15759', '#76b7b2', '#edc948', '#b07aa1',
                   '#ff9da7', '#9c755f', '#bab0ac'];
  function drawTimeline(t) {
    const w = timeline.clientWidth, h = timeline.clientHeight;
    if (timeline.width !== w || timeline.height !== h) {
      timeline.width = w;
      timeline.height = h;
    }
    const ctx = timeline.getContext('2d');
    ctx.clearRect(0, 0, w, h);
    ctx.font = '10px monospace';
    ctx.textBaseline = 'middle';
    const x = (time) => margin + (duration > 0 ? (time / duration) * (w - margin - 1) : 0);
    const name = (text, r) => {
      ctx.fillStyle = '#333';
      ctx.fillText(text.slice(0, 14), 2, (r + 0.5) * rowHeight);
    };
    name('contacts', 0);
    rows.forEach((c, r) => {
      const row = r + 1;
      name(data.channels[c].name, row);
      let start = 0;
      for (let f = 1; f <= nf; ++f) {
        if (f === nf || data.values[f * nc + c] !== data.values[start * nc + c]) {
          const value = data.values[start * nc + c];
          const x0 = x(times[start]);
          const width = Math.max(1, x(times[Math.min(f, nf - 1)]) - x0);
          ctx.fillStyle = palette[value % palette.length];
          ctx.fillRect(x0, row * rowHeight, width, rowHeight - 1);
          const label = data.channels[c].labels[value];
          if (label !== undefined && ctx.measureText(label).width + 4 < width) {
            ctx.fillStyle = '#fff';
            ctx.fillText(label, x0 + 2, (row + 0.5) * rowHeight);
          }
          start = f;
        }
      }
    });
    ctx.fillStyle = '#000';
    for (const [f] of data.contacts) ctx.fillRect(x(times[f]), 2, 1, rowHeight - 4);
    for (const [f, channel, label] of data.events) {
      if (channel === 'episode') ctx.fillRect(x(times[f]), 0, 1, h);
      if (channel === 'outcome' && label !== 'running') {
        ctx.fillStyle = '#c00';
        ctx.fillRect(x(times[f]) - 1, 0, 3, h);
        ctx.fillStyle = '#000';
      }
    }
    ctx.fillStyle = '#e00';
    ctx.fillRect(x(t) - 1, 0, 2, h);
  }

  // ---- Playback state and controls.
  const state = { t: 0, playing: true, speed: 1, follow: true };
  const hash = new URLSearchParams(window.location.hash.replace(/^#/, ''));
  if (hash.has('t')) {
    state.t = Math.min(duration, Math.max(0, parseFloat(hash.get('t')) || 0));
    state.playing = false;
  }
  if (hash.has('speed')) state.speed = parseFloat(hash.get('speed')) || 1;
  if (hash.has('follow')) state.follow = hash.get('follow') !== '0';
  const play = document.getElementById('play');
  const scrub = document.getElementById('scrub');
  const clock = document.getElementById('clock');
  const speed = document.getElementById('speed');
  const follow = document.getElementById('follow');
  speed.value = String(state.speed);
  follow.checked = state.follow;
  function setPlaying(p) {
    state.playing = p;
    play.textContent = p ? 'Pause' : 'Play';
  }
  setPlaying(state.playing);
  play.addEventListener('click', () => setPlaying(!state.playing));
  window.addEventListener('keydown', (e) => {
    if (e.code === 'Space') { setPlaying(!state.playing); e.preventDefault(); }
  });
  scrub.addEventListener('input', () => {
    state.t = (scrub.value / 1000) * duration;
    setPlaying(false);
  });
  speed.addEventListener('change', () => { state.speed = parseFloat(speed.value); });
  follow.addEventListener('change', () => { state.follow = follow.checked; });
  timeline.addEventListener('click', (e) => {
    const fraction = (e.offsetX - margin) / Math.max(1, timeline.clientWidth - margin - 1);
    state.t = Math.min(1, Math.max(0, fraction)) * duration;
    setPlaying(false);
  });

  function draw() {
    const f = pose(state.t);
    world.draw(state.follow);
    info.textContent = describe(f, state.t);
    clock.textContent = `${state.t.toFixed(2)} / ${duration.toFixed(2)} s`;
    scrub.value = String(duration > 0 ? Math.round((state.t / duration) * 1000) : 0);
    drawTimeline(state.t);
  }
  let last = null;
  function tick(now) {
    if (last !== null && state.playing) {
      state.t += ((now - last) / 1000) * state.speed;
      if (state.t > duration) state.t = 0;  // loop
    }
    last = now;
    draw();
    requestAnimationFrame(tick);
  }
  draw();
  document.body.dataset.ready = '1';
  console.log(`juggle replay ready: ${nf} frames, ${nb} bodies, ${data.geoms.length} geoms, ` +
              `${duration.toFixed(2)} s`);
  requestAnimationFrame(tick);
})();
