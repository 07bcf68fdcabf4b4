// The replay page: the run data.js holds (window.SALSA_RUN, written by salsa export --html) drawn on a
// canvas in the desktop view's colours (gui-qt/frame/view_*.cpp). Hand-written, no library: the page
// works offline from file://. The URL may say where to start: index.html#t=12.5&speed=5&trails=0&play
//
// Map → page: px = ox + scale·x, py = oy − scale·y (CSS pixels; the canvas's top left is the page's),
// with ox, oy and scale kept in <body>'s data-ox, data-oy and data-scale (and the window's size they are
// for in data-viewport, WxH), as are data-time, data-frame and data-found after each picture, and
// data-ready once the run is read.
"use strict";
(() => {
  const run = window.SALSA_RUN;
  // The arrays, frame-major: position (x, y per drone, NaN: not there), heading (a 240th of a turn,
  // counter-clockwise from +x, 255: still), look (status 0 flying, 1 landed, 2 failed, 3 removed, +4
  // when its camera failed), group (255: none); targets (x, y) and found (s, NaN: never).
  const bytes = (s) => {
    const b = atob(s), out = new Uint8Array(b.length);
    for (let i = 0; i < b.length; ++i) out[i] = b.charCodeAt(i);
    return out;
  };
  const times = new Float64Array(bytes(run.times).buffer), position = new Float32Array(bytes(run.position).buffer);
  const heading = bytes(run.heading), look = bytes(run.look), group = bytes(run.group);
  const targets = new Float32Array(bytes(run.targets).buffer), found = new Float64Array(bytes(run.found).buffer);
  const N = run.drones, F = run.frames, end = F ? times[F - 1] : 0;
  const byFound = [...found.keys()].filter((i) => found[i] === found[i]).sort((a, b) => found[a] - found[b]);

  const colour = { outside: "#d8d4cc", map: "#f4f1ea", obstacle: "#6b6b6b", edge: "#3c3c3c", found: "#2e9e48",
                   unfound: "#9a9a9a", spawn: "#8c1f6b", drone: "#1f3f8c" };
  // Okabe & Ito's colour-blind-safe set, as the desktop and the plots colour several groups.
  const okabeIto = [[230, 159, 0], [0, 114, 178], [0, 158, 115], [213, 94, 0], [86, 180, 233], [204, 121, 167], [240, 228, 66]];
  const rgb = (c, k = 1) => `rgb(${c.map((v) => Math.round(v / k)).join(",")})`;
  const several = run.groups.length > 1;
  const groupColour = (g) => (several ? rgb(okabeIto[g % 7]) : colour.drone);
  const trailSeconds = 20;  // about the desktop's 64 samples
  const $ = (id) => document.getElementById(id);
  const canvas = $("view"), ctx = canvas.getContext("2d"), body = document.body;
  let t = 0, playing = false, speed = 1, trails = true, view = { scale: 1, ox: 0, oy: 0 }, still = null, lastTick = 0;

  /// The last frame at or before time s (0 before the first).
  const frameAt = (s) => {
    let lo = 0, hi = F - 1;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (times[mid] <= s) lo = mid; else hi = mid - 1;
    }
    return lo;
  };
  const px = (x, y) => [view.ox + view.scale * x, view.oy - view.scale * y];
  /// Drone d at time s, in pixels: between two frames it moves in a straight line.
  const dronePx = (f, d, s) => {
    const i = 2 * (f * N + d);
    let x = position[i], y = position[i + 1];
    if (f + 1 < F && s > times[f]) {
      const j = i + 2 * N, a = (s - times[f]) / (times[f + 1] - times[f]);
      if (position[j] === position[j]) x += a * (position[j] - x), y += a * (position[j + 1] - y);
    }
    return px(x, y);
  };

  const path = (xy, close) => {
    ctx.beginPath();
    for (let k = 0; k < xy.length; k += 2) ctx.lineTo(...px(xy[k], xy[k + 1]));
    if (close) ctx.closePath();
  };
  const disc = (x, y, r, fill) => {
    ctx.fillStyle = fill;
    ctx.beginPath();
    ctx.arc(x, y, r, 0, 2 * Math.PI);
    ctx.fill();
  };

  /// What does not move, drawn again when the view does: the map, every target unfound, the bases.
  function drawStill() {
    const [x0, y0, x1, y1] = run.bounds, s = view.scale;
    ctx.fillStyle = colour.outside;
    ctx.fillRect(0, 0, canvas.clientWidth, canvas.clientHeight);
    ctx.fillStyle = colour.map;
    ctx.fillRect(...px(x0, y1), (x1 - x0) * s, (y1 - y0) * s);
    ctx.strokeStyle = colour.edge, ctx.fillStyle = colour.obstacle, ctx.lineWidth = 1.5;
    for (const o of run.obstacles) path(o, true), ctx.fill(), ctx.stroke();
    ctx.lineWidth = Math.max(2, 0.5 * s);
    for (const o of run.hollow) path(o, true), ctx.stroke();
    for (const l of run.lines) path(l, false), ctx.stroke();
    ctx.lineWidth = 2;
    ctx.strokeRect(...px(x0, y1), (x1 - x0) * s, (y1 - y0) * s);
    const r = targetRadius();
    for (let i = 0; i < targets.length / 2; ++i) disc(...px(targets[2 * i], targets[2 * i + 1]), r, colour.unfound);
    ctx.lineWidth = 2;
    run.groups.forEach((g, k) => {  // each group's base, in its colour when there are several
      const [x, y] = px(...g.base);
      ctx.strokeStyle = several ? rgb(okabeIto[k % 7], 1.3) : colour.spawn;
      ctx.beginPath();
      ctx.arc(x, y, 7, 0, 2 * Math.PI);
      ctx.moveTo(x - 10, y), ctx.lineTo(x + 10, y), ctx.moveTo(x, y - 10), ctx.lineTo(x, y + 10);
      ctx.stroke();
    });
  }
  const targetRadius = () => Math.max(1, run.target_radius * view.scale);

  /// A stopped drone's ✕ with a white rim.
  function cross(x, y, c) {
    for (const [pen, w] of [["#fff", 5], [c, 2.5]]) {
      ctx.strokeStyle = pen, ctx.lineWidth = w;
      ctx.beginPath();
      ctx.moveTo(x - 5, y - 5), ctx.lineTo(x + 5, y + 5), ctx.moveTo(x - 5, y + 5), ctx.lineTo(x + 5, y - 5);
      ctx.stroke();
    }
  }

  function draw() {
    const f = frameAt(t);
    ctx.drawImage(still, 0, 0, canvas.clientWidth, canvas.clientHeight);
    let shown = 0;
    for (; shown < byFound.length && found[byFound[shown]] <= t; ++shown)
      disc(...px(targets[2 * byFound[shown]], targets[2 * byFound[shown] + 1]), targetRadius(), colour.found);
    ctx.lineCap = "round";
    if (trails) {  // a line per group through each drone's positions of the last trailSeconds, to where it is
      const first = frameAt(t - trailSeconds);
      ctx.globalAlpha = 85 / 255, ctx.lineWidth = 1;
      run.groups.forEach((_, g) => {
        ctx.strokeStyle = groupColour(g);
        ctx.beginPath();
        for (let d = 0; d < N; ++d) {
          if (group[f * N + d] !== g || (look[f * N + d] & 3) === 3) continue;
          let on = false;
          for (let k = first; k <= f; ++k) {
            const i = 2 * (k * N + d);
            if (position[i] !== position[i]) { on = false; continue; }
            const [x, y] = px(position[i], position[i + 1]);
            on ? ctx.lineTo(x, y) : ctx.moveTo(x, y);
            on = true;
          }
          if (on) ctx.lineTo(...dronePx(f, d, t));
        }
        ctx.stroke();
      });
      ctx.globalAlpha = 1;
    }
    for (let d = 0; d < N; ++d) {  // a disc (a ring when its camera failed) with its velocity tick; a ✕ where it stopped
      const k = f * N + d, status = look[k] & 3, g = group[k];
      if (status === 3 || position[2 * k] !== position[2 * k]) continue;
      const [x, y] = dronePx(f, d, t), c = groupColour(g === 255 ? 0 : g);
      if (status !== 0) { cross(x, y, c); continue; }
      const r = Math.max(3, (g === 255 ? 1 : run.groups[g].radius) * view.scale);
      if (look[k] & 4) {
        ctx.strokeStyle = c, ctx.lineWidth = 2;
        ctx.beginPath();
        ctx.arc(x, y, r - 1, 0, 2 * Math.PI);
        ctx.stroke();
      } else disc(x, y, r, c);
      if (heading[k] !== 255) {
        const a = (heading[k] / 240) * 2 * Math.PI;
        ctx.strokeStyle = c, ctx.lineWidth = 1.5;
        ctx.beginPath();
        ctx.moveTo(x, y), ctx.lineTo(x + Math.cos(a) * (r + 5), y - Math.sin(a) * (r + 5));
        ctx.stroke();
      }
    }
    $("time").textContent = `${t.toFixed(1)} / ${end.toFixed(1)} s`;
    $("found").textContent = `found ${shown} of ${targets.length / 2}`;
    $("timeline").value = t;
    Object.assign(body.dataset, { time: t, frame: f, found: shown });
  }

  /// Sizes the canvas to the window at the screen's resolution and fits the map into it (20 px around).
  function resize() {
    const w = canvas.clientWidth, h = canvas.clientHeight, dpr = window.devicePixelRatio || 1;
    canvas.width = Math.round(w * dpr), canvas.height = Math.round(h * dpr);
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    const [x0, y0, x1, y1] = run.bounds;
    const scale = Math.max(1e-9, Math.min((w - 40) / (x1 - x0), (h - 40) / (y1 - y0)));
    moved({ scale, ox: (w - (x1 - x0) * scale) / 2 - x0 * scale, oy: (h + (y1 - y0) * scale) / 2 + y0 * scale });
  }
  /// The view is now `v`: the still layer is drawn again and kept, then the picture.
  function moved(v) {
    view = v;
    Object.assign(body.dataset, view, { viewport: `${innerWidth}x${innerHeight}` });
    drawStill();
    still = still || document.createElement("canvas");
    still.width = canvas.width, still.height = canvas.height;
    still.getContext("2d").drawImage(canvas, 0, 0);
    draw();
  }
  // The wheel zooms about the pointer, a drag pans, a double click fits the map again.
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    const k = Math.exp(-e.deltaY / 500), x = e.offsetX, y = e.offsetY;
    moved({ scale: view.scale * k, ox: x - (x - view.ox) * k, oy: y - (y - view.oy) * k });
  }, { passive: false });
  canvas.addEventListener("pointermove", (e) => {
    if (e.buttons & 1) moved({ scale: view.scale, ox: view.ox + e.movementX, oy: view.oy + e.movementY });
  });
  canvas.addEventListener("dblclick", resize);

  const seek = (s) => { t = Math.min(end, Math.max(times[0] || 0, s)); draw(); };
  function setPlaying(on) {
    playing = on && F > 1;
    $("play").textContent = playing ? "❚❚" : "▶";
    if (playing) {
      if (t >= end) t = times[0];
      lastTick = performance.now();
      requestAnimationFrame(tick);
    }
  }
  function tick(now) {
    if (!playing) return;
    t = Math.min(end, t + ((now - lastTick) / 1000) * speed);
    lastTick = now;
    draw();
    if (t >= end) setPlaying(false); else requestAnimationFrame(tick);
  }
  /// To the next (+1) or previous (−1) logged frame.
  function step(dir) {
    setPlaying(false);
    const f = frameAt(t);
    seek(dir > 0 ? times[Math.min(F - 1, f + 1)] : times[times[f] < t ? f : Math.max(0, f - 1)]);
  }
  /// index.html#t=12.5&speed=5&trails=0&play
  function fromUrl() {
    const p = new URLSearchParams(location.hash.slice(1));
    if (p.has("speed")) speed = Number(p.get("speed")) || 1, $("speed").value = String(speed);
    if (p.has("trails")) trails = p.get("trails") !== "0", $("trails").checked = trails;
    seek(p.has("t") ? Number(p.get("t")) || 0 : t);
    setPlaying(p.has("play"));
  }

  document.title = `salsa replay: ${run.test}`;
  $("title").textContent = `${run.test} (seed ${run.seed})`;
  if (several)  // with several groups, each group's colour and name
    run.groups.forEach((g, k) => {
      const entry = document.createElement("span"), dot = document.createElement("i");
      dot.style.background = groupColour(k);
      entry.append(dot, g.name);
      $("legend").append(entry);
    });
  $("timeline").min = times[0] || 0, $("timeline").max = end;
  $("timeline").addEventListener("input", (e) => { setPlaying(false); seek(Number(e.target.value)); });
  $("play").addEventListener("click", () => setPlaying(!playing));
  $("back").addEventListener("click", () => step(-1));
  $("forward").addEventListener("click", () => step(1));
  $("speed").addEventListener("change", (e) => { speed = Number(e.target.value); });
  $("trails").addEventListener("change", (e) => { trails = e.target.checked; draw(); });
  document.addEventListener("keydown", (e) => {
    if (e.target.tagName === "SELECT") return;
    if (e.key === " ") setPlaying(!playing), e.preventDefault();
    else if (e.key === "ArrowLeft") step(-1), e.preventDefault();
    else if (e.key === "ArrowRight") step(1), e.preventDefault();
  });
  window.addEventListener("hashchange", fromUrl);
  new ResizeObserver(resize).observe(canvas);
  resize();
  fromUrl();
  body.dataset.ready = "1";
})();
