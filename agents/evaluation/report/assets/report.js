"use strict";
// The report's episode list and replay player. Data: #report-data (the run, the episode list, each
// recorded episode's scene) and #report-trajectories (one base64 zlib string per recorded episode,
// decoded only when the episode is opened). No network: everything is in this file.
(function () {
  const data = JSON.parse(document.getElementById("report-data").textContent);
  const packed = JSON.parse(document.getElementById("report-trajectories").textContent);
  const col = Object.fromEntries(data.columns.map((name, i) => [name, i]));
  const episodes = data.episodes;
  const PAGE = 300;
  const COLOURS = { background: "rgb(250,250,247)", wall: "rgb(60,60,60)", static: "rgb(110,110,118)", obstacle: "rgb(214,96,77)",
    human: "rgb(197,27,125)", robot: "rgb(52,101,164)", heading: "rgb(250,250,247)", trail: "rgb(120,160,210)", goal: "rgb(46,160,67)",
    waypoint: "rgb(240,170,20)", plan: "rgb(150,90,190)", beam: "rgb(170,205,235)" };
  // a multi-robot episode's robots by their status: its codes' names come with the page (pathplan_env.records.multi.STATUS)
  const STATUS_NAMES = data.status_names || [];
  const STATUS_COLOURS = STATUS_NAMES.map((name) => ({ active: COLOURS.robot, arrived: COLOURS.goal, left: "rgb(170,170,170)",
    collided: "rgb(120,20,20)", timeout: COLOURS.waypoint })[name] || COLOURS.robot);
  const $ = (id) => document.getElementById(id);
  const state = { shown: PAGE, matching: [], views: [], step: 0, playing: false, speed: 1, last: 0, carry: 0, opened: -1 };
  window.report = state; // for tests and the curious: the player's state

  // -- the run's configuration line --------------------------------------------------------------
  const c = data.config;
  $("run-config").textContent = [`agents: ${(c.agents || []).join(", ")}`, `scenarios: ${(c.scenarios || []).join(", ")}`,
    `Δd: ${(c.delta_d || []).map((d) => (d === null ? "own" : d)).join(", ")}`, `${c.episodes} episodes a cell`,
    `seed ${c.seed}, ${c.split} split`, `${episodes.length} episodes in all`].join(" · ");

  // -- the episode list and its filters -------------------------------------------------------
  const FILTERS = { agent: "f-agent", scenario: "f-scenario", delta_d: "f-delta", outcome: "f-outcome" };
  const OUTCOMES = data.multi ? ["success", "collision", "timeout"] : ["success", "collision", "timeout", "limit: lost", "limit: undetermined"];
  function fillSelect(select, values) {
    select.innerHTML = "";
    for (const v of ["all", ...values]) {
      const option = document.createElement("option");
      option.value = option.textContent = String(v);
      select.appendChild(option);
    }
  }
  for (const [name, id] of Object.entries(FILTERS)) {
    const values = name === "outcome" ? OUTCOMES : [...new Set(episodes.map((e) => e[col[name]]))].sort();
    fillSelect($(id), values);
    $(id).addEventListener("change", () => { state.shown = PAGE; renderList(); });
  }
  const SHOWN = data.shown || ["agent", "scenario", "delta_d", "episode", "seed", "outcome", "limit", "steps", "path_length", "min_clearance"];
  $("episode-table").tHead.innerHTML = "<tr>" + SHOWN.map((n) => `<th>${n === "delta_d" ? "Δd" : n.replace("_", " ")}</th>`).join("") + "</tr>";

  function matches(e) {
    for (const [name, id] of Object.entries(FILTERS)) {
      const want = $(id).value;
      if (want === "all") continue;
      if (name === "outcome") {
        if (want.startsWith("limit: ") ? e[col.limit] !== want.slice(7) : e[col.outcome] !== want) return false;
      } else if (String(e[col[name]]) !== want) return false;
    }
    return true;
  }
  function renderList() {
    state.matching = [];
    episodes.forEach((e, i) => { if (matches(e)) state.matching.push(i); });
    const body = $("episode-table").tBodies[0];
    const rows = state.matching.slice(0, state.shown).map((i) => {
      const e = episodes[i];
      const cells = SHOWN.map((n) => {
        const v = e[col[n]];
        const cls = n === "outcome" ? ` class="outcome-${v}"` : typeof v === "number" ? ' class="num"' : "";
        return `<td${cls}>${v === null ? "-" : escapeHtml(String(v))}</td>`;
      });
      const recorded = e[col.record] >= 0;
      return `<tr data-index="${i}" class="${recorded ? "" : "unrecorded"}${i === state.opened ? " open" : ""}"` +
        `${recorded ? "" : ' title="not recorded: run with --record to replay it"'}>${cells.join("")}</tr>`;
    });
    body.innerHTML = rows.join("");
    const count = $("episode-count");
    count.dataset.count = String(state.matching.length);
    count.textContent = `${state.matching.length} of ${episodes.length} episodes` + (data.recorded ? "" : " (not recorded: no replay)");
    $("more").hidden = state.matching.length <= state.shown;
  }
  function escapeHtml(text) {
    return text.replace(/[&<>"]/g, (ch) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" })[ch]);
  }
  $("more").addEventListener("click", () => { state.shown += PAGE; renderList(); });
  $("episode-table").tBodies[0].addEventListener("click", (event) => {
    const row = event.target.closest("tr");
    if (row && !row.classList.contains("unrecorded")) openEpisode(Number(row.dataset.index));
  });

  // -- decoding a trajectory ----------------------------------------------------------------------
  const decoded = new Map();
  async function decode(record) {
    if (decoded.has(record)) return decoded.get(record);
    const bytes = Uint8Array.from(atob(packed[record]), (ch) => ch.charCodeAt(0));
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate"));
    const buffer = await new Response(stream).arrayBuffer();
    const scene = data.scenes[record];
    let at = 16; // past the four counts
    const u32 = (count) => { const a = new Uint32Array(buffer, at, count); at += 4 * count; return a; };
    const u16 = (count) => { const a = new Uint16Array(buffer, at, count); at += 2 * count; return a; };
    const [xmin, ymin, xmax, ymax] = scene.bounds;
    const X = (q) => (q === 65535 ? NaN : xmin + (q / 65534) * (xmax - xmin));
    const Y = (q) => (q === 65535 ? NaN : ymin + (q / 65534) * (ymax - ymin));
    const points = (a) => { const out = new Float64Array(a.length); for (let i = 0; i < a.length; i += 2) { out[i] = X(a[i]); out[i + 1] = Y(a[i + 1]); } return out; };
    const angles = (a) => Float64Array.from(a, (q) => -Math.PI + (q / 65534) * 2 * Math.PI);
    const counts = new Uint32Array(buffer, 0, 4);
    const episode = scene.multi ? decodeMulti(record, scene, counts, u32, u16, points, angles) : decodeSingle(record, scene, counts, u32, u16, points, angles);
    decoded.set(record, episode);
    return episode;
  }

  function decodeSingle(record, scene, [rows, n, p, beamCount], u32, u16, points, angles) { // pathplan_env.records.compact.pack's layout
    const offsets = u32(rows + 1);
    const robot = points(u16(rows * 2));
    const heading = angles(u16(rows));
    const obstacles = points(u16(rows * n * 2));
    const waypoint = points(u16(rows * 2));
    const clearance = Float64Array.from(u16(rows), (q) => q / 1000);
    const plan = points(u16(p * 2));
    const beams = points(u16(rows * beamCount * 2)); // a lidar's beam ends, where they were recorded
    return { record, scene, rows, n, offsets, robot, heading, obstacles, waypoint, clearance, plan, beams, beamCount };
  }

  function decodeMulti(record, scene, [rows, robots, n, p], u32, u16, points, angles) { // pathplan_env.records.compact.pack_multi_episode's layout
    const offsets = u32(rows * robots + 1);
    const pose = points(u16(rows * robots * 2));
    const heading = angles(u16(rows * robots));
    const status = u16(rows * robots), hit = u16(rows * robots);
    const obstacles = points(u16(rows * n * 2));
    const plan = points(u16(p * 2));
    return { record, scene, rows, robots, n, offsets, pose, heading, status, hit, obstacles, plan };
  }

  // -- drawing one frame ----------------------------------------------------------------------------
  // the canvas sized to its box, the arena, its walls and polygons and the obstacles at step k drawn
  // (``under`` first, given ``line``); returns the drawing helpers in the world's metres
  function surface(view, k, under) {
    const { canvas, episode: ep } = view;
    const s = ep.scene;
    const [xmin, ymin, xmax, ymax] = s.bounds;
    const css = canvas.clientWidth || 300;
    const ratio = window.devicePixelRatio || 1;
    const scale = (css * ratio) / (xmax - xmin);
    const width = Math.round((xmax - xmin) * scale), height = Math.round((ymax - ymin) * scale);
    if (canvas.width !== width || canvas.height !== height) { canvas.width = width; canvas.height = height; }
    const g = canvas.getContext("2d");
    const sx = (x) => (x - xmin) * scale, sy = (y) => (ymax - y) * scale;
    const circle = (x, y, r, fill) => { g.beginPath(); g.arc(sx(x), sy(y), Math.max(2, r * scale), 0, 2 * Math.PI); g.fillStyle = fill; g.fill(); };
    const line = (pts, colour, w) => {
      g.beginPath(); let started = false;
      for (const [x, y] of pts) { if (Number.isNaN(x)) continue; if (started) g.lineTo(sx(x), sy(y)); else { g.moveTo(sx(x), sy(y)); started = true; } }
      g.strokeStyle = colour; g.lineWidth = w; g.stroke();
    };
    g.fillStyle = COLOURS.background; g.fillRect(0, 0, width, height);
    g.strokeStyle = COLOURS.wall; g.lineWidth = 3 * ratio; g.strokeRect(0, 0, width, height);
    g.lineCap = "round"; g.lineJoin = "round";
    if (under) under(line);
    for (const [a, b] of s.walls) line([a, b], COLOURS.static, Math.max(2 * ratio, s.wall_thickness * scale));
    for (const poly of s.polygons) {
      g.beginPath(); poly.forEach(([x, y], i) => (i ? g.lineTo(sx(x), sy(y)) : g.moveTo(sx(x), sy(y)))); g.closePath();
      g.fillStyle = COLOURS.static; g.fill();
    }
    const base = k * ep.n * 2;
    for (let i = 0; i < ep.n; i++) circle(ep.obstacles[base + 2 * i], ep.obstacles[base + 2 * i + 1], s.radii[i], s.humans[i] ? COLOURS.human : COLOURS.obstacle);
    const ring = ([x, y], r) => { // a goal
      g.beginPath(); g.arc(sx(x), sy(y), Math.max(3, r * scale), 0, 2 * Math.PI); g.strokeStyle = COLOURS.goal; g.lineWidth = 2 * ratio; g.stroke();
    };
    return { g, sx, sy, scale, ratio, circle, line, ring };
  }

  // the caption's start: which episode, which step
  function captionHead(view, k) {
    const e = episodes[view.index], ep = view.episode;
    return `${e[col.agent]} · ${e[col.scenario]} · Δd ${e[col.delta_d]} · episode ${e[col.episode]} (seed ${e[col.seed]}) · ` +
      `step ${k} of ${ep.rows - 1}, t = ${(k * ep.scene.dt).toFixed(2)} s`;
  }

  function draw(view, k) {
    const { episode: ep } = view;
    const s = ep.scene;
    if (s.multi) return drawMulti(view, k);
    k = Math.min(k, ep.rows - 1);
    const [x, y] = [ep.robot[2 * k], ep.robot[2 * k + 1]];
    const { scale, ratio, circle, line, ring } = surface(view, k, (line) => { // a lidar's beams, under the world
      for (let j = 0; j < ep.beamCount; j++) {
        const at = (k * ep.beamCount + j) * 2;
        line([[x, y], [ep.beams[at], ep.beams[at + 1]]], COLOURS.beam, 1);
      }
    });
    const [gx, gy] = s.goal;
    ring(s.goal, s.goal_radius);
    line([[gx - 6 / scale * ratio, gy], [gx + 6 / scale * ratio, gy]], COLOURS.goal, 2 * ratio);
    line([[gx, gy - 6 / scale * ratio], [gx, gy + 6 / scale * ratio]], COLOURS.goal, 2 * ratio);
    const trail = [];
    for (let j = 0; j <= k; j++) trail.push([ep.robot[2 * j], ep.robot[2 * j + 1]]);
    if (trail.length > 1) line(trail, COLOURS.trail, 2 * ratio);
    const a = ep.offsets[k], b = ep.offsets[k + 1];
    if (b - a > 1) { const pts = []; for (let j = a; j < b; j++) pts.push([ep.plan[2 * j], ep.plan[2 * j + 1]]); line(pts, COLOURS.plan, 2 * ratio); }
    const [wx, wy] = [ep.waypoint[2 * k], ep.waypoint[2 * k + 1]];
    if (!Number.isNaN(wx)) { line([[x, y], [wx, wy]], COLOURS.waypoint, 1 * ratio); circle(wx, wy, 4 / scale * ratio, COLOURS.waypoint); }
    circle(x, y, s.robot_radius, COLOURS.robot);
    let angle = s.turns ? ep.heading[k] : NaN; // a holonomic robot faces where it last moved
    if (!s.turns) for (let j = k; j > 0 && Number.isNaN(angle); j--) {
      const dx = ep.robot[2 * j] - ep.robot[2 * j - 2], dy = ep.robot[2 * j + 1] - ep.robot[2 * j - 1];
      if (Math.hypot(dx, dy) > 1e-6) angle = Math.atan2(dy, dx);
    }
    if (!Number.isNaN(angle)) line([[x, y], [x + s.robot_radius * Math.cos(angle), y + s.robot_radius * Math.sin(angle)]], COLOURS.heading,
      Math.max(2, 0.25 * s.robot_radius * scale));
    const e = episodes[view.index];
    view.caption.textContent = `${captionHead(view, k)}, clearance ${ep.clearance[k].toFixed(3)} m` + (k === ep.rows - 1 ? ` · ${e[col.outcome]}` : "");
  }

  function drawMulti(view, k) {
    const { episode: ep } = view;
    const s = ep.scene, K = ep.robots;
    k = Math.min(k, ep.rows - 1);
    const { g, sx, sy, scale, ratio, circle, line, ring } = surface(view, k);
    const label = (x, y, text, colour) => { g.fillStyle = colour; g.font = `${Math.round(11 * ratio)}px sans-serif`; g.textAlign = "center";
      g.textBaseline = "middle"; g.fillText(text, sx(x), sy(y)); };
    const at = (j, i) => 2 * (j * K + i);
    const counts = STATUS_NAMES.map(() => 0);
    for (let i = 0; i < K; i++) {
      const r = s.robots[i], [gx, gy] = r.goal;
      ring(r.goal, r.goal_radius);
      label(gx, gy, String(i), COLOURS.goal);
      const trail = [];
      for (let j = 0; j <= k; j++) trail.push([ep.pose[at(j, i)], ep.pose[at(j, i) + 1]]);
      if (trail.length > 1) line(trail, COLOURS.trail, 2 * ratio);
      if (k + 1 < ep.rows) { // the plan the robot flies next (the one that leads to row k + 1), as the command line's frames
        const a = ep.offsets[(k + 1) * K + i], b = ep.offsets[(k + 1) * K + i + 1];
        if (b - a > 1) { const pts = []; for (let j = a; j < b; j++) pts.push([ep.plan[2 * j], ep.plan[2 * j + 1]]); line(pts, COLOURS.plan, 1.5 * ratio); }
      }
    }
    for (let i = 0; i < K; i++) {
      const r = s.robots[i], status = ep.status[k * K + i];
      counts[status] += 1;
      if (STATUS_NAMES[status] === "left") continue; // it left the world
      const [x, y] = [ep.pose[at(k, i)], ep.pose[at(k, i) + 1]];
      circle(x, y, r.radius, STATUS_COLOURS[status]);
      if (r.turns) line([[x, y], [x + r.radius * Math.cos(ep.heading[k * K + i]), y + r.radius * Math.sin(ep.heading[k * K + i])]], COLOURS.heading, Math.max(2, 0.2 * r.radius * scale));
      else label(x, y, String(i), COLOURS.heading);
    }
    const e = episodes[view.index];
    view.caption.textContent = `${captionHead(view, k)} · ` + counts.map((c, j) => (c ? `${c} ${STATUS_NAMES[j]}` : "")).filter(Boolean).join(", ") +
      (k === ep.rows - 1 ? ` · ${e[col.outcome]}` : "");
  }

  // -- CSV of a view's episode, built here -------------------------------------------------------
  const csvNumber = (v) => (Number.isNaN(v) ? "" : v.toFixed(4));
  function obstacleHead(ep) {
    const head = [];
    for (let i = 0; i < ep.n; i++) head.push(`${ep.scene.humans[i] ? "human" : "obstacle"}${i}_x`, `${ep.scene.humans[i] ? "human" : "obstacle"}${i}_y`);
    return head;
  }
  function obstacleCells(ep, k) {
    const cells = [];
    for (let i = 0; i < ep.n; i++) cells.push(csvNumber(ep.obstacles[(k * ep.n + i) * 2]), csvNumber(ep.obstacles[(k * ep.n + i) * 2 + 1]));
    return cells;
  }

  function csvOf(ep) {
    if (ep.scene.multi) return csvOfMulti(ep);
    const head = ["step", "time", "robot_x", "robot_y", "robot_heading", "waypoint_x", "waypoint_y", "clearance", ...obstacleHead(ep)];
    const lines = [head.join(",")];
    const f = csvNumber;
    for (let k = 0; k < ep.rows; k++) {
      const row = [k, (k * ep.scene.dt).toFixed(3), f(ep.robot[2 * k]), f(ep.robot[2 * k + 1]), f(ep.heading[k]), f(ep.waypoint[2 * k]), f(ep.waypoint[2 * k + 1]), f(ep.clearance[k]),
        ...obstacleCells(ep, k)];
      lines.push(row.join(","));
    }
    return lines.join("\n") + "\n";
  }

  function csvOfMulti(ep) {
    const K = ep.robots, head = ["step", "time"];
    ep.scene.robots.forEach((r) => head.push(`${r.name}_x`, `${r.name}_y`, `${r.name}_status`));
    head.push(...obstacleHead(ep));
    const lines = [head.join(",")];
    for (let k = 0; k < ep.rows; k++) {
      const row = [k, (k * ep.scene.dt).toFixed(3)];
      for (let i = 0; i < K; i++) row.push(ep.pose[2 * (k * K + i)].toFixed(4), ep.pose[2 * (k * K + i) + 1].toFixed(4), STATUS_NAMES[ep.status[k * K + i]]);
      row.push(...obstacleCells(ep, k));
      lines.push(row.join(","));
    }
    return lines.join("\n") + "\n";
  }

  // -- the player ---------------------------------------------------------------------------------
  async function makeView(index) {
    const e = episodes[index];
    const ep = await decode(e[col.record]);
    const box = document.createElement("div");
    box.className = "view";
    const canvas = document.createElement("canvas");
    const caption = document.createElement("p");
    caption.className = "caption";
    const link = document.createElement("a");
    link.textContent = "trajectory as CSV";
    link.download = `${e[col.agent]}_${e[col.scenario]}_dd${e[col.delta_d]}_ep${e[col.episode]}.csv`.replace(/[^\w.=-]+/g, "_");
    link.href = URL.createObjectURL(new Blob([csvOf(ep)], { type: "text/csv" }));
    box.append(canvas, caption, link);
    return { index, episode: ep, canvas, caption, link, box };
  }
  function sameEpisode(index) { // the other agents' records of this episode: same scenario, Δd and seed
    const e = episodes[index];
    return episodes.map((o, i) => i).filter((i) => i !== index && episodes[i][col.record] >= 0 && episodes[i][col.scenario] === e[col.scenario] &&
      episodes[i][col.delta_d] === e[col.delta_d] && episodes[i][col.seed] === e[col.seed]);
  }
  async function openEpisode(index, compare) {
    state.opened = index;
    const views = [await makeView(index)];
    if (compare !== undefined && compare >= 0) views.push(await makeView(compare));
    for (const v of state.views) URL.revokeObjectURL(v.link.href);
    state.views = views;
    const box = $("views");
    box.replaceChildren(...views.map((v) => v.box));
    $("player-hint").hidden = true;
    $("player-body").hidden = false;
    const others = sameEpisode(index);
    const select = $("p-compare");
    select.innerHTML = '<option value="-1">none</option>' + others.map((i) => `<option value="${i}">${escapeHtml(String(episodes[i][col.agent]))}</option>`).join("");
    select.value = String(compare !== undefined ? compare : -1);
    const longest = Math.max(...views.map((v) => v.episode.rows - 1));
    $("p-scrub").max = String(longest);
    setStep(0);
    renderList();
    $("player").scrollIntoView({ block: "start" });
  }
  function setStep(k) {
    const longest = Number($("p-scrub").max);
    state.step = Math.max(0, Math.min(k, longest));
    $("p-scrub").value = String(state.step);
    $("p-step").textContent = `${state.step} / ${longest}`;
    for (const v of state.views) draw(v, state.step);
  }
  function setPlaying(on) {
    state.playing = on;
    $("p-play").textContent = on ? "pause" : "play";
    if (on) { state.last = performance.now(); state.carry = 0; requestAnimationFrame(tick); }
  }
  function tick(now) {
    if (!state.playing || !state.views.length) return;
    const period = (1000 * state.views[0].episode.scene.dt) / state.speed; // real time at speed 1
    state.carry += now - state.last; state.last = now;
    const steps = Math.floor(state.carry / period);
    if (steps > 0) {
      state.carry -= steps * period;
      if (state.step >= Number($("p-scrub").max)) { setPlaying(false); return; }
      setStep(state.step + steps);
    }
    requestAnimationFrame(tick);
  }
  $("p-play").addEventListener("click", () => {
    if (!state.playing && state.step >= Number($("p-scrub").max)) setStep(0);
    setPlaying(!state.playing);
  });
  $("p-back").addEventListener("click", () => { setPlaying(false); setStep(state.step - 1); });
  $("p-next").addEventListener("click", () => { setPlaying(false); setStep(state.step + 1); });
  $("p-scrub").addEventListener("input", () => setStep(Number($("p-scrub").value)));
  $("p-speed").addEventListener("change", () => { state.speed = Number($("p-speed").value); });
  $("p-compare").addEventListener("change", () => openEpisode(state.opened, Number($("p-compare").value)));
  window.addEventListener("resize", () => setStep(state.step));
  state.open = openEpisode; // tests open episodes by their index in the list
  state.setStep = setStep;
  renderList();
})();
