// kapitza explorer: the exact stability chart and the pendulum on its vibrating pivot, one picture.
// Plain JavaScript, no libraries: an ES module shared by the page (app.js, which asks the JSON API
// under /api over HTTP) and the notebook widget (kapitza.widgets, which asks the kernel). Every number
// shown comes from the library; the explorer converts only between (eps, mu) and (T, A) for the hover
// readout and inputs.

// The explorer in `root` (the document, or the shadow root of a notebook cell), which holds the
// page's elements (index.html). `host` says where it lives:
//   getJSON(url, signal): answers "/api/...?query" (default: fetch over HTTP);
//   url: keep the view and point in the address bar (default true);
//   box: the element carrying the classes "rig-on" and "projector" (default document.body), watched
//        for changes of size;
//   state: a first state {point: {T, A}, l, g, drive, zeta, plane, theta0};
//   onPoint(point), onState(state): told when the user chooses a point or changes the rig.
// Returns {S, anim, chart, panel, set(state), destroy(), pixel(x, y)}.
export function mount(root, host = {}) {
  const $ = (id) => root.getElementById(id);
  const shell = host.box || document.body, useURL = host.url !== false;
  let stopped = false;

  const COLORS = { edge2: "#1f4e9c", edge4: "#c0392b", fill: "#9ecae1", overlay: "#d55e00", point: "#ffbf00",
    grid: "#e4e8ee", axis: "#34404f", nonlinear: "#1f4e9c", linear: "#8a94a3", forbidden: "#eef0f3" };

  // ------------------------------------------------------------------ the drives
  // The drives come from the server's registry (/api/drives): the page lists those it can offer
  // (page: true), with a field for a drive's one number (the rectangular wave's duty). What the page
  // needs of a drive it asks /api/drive for that drive's text and damping (INFO): mu_max, the stroke
  // coefficient, whether its edges are closed forms and whether a motion is followed exactly.
  let DRIVES = [];
  const INFO = new Map();
  const listed = (name) => DRIVES.find((d) => d.page && d.name === name) || null;
  const driveParam = (name = S.drive) => { const d = listed(name); return d && d.parameters.length ? d.parameters[0] : null; };
  const paramValue = (name = S.drive) => { const p = driveParam(name); return p ? (S.params[name] ?? p.default) : null; };
  const infoKey = (text) => `${text}|${S.zeta}`;
  const info = (text = driveText()) => INFO.get(infoKey(text)) || null;
  // The drives' numbers for the current drive and overlay (a drive the server refuses gets none: the
  // chart's own request then says what is wrong).
  async function ensureInfo() {
    await Promise.all([driveText(), S.overlay].filter(Boolean).map(async (text) => {
      const k = infoKey(text);
      if (INFO.has(k)) return;
      try { INFO.set(k, await getJSON("/api/drive?" + qs({ drive: text, zeta: S.zeta }))); } catch (e) { /* the chart says */ }
    }));
  }
  // The drive list (both selects) from the registry.
  async function loadDrives() {
    try { DRIVES = (await getJSON("/api/drives")).drives; } catch (e) { chart.error = String(e.message || e); return; }
    const sel = $("drive"), over = $("overlay");
    sel.innerHTML = "";
    for (const d of DRIVES) if (d.page) sel.add(new Option(d.title, d.name));
    while (over.options.length > 1) over.remove(1);
    for (const d of DRIVES) if (d.page) for (const x of d.examples) over.add(new Option(x.label, x.text));
  }
  // The drive's number: its field shows for a drive that has one, named and bounded as the server says.
  function syncParam() {
    const p = driveParam();
    $("duty-l").style.display = p ? "" : "none";
    if (!p) return;
    $("duty-name").textContent = p.name; $("duty").min = String(p.min); $("duty").max = String(p.max);
    $("duty").value = paramValue(); $("duty").title = p.description || "";
  }
  // The mu at and above which the upright falls whatever T and damping (kapitza's Drive.mu_max: the
  // square root of the drive's largest downward acceleration in units of A; 1 until the server said).
  // A chart shows mu up to the larger of it and 1, as kapitza.curves.mu_top.
  const muMax = (drive) => { const i = info(drive); return i ? i.mu_max : 1; };
  const muTop = (drive) => Math.max(1, muMax(drive));
  // Whether the drive's edges are closed forms at this damping (the square wave undamped): a chart
  // then asks more samples, and views may reach further.
  const closedForm = (drive = driveText()) => { const i = info(drive); return !!(i && i.closed_form); };
  // The rig plane (drive frequency across, stroke up, both logarithmic): around the chosen point a
  // factor 4 in frequency and 40 in stroke, else from the pendulum's own frequency (kapitza.rig_plane.rig_window).
  const rigView = (l, g, P) => {
    if (P) { const f = 1 / (2 * P.T), s = strokeCoef() * P.A * P.T * P.T; return { x0: f / 4, x1: 4 * f, y0: s / 40, y1: 40 * s }; }
    const fn = Math.sqrt(g / l) / (2 * Math.PI);
    return { x0: 2 * fn, x1: 200 * fn, y0: l / 1000, y1: l };
  };
  const DEFAULT_VIEWS = (l, g, top = 1, P = null) => ({
    arnold: { x0: 0, x1: 4, y0: 0, y1: top },
    physical: { x0: 0, x1: 2.5 * Math.sqrt(l / g), y0: g / (top * top), y1: 50 * g },
    rig: rigView(l, g, P),
  });
  // A demo point for the first view: zone 0, where the pendulum stands from the default start tilt.
  const DEMO = { T: 0.15, A: 100 };
  const S = {
    plane: "arnold", l: 1, g: 9.81, drive: "square", params: {}, zeta: 0, overlay: "",
    point: null, theta0: 0.1, speed: 0.25, views: DEFAULT_VIEWS(1, 9.81),
    rig: false, rod: 1.5, rodKind: "rod", given: "amplitude", dampUnit: "zeta", k: null,
    // the tower: from 2 links on the chart is its band on the rig plane (views.tower: null = its whole band)
    links: 1, chain: [0.2, 0.2, 0.2, 0.2], masses: [1, 1, 1, 1], linkKind: "rod", jointDamping: 0, towerNew: false,
  };
  // The tower's routes (/api/tower/...) are the web API's; a host answering requests itself says it knows them.
  const towerOK = !host.getJSON || !!host.tower;
  const isTower = () => towerOK && S.links > 1;
  const towerHeight = () => S.chain.slice(0, S.links).reduce((a, b) => a + b, 0);
  // stroke = k A T^2 (peak-to-peak travel of the pivot): the server's value for the drive (1/4 for the
  // square wave), else that of the last chart.
  function strokeCoef() {
    const i = info();
    return i ? i.stroke_coefficient : S.k || 0.25;
  }
  // The same conversions as kapitza.to_arnold / kapitza.to_physical (docs/theory.md section 2).
  const toArnold = (T, A, l, g) => ({ eps: T * Math.sqrt(A / (8 * l)), mu: Math.sqrt(g / A) });
  const toPhysical = (eps, mu, l, g) => { const A = g / (mu * mu); return { T: eps * Math.sqrt(8 * l / A), A }; };
  // The drive's text form (kapitza.parse_drive): NAME, or NAME:VALUE for a drive with a number.
  const driveText = () => (driveParam() ? `${S.drive}:${paramValue()}` : S.drive);
  const view = () => {
    if (!isTower()) return S.views[S.plane];
    if (!S.views.tower) S.views.tower = { ...rigView(towerHeight(), S.g, null), auto: true };  // until the band's own window comes
    return S.views.tower;
  };
  // What the tower's routes are told: the links, their masses and kind, the joint friction, the drive and g.
  const towerBase = () => ({ chain: S.chain.slice(0, S.links).join(","), masses: S.masses.slice(0, S.links).join(","),
    links: S.linkKind, joint_damping: S.jointDamping > 0 ? S.jointDamping : null, drive: driveText(), g: S.g });

  function qs(obj) {
    const p = new URLSearchParams();
    for (const [k, v] of Object.entries(obj)) if (v !== null && v !== undefined && v !== "") p.set(k, String(v));
    return p.toString();
  }
  const short = (v) => (Math.abs(v) >= 1000 || (Math.abs(v) < 0.01 && v !== 0) ? v.toExponential(0) : String(Number(v.toPrecision(2))));
  const fmt = (v, d = 6) => (v === null || v === undefined || !isFinite(v) ? "–"
    : Number(v).toPrecision(d).replace(/(\.\d*?)0+(e|$)/, "$1$2").replace(/\.(e|$)/, "$1"));

  // ------------------------------------------------------------------ URL (shareable state)
  function saveURL() {
    if (!useURL) return;
    const v = view();
    const o = { plane: S.plane, x0: v.x0, x1: v.x1, y0: v.y0, y1: v.y1, l: S.l, g: S.g, drive: S.drive, zeta: S.zeta,
      overlay: S.overlay, theta0: S.theta0, speed: S.speed };
    if (S.rig) { o.rig = 1; o.rod = S.rod; o.rod_kind = S.rodKind; o.given = S.given; o.damp_unit = S.dampUnit; }
    const dp = driveParam();
    if (dp) o[dp.name] = paramValue();
    if (S.links > 1) { o.links = S.links; o.chain = S.chain.slice(0, S.links).join(","); o.masses = S.masses.slice(0, S.links).join(","); o.link_kind = S.linkKind; if (S.jointDamping > 0) o.joint_damping = S.jointDamping; }
    if (S.point) { o.T = S.point.T; o.A = S.point.A; }
    history.replaceState(null, "", "?" + qs(o));
  }
  async function loadURL() {
    const p = new URLSearchParams(location.search);
    const num = (k) => (p.has(k) && isFinite(parseFloat(p.get(k))) ? parseFloat(p.get(k)) : null);
    if (num("l") > 0) S.l = num("l");
    if (num("g") > 0) S.g = num("g");
    if (["arnold", "physical", "rig"].includes(p.get("plane"))) S.plane = p.get("plane");
    if (p.get("rig") === "1") S.rig = true;
    if (num("rod") > 0) S.rod = num("rod");
    if (["rod", "point"].includes(p.get("rod_kind"))) S.rodKind = p.get("rod_kind");
    if (["amplitude", "stroke"].includes(p.get("given"))) S.given = p.get("given");
    if (["zeta", "c"].includes(p.get("damp_unit"))) S.dampUnit = p.get("damp_unit");
    if (listed(p.get("drive"))) S.drive = p.get("drive");  // a drive the server listed
    const dp = driveParam();
    if (dp && num(dp.name) !== null) S.params[S.drive] = num(dp.name);
    if (num("zeta") !== null) S.zeta = num("zeta");
    if (p.has("overlay")) S.overlay = p.get("overlay");
    await ensureInfo();
    S.views = DEFAULT_VIEWS(S.l, S.g, muTop(driveText()));
    if (num("theta0") !== null) S.theta0 = num("theta0");
    if (num("speed") !== null) S.speed = num("speed");
    const v = ["x0", "x1", "y0", "y1"].map(num);
    if (v.every((x) => x !== null) && v[0] < v[1] && v[2] < v[3]) S.views[S.plane] = { x0: v[0], x1: v[1], y0: v[2], y1: v[3] };
    if (num("T") > 0 && num("A") > 0) S.point = { T: num("T"), A: num("A") };
    if (!v.every((x) => x !== null) && S.plane === "rig") S.views.rig = rigView(S.l, S.g, S.point);
    const n = parseInt(p.get("links"), 10), list = (k) => (p.get(k) || "").split(",").map(parseFloat);
    if (towerOK && n >= 2 && n <= 4) {
      S.links = n; S.plane = "rig"; S.rig = true; S.towerNew = true;
      list("chain").forEach((x, i) => { if (i < 4 && x > 0) S.chain[i] = x; });
      list("masses").forEach((x, i) => { if (i < 4 && x > 0) S.masses[i] = x; });
      if (["rod", "point"].includes(p.get("link_kind"))) S.linkKind = p.get("link_kind");
      if (num("joint_damping") > 0) S.jointDamping = num("joint_damping");
      S.views.tower = v.every((x) => x !== null) && v[0] > 0 && v[2] > 0 ? { x0: v[0], x1: v[1], y0: v[2], y1: v[3] } : null;
    }
  }

  // ------------------------------------------------------------------ canvas helpers
  function fit(canvas) {
    const r = canvas.getBoundingClientRect(), dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(r.width * dpr)), h = Math.max(1, Math.round(r.height * dpr));
    if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
    const ctx = canvas.getContext("2d");
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    return { ctx, w: r.width, h: r.height };
  }
  function niceStep(span, target) {
    const raw = span / target, p = Math.pow(10, Math.floor(Math.log10(raw))), m = raw / p;
    return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
  }
  function linTicks(a, b, target) {
    const step = niceStep(b - a, target), out = [];
    for (let k = Math.ceil(a / step); k * step <= b + 1e-12 * Math.abs(step); k++) out.push(k * step);
    return { ticks: out, step };
  }
  function tickLabel(v, step) {
    if (v === 0) return "0";
    const digits = Math.max(1, Math.ceil(Math.log10(Math.abs(v) / step) + 1e-9) + 1);
    if (digits > 16) return v.toPrecision(16);
    const a = Math.abs(v);
    if (a >= 1e-3 && a < 1e5 && step >= 1e-6) return Number(v.toFixed(Math.max(0, -Math.floor(Math.log10(step) + 1e-9))));
    return Number(v.toPrecision(Math.min(digits, 16))).toString();
  }

  // ------------------------------------------------------------------ the chart
  const chart = { canvas: $("chart"), data: null, overlay: null, pad: { l: 78, r: 18, t: 14, b: 50 }, error: null };
  const inset = { canvas: $("inset"), data: null };  // the magnified zone beside "show zone n"
  function axes(w, h) {
    const v = view(), P = chart.pad, logY = S.plane !== "arnold", logX = S.plane === "rig";
    const fy = logY ? Math.log : (x) => x, fx = logX ? Math.log : (x) => x;
    const y0 = fy(v.y0 > 0 || !logY ? v.y0 : 1e-9), y1 = fy(v.y1);
    const x0 = fx(v.x0 > 0 || !logX ? v.x0 : 1e-9), x1 = fx(v.x1);
    return {
      left: P.l, right: w - P.r, top: P.t, bottom: h - P.b, logY, logX,
      X: (x) => P.l + ((fx(x) - x0) / (x1 - x0)) * (w - P.l - P.r),
      Y: (y) => h - P.b - ((fy(y) - y0) / (y1 - y0)) * (h - P.t - P.b),
      invX: (px) => { const f = x0 + ((px - P.l) / (w - P.l - P.r)) * (x1 - x0); return logX ? Math.exp(f) : f; },
      invY: (py) => { const f = y0 + ((h - P.b - py) / (h - P.t - P.b)) * (y1 - y0); return logY ? Math.exp(f) : f; },
    };
  }
  // Where a parameter set (T, A) lies on the current plane, and back.
  function toPlane(P) {
    if (S.plane === "arnold") { const { eps, mu } = toArnold(P.T, P.A, S.l, S.g); return { x: eps, y: mu }; }
    if (S.plane === "physical") return { x: P.T, y: P.A };
    return { x: 1 / (2 * P.T), y: strokeCoef() * P.A * P.T * P.T };
  }
  function fromPlane(x, y) {
    if (S.plane === "arnold") return toPhysical(x, y, S.l, S.g);
    if (S.plane === "physical") return { T: x, A: y };
    const T = 1 / (2 * x); return { T, A: y / (strokeCoef() * T * T) };
  }
  function logTicks(a, b) {
    const out = [], lo = Math.floor(Math.log10(a)), hi = Math.ceil(Math.log10(b));
    const mult = hi - lo > 3 ? [1] : hi - lo > 1 ? [1, 2, 5] : [1, 1.5, 2, 3, 4, 5, 6, 7, 8, 9];
    for (let e = lo; e <= hi; e++) for (const m of mult) { const t = m * Math.pow(10, e); if (t >= a && t <= b) out.push(t); }
    return out.length >= 2 ? { ticks: out, step: 1, log: true } : linTicks(a, b, 6);
  }
  const logLabel = (v) => String(Number(v.toPrecision(3)));
  const clampPx = (p) => Math.max(-4000, Math.min(8000, p));

  function drawZones(ctx, ax, d, style) {
    const ys = d.y_values, v = view(), far = ax.logX ? v.x1 * 10 : v.x1 + 10 * (v.x1 - v.x0);
    const val = (x) => (x === null ? null : x > far ? far : ax.logX && x <= v.x0 / 10 ? v.x0 / 10 : x);
    for (const z of d.zones) {
      const runs = []; let cur = [];
      for (let j = 0; j < ys.length; j++) {
        const a = val(z.lo[j]), b = val(z.hi[j]);
        if (a === null || b === null) { if (cur.length) runs.push(cur); cur = []; continue; }
        cur.push(j);
      }
      if (cur.length) runs.push(cur);
      for (const run of runs) {
        if (style.fill) {
          ctx.beginPath();
          run.forEach((j, i) => { const X = clampPx(ax.X(val(z.lo[j]))), Y = clampPx(ax.Y(ys[j])); i ? ctx.lineTo(X, Y) : ctx.moveTo(X, Y); });
          for (let i = run.length - 1; i >= 0; i--) { const j = run[i]; ctx.lineTo(clampPx(ax.X(val(z.hi[j]))), clampPx(ax.Y(ys[j]))); }
          ctx.closePath(); ctx.fillStyle = style.fill; ctx.fill();
        }
        for (const [key, kind] of [["lo", z.lower_edge], ["hi", z.upper_edge]]) {
          ctx.beginPath();
          let on = false;
          // An edge beyond the view (an asymptote: the rig plane's upper edge as the frequency grows)
          // is drawn to the same point off the canvas as the shading, so it runs out of the view with it.
          for (const j of run) {
            const X = clampPx(ax.X(val(z[key][j]))), Y = clampPx(ax.Y(ys[j]));
            on ? ctx.lineTo(X, Y) : ctx.moveTo(X, Y); on = true;
          }
          ctx.strokeStyle = style.color ? style.color : kind === "2T" ? COLORS.edge2 : COLORS.edge4;
          ctx.setLineDash(kind === "4T" ? [7, 4] : []);
          ctx.lineWidth = style.width || 1.8;
          ctx.stroke();
        }
        ctx.setLineDash([]);
      }
    }
  }

  function zoneLabels(ctx, ax, d) {
    ctx.font = "600 13px DejaVu Sans, sans-serif";
    ctx.textBaseline = "middle";
    for (const z of d.zones) {
      const vis = [];
      for (let j = 0; j < d.y_values.length; j++) {
        if (z.lo[j] === null || z.hi[j] === null) continue;
        const X = ax.X(z.hi[j]), Y = ax.Y(d.y_values[j]), X0 = ax.X(z.lo[j]);
        if (Y > ax.top + 10 && Y < ax.bottom - 10 && X0 < ax.right - 10 && X > ax.left + 4) vis.push([j, X0, X, Y]);
      }
      if (!vis.length) continue;
      // Near the lower third of the visible part, right of the upper edge (inside when it is wide),
      // and not under the legend.
      const text = `n = ${z.n}`, tw = ctx.measureText(text).width, L = chart.legendBox;
      const place = (k) => {
        const [, X0, X1, Y] = vis[k];
        let x = X1 - X0 > tw + 16 ? (Math.max(X0, ax.left) + Math.min(X1, ax.right)) / 2 - tw / 2 : X1 + 6;
        x = Math.min(Math.max(x, ax.left + 4), ax.right - tw - 4);
        const hidden = L && x + tw > L.x && x < L.x + L.w && Y + 9 > L.y && Y - 9 < L.y + L.h;
        return hidden ? null : [x, Y];
      };
      const k0 = Math.floor(vis.length * (ax.logY ? 0.7 : 0.3));
      let at = null;
      for (let d = 0; d < vis.length && !at; d += Math.max(1, Math.floor(vis.length / 40))) {
        at = (k0 + d < vis.length && place(k0 + d)) || (k0 - d >= 0 && place(k0 - d)) || null;
      }
      if (!at) continue;
      const [x, Y] = at;
      ctx.fillStyle = "rgba(255,255,255,0.85)"; ctx.fillRect(x - 3, Y - 9, tw + 6, 18);
      ctx.fillStyle = "#16263d"; ctx.fillText(text, x, Y);
    }
  }

  function drawChart() {
    drawInset();  // (it hides itself once the plane, the drive or the damping is no longer its own)
    const { ctx, w, h } = fit(chart.canvas), v = view();
    // room for the longest tick label of the vertical axis, then the axis title
    ctx.font = "12.5px DejaVu Sans, sans-serif";
    const yt0 = S.plane === "arnold" ? linTicks(v.y0, v.y1, 6) : null;
    const widest = yt0 ? Math.max(...yt0.ticks.map((t) => ctx.measureText(tickLabel(t, yt0.step)).width), 20) : 40;
    chart.pad.l = Math.max(64, Math.ceil(widest) + 36);
    const ax = axes(w, h);
    ctx.clearRect(0, 0, w, h);
    ctx.fillStyle = "#fff"; ctx.fillRect(ax.left, ax.top, ax.right - ax.left, ax.bottom - ax.top);
    // Where the upright is always unstable (mu >= mu_max: A <= g for the square and sine waves): grey.
    const mMax = muMax(driveText()), edge = S.plane === "arnold" ? ax.Y(mMax) : ax.Y(S.g / (mMax * mMax));
    const weak = mMax === 1 ? "A ≤ g" : `A ≤ ${fmt(1 / (mMax * mMax), 3)} g`;
    ctx.save(); ctx.beginPath(); ctx.rect(ax.left, ax.top, ax.right - ax.left, ax.bottom - ax.top); ctx.clip();
    ctx.fillStyle = COLORS.forbidden;
    if (S.plane === "arnold" && edge > ax.top) ctx.fillRect(ax.left, ax.top, ax.right - ax.left, edge - ax.top);
    if (S.plane === "physical" && edge < ax.bottom) ctx.fillRect(ax.left, edge, ax.right - ax.left, ax.bottom - edge);
    if (S.plane === "rig") {  // A <= g / mu_max^2: stroke <= g k / (4 f^2 mu_max^2), always falls
      ctx.beginPath();
      for (let i = 0; i <= 60; i++) { const f = v.x0 * Math.pow(v.x1 / v.x0, i / 60), sc = S.g * strokeCoef() / (4 * f * f * mMax * mMax);
        const X = ax.X(f), Y = clampPx(ax.Y(Math.max(sc, 1e-300))); i ? ctx.lineTo(X, Y) : ctx.moveTo(X, Y); }
      ctx.lineTo(ax.right, ax.bottom + 10); ctx.lineTo(ax.left, ax.bottom + 10); ctx.closePath(); ctx.fill();
    }
    // grid
    const xt = ax.logX ? logTicks(v.x0, v.x1) : linTicks(v.x0, v.x1, 8);
    const yt = ax.logY ? logTicks(v.y0, v.y1) : linTicks(v.y0, v.y1, 6);
    ctx.strokeStyle = COLORS.grid; ctx.lineWidth = 1;
    for (const t of xt.ticks) { ctx.beginPath(); ctx.moveTo(ax.X(t), ax.top); ctx.lineTo(ax.X(t), ax.bottom); ctx.stroke(); }
    for (const t of yt.ticks) { ctx.beginPath(); ctx.moveTo(ax.left, ax.Y(t)); ctx.lineTo(ax.right, ax.Y(t)); ctx.stroke(); }
    if (chart.data) drawZones(ctx, ax, chart.data, { fill: "rgba(158,202,225,0.85)" });
    if (isTower() && chart.tower) drawBand(ctx, ax, chart.tower);
    if (chart.overlay) drawZones(ctx, ax, chart.overlay, { fill: "rgba(213,94,0,0.13)", color: COLORS.overlay, width: 2.2 });
    chart.legendBox = legendBox(ctx, ax);
    if (chart.data) zoneLabels(ctx, ax, chart.data);
    if (isTower() && chart.tower) modeLabels(ctx, ax, chart.tower);
    if (S.plane === "arnold" && edge > ax.top + 14) label(ctx, `μ ≥ ${fmt(mMax, 4)} (${weak}): always unstable`, ax.left + 8, Math.max(ax.top + 12, edge - 12));
    if (S.plane === "physical" && edge < ax.bottom - 14) label(ctx, `${weak}: always unstable`, ax.left + 8, Math.min(ax.bottom - 12, edge + 14));
    if (S.plane === "rig") label(ctx, `grey: ${weak}, always falls`, ax.left + 8, ax.bottom - 12);
    // the chosen point
    if (S.point) { const q = toPlane(S.point); star(ctx, ax.X(q.x), ax.Y(q.y), 11); }
    ctx.restore();
    // frame, ticks, labels
    ctx.strokeStyle = COLORS.axis; ctx.lineWidth = 1.2; ctx.strokeRect(ax.left, ax.top, ax.right - ax.left, ax.bottom - ax.top);
    ctx.fillStyle = COLORS.axis; ctx.font = "12.5px DejaVu Sans, sans-serif";
    ctx.textAlign = "center"; ctx.textBaseline = "top";
    const yScale = S.plane === "rig" ? 1e3 : 1;  // the stroke in mm
    for (const t of xt.ticks) ctx.fillText(xt.log ? logLabel(t) : tickLabel(t, xt.step), ax.X(t), ax.bottom + 5);
    ctx.textAlign = "right"; ctx.textBaseline = "middle";
    for (const t of yt.ticks) ctx.fillText(yt.log ? logLabel(t * yScale) : tickLabel(t, yt.step || t / 10), ax.left - 6, ax.Y(t));
    ctx.font = "14px DejaVu Sans, sans-serif"; ctx.textAlign = "center"; ctx.textBaseline = "bottom";
    ctx.fillText({ arnold: "ε = T √(A / 8l)", physical: "half-period of the drive T [s]", rig: "drive frequency [Hz] (log scale)" }[S.plane],
      (ax.left + ax.right) / 2, h - 4);
    ctx.save(); ctx.translate(16, (ax.top + ax.bottom) / 2); ctx.rotate(-Math.PI / 2); ctx.textBaseline = "middle";
    ctx.fillText({ arnold: "μ = √(g / A)", physical: "pivot acceleration amplitude A [m/s²] (log scale)",
      rig: "stroke, peak to peak [mm] (log scale)" }[S.plane], 0, 0);
    ctx.restore();
    legend(ctx, ax);
    if (chart.error) { ctx.fillStyle = "rgba(180,35,24,0.92)"; ctx.font = "600 14px DejaVu Sans, sans-serif"; ctx.textAlign = "left";
      ctx.textBaseline = "top"; wrapText(ctx, chart.error, ax.left + 12, ax.top + 12, ax.right - ax.left - 24); }
    $("view-info").textContent = S.plane === "arnold"
      ? `ε ${tickLabel(v.x0, (v.x1 - v.x0) / 100)} … ${tickLabel(v.x1, (v.x1 - v.x0) / 100)} · μ ${tickLabel(v.y0, (v.y1 - v.y0) / 100)} … ${tickLabel(v.y1, (v.y1 - v.y0) / 100)}`
      : S.plane === "physical" ? `T ${fmt(v.x0, 4)} … ${fmt(v.x1, 4)} s · A ${fmt(v.y0, 4)} … ${fmt(v.y1, 4)} m/s²`
      : `f ${fmt(v.x0, 4)} … ${fmt(v.x1, 4)} Hz · stroke ${fmt(1e3 * v.y0, 4)} … ${fmt(1e3 * v.y1, 4)} mm`;
  }
  function label(ctx, text, x, y) {
    ctx.font = "italic 12.5px DejaVu Sans, sans-serif"; ctx.fillStyle = "#6b7685"; ctx.textAlign = "left"; ctx.textBaseline = "middle";
    ctx.fillText(text, x, y);
  }
  function wrapText(ctx, text, x, y, width) {
    let line = "";
    for (const word of text.split(" ")) {
      if (ctx.measureText(line + word).width > width && line) { ctx.fillText(line, x, y); y += 18; line = ""; }
      line += word + " ";
    }
    ctx.fillText(line, x, y);
  }
  function star(ctx, x, y, r) {
    ctx.beginPath();
    for (let k = 0; k < 10; k++) {
      const a = -Math.PI / 2 + (k * Math.PI) / 5, rr = k % 2 ? r * 0.45 : r;
      k ? ctx.lineTo(x + rr * Math.cos(a), y + rr * Math.sin(a)) : ctx.moveTo(x + rr * Math.cos(a), y + rr * Math.sin(a));
    }
    ctx.closePath(); ctx.fillStyle = COLORS.point; ctx.fill(); ctx.strokeStyle = "#000"; ctx.lineWidth = 1.3; ctx.stroke();
  }
  // The tower's band: its verdict on a grid (log-spaced, so an image on log axes), and each mode's
  // edges of zone 0 on top: solid, the lower edge (below it in frequency that mode falls), dashed,
  // the upper edge (beyond it that mode doubles its period). Mode 1 is the longest, drawn widest.
  function drawBand(ctx, ax, d) {
    const b = d.band, nf = b.frequency.length, ns = b.stroke.length;
    if (nf >= 2 && ns >= 2) {
      const img = document.createElement("canvas"); img.width = nf; img.height = ns;
      const g = img.getContext("2d"), data = g.createImageData(nf, ns);
      for (let i = 0; i < ns; i++) for (let j = 0; j < nf; j++) {
        const o = 4 * ((ns - 1 - i) * nf + j), on = b.stable[i][j];
        data.data[o] = 158; data.data[o + 1] = 202; data.data[o + 2] = 225; data.data[o + 3] = on ? 220 : 0;
      }
      g.putImageData(data, 0, 0);
      // cell j spans half a grid step either side of frequency[j] (in log)
      const hf = Math.sqrt(b.frequency[1] / b.frequency[0]), hs = Math.sqrt(b.stroke[1] / b.stroke[0]);
      const X0 = ax.X(b.frequency[0] / hf), X1 = ax.X(b.frequency[nf - 1] * hf), Y0 = ax.Y(b.stroke[ns - 1] * hs), Y1 = ax.Y(b.stroke[0] / hs);
      ctx.save(); ctx.imageSmoothingEnabled = true; ctx.drawImage(img, X0, Y0, X1 - X0, Y1 - Y0); ctx.restore();
    }
    const v = view();
    d.modes.forEach((m, k) => {
      for (const [edge, dash, col] of [["lower", [], COLORS.edge2], ["upper", [7, 4], COLORS.edge4]]) {
        const F = m[edge].frequency, St = m[edge].stroke;
        ctx.beginPath(); let on = false;
        for (let j = 0; j < F.length; j++) {
          const f = F[j], st = St[j];
          if (f === null || st === null || !(f > v.x0 / 10 && f < v.x1 * 10 && st > v.y0 / 10 && st < v.y1 * 10)) { on = false; continue; }
          const X = clampPx(ax.X(f)), Y = clampPx(ax.Y(st));
          on ? ctx.lineTo(X, Y) : ctx.moveTo(X, Y); on = true;
        }
        ctx.strokeStyle = col; ctx.setLineDash(dash); ctx.lineWidth = k === 0 ? 2.4 : 1.6; ctx.stroke();
      }
    });
    ctx.setLineDash([]);
  }
  // "mode k falls" on each lower edge, "mode k doubles" on each upper edge, where there is room.
  function modeLabels(ctx, ax, d) {
    ctx.font = "600 12.5px DejaVu Sans, sans-serif"; ctx.textBaseline = "middle";
    const L = chart.legendBox, taken = [];
    const free = (x, y, w) => !(L && x + w > L.x && x < L.x + L.w && y + 9 > L.y && y - 9 < L.y + L.h) &&
      taken.every(([a, b, c]) => x + w < a || x > a + c || Math.abs(y - b) > 18);
    d.modes.forEach((m, k) => {
      for (const [edge, text, frac] of [["lower", `mode ${m.mode} falls`, 0.35 + 0.1 * k], ["upper", `mode ${m.mode} doubles`, 0.75 - 0.05 * k]]) {
        const F = m[edge].frequency, St = m[edge].stroke, tw = ctx.measureText(text).width, vis = [];
        for (let j = 0; j < F.length; j++) {
          if (F[j] === null || St[j] === null) continue;
          const X = ax.X(F[j]), Y = ax.Y(St[j]);
          if (X > ax.left + 4 && X < ax.right - tw - 12 && Y > ax.top + 12 && Y < ax.bottom - 26) vis.push([X, Y]);
        }
        if (!vis.length) continue;
        vis.sort((a, b) => a[0] - b[0]);
        for (let t = 0; t < vis.length; t++) {
          const q = vis[Math.floor(((frac * vis.length) + t) % vis.length)], x = q[0] + 6, y = q[1] - (edge === "upper" ? 10 : 0);
          if (!free(x, y, tw)) continue;
          taken.push([x, y, tw]);
          ctx.fillStyle = "rgba(255,255,255,0.85)"; ctx.fillRect(x - 3, y - 9, tw + 6, 18);
          ctx.fillStyle = edge === "lower" ? COLORS.edge2 : COLORS.edge4; ctx.fillText(text, x, y);
          break;
        }
      }
    });
  }
  // A narrow chart (a phone) gets the short legend in a smaller font: the full one would hide a
  // third of the plot. The plain words stay first.
  const narrowChart = (ax) => ax.right - ax.left < 420;
  function legendRows(narrow) {
    if (isTower()) {
      const d = chart.tower, damped = d && d.joint_damping > 0, rows = narrow
        ? [["fill", COLORS.fill, `stands (${S.links} links${damped ? ", damped" : ""})`], ["blank", "#fff", "falls"],
           ["line", COLORS.edge2, "mode k: 2T edge"], ["dash", COLORS.edge4, "mode k: 4T edge"]]
        : [["fill", COLORS.fill, `shaded: the ${S.links}-link tower stands (${damped ? "damped: every multiplier inside the unit circle" : "every mode stable"})`],
           ["blank", "#fff", "white: it falls"],
           ["line", COLORS.edge2, "mode k falls below this edge (2T)"], ["dash", COLORS.edge4, "mode k doubles its period beyond (4T)"]];
      if (S.point) rows.push(["star", COLORS.point, narrow ? "point" : "chosen point"]);
      return rows;
    }
    const rows = narrow
      ? [["fill", COLORS.fill, "stays up (zone n)"], ["blank", "#fff", "falls"],
         ["line", COLORS.edge2, "edge: 2T (Tₙ)"], ["dash", COLORS.edge4, "edge: 4T (T̃ₙ)"]]
      : [["fill", COLORS.fill, `shaded: stays up (stable zone n${chart.data ? `, ${shortDrive(chart.data.drive)}${S.zeta > 0 ? `, ζ = ${S.zeta}` : ""}` : ""})`],
         ["blank", "#fff", "white: falls"],
         ["line", COLORS.edge2, "edge: 2T-periodic motion (Tₙ)"], ["dash", COLORS.edge4, "edge: period doubling, 4T (T̃ₙ)"]];
    if (chart.overlay) rows.push(["line", COLORS.overlay, `${narrow ? "" : "overlay: "}${shortDrive(chart.overlay.drive)}`]);
    if (S.point) rows.push(["star", COLORS.point, narrow ? "point" : "chosen point"]);
    return rows;
  }
  const legendFont = (narrow) => `${narrow ? 11 : 12.5}px DejaVu Sans, sans-serif`;
  function legendBox(ctx, ax) {
    const narrow = narrowChart(ax), rows = legendRows(narrow), step = narrow ? 15 : 19;
    ctx.font = legendFont(narrow);
    const w = Math.max(...rows.map((r) => ctx.measureText(r[2]).width)) + (narrow ? 40 : 46), h = rows.length * step + (narrow ? 6 : 10);
    return { x: ax.right - w - (narrow ? 4 : 8), y: ax.top + (narrow ? 4 : 8), w, h, narrow, step };
  }
  function legend(ctx, ax) {
    const B = legendBox(ctx, ax), rows = legendRows(B.narrow), wd = B.w, ht = B.h, x = B.x, y = B.y;
    const key = B.narrow ? 20 : 26, gap = B.narrow ? 34 : 40;
    ctx.font = legendFont(B.narrow);
    ctx.fillStyle = "rgba(255,255,255,0.93)"; ctx.fillRect(x, y, wd, ht); ctx.strokeStyle = "#c9d1dc"; ctx.lineWidth = 1; ctx.strokeRect(x, y, wd, ht);
    rows.forEach(([kind, col, text], i) => {
      const yy = y + (B.narrow ? 11 : 14) + i * B.step;
      if (kind === "fill") { ctx.fillStyle = col; ctx.fillRect(x + 8, yy - 6, key, 12); }
      else if (kind === "blank") { ctx.fillStyle = col; ctx.fillRect(x + 8, yy - 6, key, 12); ctx.strokeStyle = "#b8c2cf"; ctx.lineWidth = 1; ctx.strokeRect(x + 8, yy - 6, key, 12); }
      else if (kind === "star") star(ctx, x + 8 + key / 2, yy, B.narrow ? 6 : 7);
      else { ctx.beginPath(); ctx.moveTo(x + 8, yy); ctx.lineTo(x + 8 + key, yy); ctx.strokeStyle = col; ctx.lineWidth = 2; ctx.setLineDash(kind === "dash" ? [7, 4] : []); ctx.stroke(); ctx.setLineDash([]); }
      ctx.fillStyle = COLORS.axis; ctx.textAlign = "left"; ctx.textBaseline = "middle"; ctx.fillText(text, x + gap, yy);
    });
  }
  const shortDrive = (d) => (d || "").replace(/ \(.*\)$/, "");

  function chartParams(drive) {
    // The square wave's edges are closed forms (1000 samples in milliseconds); another drive or
    // damping solves an eigenproblem per edge and sample, so fewer samples keep the view quick.
    // null: the view lies where this drive cannot hold the rod up (nothing to ask for).
    if (isTower()) {  // the tower's band: its whole window until the user moves it
      const v = view();
      return v.auto ? towerBase() : { ...towerBase(), f_min: v.x0, f_max: v.x1, stroke_min: v.y0, stroke_max: v.y1 };
    }
    const samples = closedForm(drive) ? 1000 : 300;
    const v = view(), base = { plane: S.plane, l: S.l, g: S.g, drive, zeta: S.zeta, samples }, top = muTop(drive);
    if (v.x1 <= 0) return null;
    if (S.plane === "arnold") return v.y0 >= top ? null : { ...base, eps_min: Math.max(0, v.x0), eps_max: v.x1, mu_min: Math.max(0, v.y0), mu_max: Math.min(top, v.y1) };
    if (S.plane === "rig") return { ...base, samples: 300, f_min: v.x0, f_max: v.x1, stroke_min: v.y0, stroke_max: v.y1 };
    const A_min = Math.max(S.g / (top * top), v.y0);
    return v.y1 <= A_min ? null : { ...base, T_min: Math.max(0, v.x0), T_max: v.x1, A_min, A_max: v.y1 };
  }
  let chartTimer = null, chartAbort = null, chartSeq = 0;
  function requestChart(delay = 60) {
    clearTimeout(chartTimer);
    chartTimer = setTimeout(fetchChart, delay);
  }
  async function fetchChart() {
    if (chartAbort) chartAbort.abort();
    chartAbort = new AbortController();
    const seq = ++chartSeq, signal = chartAbort.signal;
    $("busy").hidden = false;
    try {
      if (isTower()) {
        const a = await getJSON("/api/tower/chart?" + qs(chartParams(driveText())), signal);
        if (seq !== chartSeq) return;
        chart.tower = a; chart.data = null; chart.overlay = null; chart.error = null;
        if (view().auto) S.views.tower = { x0: a.view.f_min, x1: a.view.f_max, y0: a.view.stroke_min, y1: a.view.stroke_max };
        if (a.stroke_coefficient) { const k = S.k; S.k = a.stroke_coefficient; if (k !== S.k) setPointInputs(); }
        if (S.towerNew) { S.towerNew = false; towerStart(a); }
        return;
      }
      chart.tower = null;
      const p = chartParams(driveText()), po = S.overlay && S.overlay !== driveText() ? chartParams(S.overlay) : null;
      const main = p ? getJSON("/api/chart?" + qs(p), signal) : null;
      const over = po ? getJSON("/api/chart?" + qs(po), signal) : null;
      const [a, b] = await Promise.all([main, over]);
      if (seq !== chartSeq) return;
      chart.data = a; chart.overlay = b; chart.error = null;
      if (a && a.stroke_coefficient) { const k = S.k; S.k = a.stroke_coefficient; if (k !== S.k) setPointInputs(); }
    } catch (e) {
      if (e.name === "AbortError") return;
      chart.error = String(e.message || e);
    } finally {
      if (seq === chartSeq) {
        $("busy").hidden = true; chart.canvas.dataset.fetches = String(seq);
        chart.canvas.dataset.tower = chart.tower && isTower() ? String(chart.tower.n_links) : "";
        drawChart(); updateCaption(); updateExports(); saveURL();
      }
    }
  }
  async function getJSON(url, signal) {
    if (host.getJSON) return host.getJSON(url, signal);  // the notebook: the kernel answers
    const r = await fetch(url, { signal });
    const body = await r.json().catch(() => ({}));
    if (!r.ok) throw new Error(body.detail || `${r.status} ${r.statusText}`);
    return body;
  }
  function updateCaption() {
    if (isTower()) {
      const d = chart.tower;
      $("caption").textContent = !d ? "" : `Shaded: the tower of ${d.chain} stands upright (${d.drive}, g = ${d.g} m/s²); white: it falls. ` +
        `Without friction it moves as ${d.n_links} single pendulums, its modes, of equivalent lengths ` +
        `${d.modal_lengths.map((x) => fmt(x, 4)).join(", ")} m; it stands where every mode does. ` +
        (d.joint_damping > 0 ? `Joint friction c = ${fmt(d.joint_damping, 4)} N m s/rad couples the modes: the shading is the ` +
          `full ${2 * d.n_links}-dimensional monodromy's verdict on a ${d.band.frequency.length} × ${d.band.stroke.length} grid, ` +
          "the edges drawn are the frictionless modes'. " : "") +
        "Solid blue: a mode's lower edge (at lower frequency it falls; mode 1, the longest, sets the tower's); " +
        "dashed red: its upper edge (at larger stroke it doubles its period; the shortest mode's comes first). Click a point: the tower's verdict and its motion.";
      return;
    }
    const d = chart.data;
    if (!d) { $("caption").textContent = ""; return; }
    const zones = d.zones.map((z) => z.n);
    $("caption").textContent = `Shaded: the pendulum stays up (the upright is stable; ${d.drive}${S.zeta > 0 ? `, damping ratio ζ = ${S.zeta}` : ""}). ` +
      `White: it falls. Zones in view: ${zones.length ? zones.join(", ") : "none"}; each edge exact at ${d.samples} samples of ${d.y}. ` +
      (S.plane !== "arnold" ? `Equivalent length l = ${fmt(S.l, 4)} m, g = ${S.g} m/s². ` : "") +
      (S.plane === "rig" ? "At a fixed stroke the zone is a band of frequencies. " : "") +
      "Solid blue edges: a 2T-periodic motion; dashed red: a period-doubling (4T-periodic) one.";
  }

  // ------------------------------------------------------------------ chart interaction
  let drag = null, hoverSeq = 0, hoverBusy = false, hoverNext = null, hoverAt = null;
  chart.canvas.addEventListener("wheel", (ev) => {
    ev.preventDefault();
    const r = chart.canvas.getBoundingClientRect(), ax = axes(r.width, r.height), v = view();
    const f = Math.exp(Math.max(-0.5, Math.min(0.5, ev.deltaY * 0.0015)));
    const mx = ax.invX(ev.clientX - r.left), my = ax.invY(ev.clientY - r.top);
    if (!ev.altKey) {
      if (ax.logX) { const L = Math.log(mx); v.x0 = Math.exp(L + (Math.log(v.x0) - L) * f); v.x1 = Math.exp(L + (Math.log(v.x1) - L) * f); }
      else { v.x0 = mx + (v.x0 - mx) * f; v.x1 = mx + (v.x1 - mx) * f; }
    }
    if (!ev.shiftKey) {
      if (ax.logY) { const L = Math.log(my); v.y0 = Math.exp(L + (Math.log(v.y0) - L) * f); v.y1 = Math.exp(L + (Math.log(v.y1) - L) * f); }
      else { v.y0 = my + (v.y0 - my) * f; v.y1 = my + (v.y1 - my) * f; }
    }
    clampView(); drawChart(); requestChart(); saveURL();
  }, { passive: false });
  chart.canvas.addEventListener("pointerdown", (ev) => {
    chart.canvas.setPointerCapture(ev.pointerId);
    drag = { x: ev.clientX, y: ev.clientY, v: { ...view() }, moved: false };
  });
  chart.canvas.addEventListener("pointermove", (ev) => {
    const r = chart.canvas.getBoundingClientRect(), ax = axes(r.width, r.height);
    if (drag) {
      const dx = ev.clientX - drag.x, dy = ev.clientY - drag.y;
      if (Math.abs(dx) + Math.abs(dy) > 4) drag.moved = true;
      if (drag.moved) {
        chart.canvas.classList.add("dragging");
        const v = view(), o = drag.v, sx = (o.x1 - o.x0) / (ax.right - ax.left);
        if (ax.logX) { const k = Math.log(o.x1 / o.x0) / (ax.right - ax.left); v.x0 = o.x0 * Math.exp(-dx * k); v.x1 = o.x1 * Math.exp(-dx * k); }
        else { v.x0 = o.x0 - dx * sx; v.x1 = o.x1 - dx * sx; }
        if (ax.logY) { const k = Math.log(o.y1 / o.y0) / (ax.bottom - ax.top); v.y0 = o.y0 * Math.exp(dy * k); v.y1 = o.y1 * Math.exp(dy * k); }
        else { const sy = (o.y1 - o.y0) / (ax.bottom - ax.top); v.y0 = o.y0 + dy * sy; v.y1 = o.y1 + dy * sy; }
        clampView(); drawChart(); requestChart(120);
      }
    }
    hover(ev.clientX - r.left, ev.clientY - r.top, ax);
  });
  chart.canvas.addEventListener("pointerup", (ev) => {
    chart.canvas.classList.remove("dragging");
    if (drag && !drag.moved) {
      const r = chart.canvas.getBoundingClientRect(), ax = axes(r.width, r.height);
      // rounded to the decimals a pixel can tell apart
      const round = (v, px) => { const d = Math.max(0, Math.ceil(-Math.log10(Math.abs(px) || 1e-300))); return d > 20 ? v : Number(v.toFixed(d)); };
      const x = round(ax.invX(ev.clientX - r.left), ax.invX(1) - ax.invX(0));
      const y = round(ax.invY(ev.clientY - r.top), ax.invY(ev.clientY - r.top - 1) - ax.invY(ev.clientY - r.top));
      if (x > 0 && y > 0) choosePoint(fromPlane(x, y));
    }
    drag = null; saveURL();
  });
  chart.canvas.addEventListener("pointerleave", () => { $("hover").hidden = true; });

  function clampView() {
    const top = muTop(driveText());
    const v = view();
    if (S.plane === "rig") {  // log-log: bound each range (1e-3 .. 1e6 Hz, 1 um .. 100 m) and keep it ordered
      if (!(v.x0 > 0 && v.x1 > v.x0 && v.y0 > 0 && v.y1 > v.y0 && isFinite(v.x1) && isFinite(v.y1))) Object.assign(v, rigView(S.l, S.g, S.point));
      const fit1 = (a, b, lo, hi) => { const r = Math.min(b / a, hi / lo); if (a < lo) { a = lo; b = lo * r; } if (b > hi) { b = hi; a = hi / r; }
        if (b / a < 1 + 1e-9) { const c = Math.sqrt(a * b); a = c / (1 + 5e-10); b = c * (1 + 5e-10); } return [a, b]; };
      [v.x0, v.x1] = fit1(v.x0, v.x1, 1e-3, 1e6); [v.y0, v.y1] = fit1(v.y0, v.y1, 1e-6, 100);
      return;
    }
    const B = S.plane === "arnold" ? { x0: 0, x1: 12, y0: 0, y1: 1.2 * top } : { x0: 0, x1: 4 * Math.sqrt(S.l / S.g), y0: 0.3 * S.g / (top * top), y1: 300 * S.g };
    const span = Math.min(v.x1 - v.x0, B.x1 - B.x0), ok = (a) => isFinite(a);
    if (!ok(v.x0) || !ok(v.x1) || !(v.x1 > v.x0)) Object.assign(v, DEFAULT_VIEWS(S.l, S.g, top)[S.plane]);
    if (v.x1 - v.x0 > B.x1 - B.x0) { v.x0 = B.x0; v.x1 = B.x1; }
    if (v.x0 < B.x0) { v.x0 = B.x0; v.x1 = B.x0 + span; }
    if (v.x1 > B.x1) { v.x1 = B.x1; v.x0 = B.x1 - span; }
    if (S.plane === "arnold") {
      const sy = Math.min(v.y1 - v.y0, B.y1 - B.y0);
      if (v.y0 < B.y0) { v.y0 = B.y0; v.y1 = B.y0 + sy; }
      if (v.y1 > B.y1) { v.y1 = B.y1; v.y0 = B.y1 - sy; }
    } else {
      const r = Math.min(v.y1 / v.y0, B.y1 / B.y0);
      if (v.y0 < B.y0) { v.y0 = B.y0; v.y1 = B.y0 * r; }
      if (v.y1 > B.y1) { v.y1 = B.y1; v.y0 = B.y1 / r; }
    }
    // A view narrower than about 1e-13 of its position cannot be told apart in double precision.
    const minX = 1e-13 * Math.max(Math.abs(v.x0), Math.abs(v.x1), 1e-12), minY = 1e-13 * Math.max(Math.abs(v.y1), 1e-12);
    if (v.x1 - v.x0 < minX) { const c = (v.x0 + v.x1) / 2; v.x0 = c - minX / 2; v.x1 = c + minX / 2; }
    if (v.y1 - v.y0 < minY) { const c = (v.y0 + v.y1) / 2; v.y0 = c - minY / 2; v.y1 = c + minY / 2; }
  }

  function hover(px, py, ax) {
    const box = $("hover");
    if (px < ax.left || px > ax.right || py < ax.top || py > ax.bottom) { box.hidden = true; return; }
    const x = ax.invX(px), y = ax.invY(py);
    const { T, A } = fromPlane(x, y), { eps, mu } = toArnold(T, A, S.l, S.g);
    const v = view(), dx = ax.logX ? x * 1e-3 : (v.x1 - v.x0) / 2000;
    const digits = Math.min(16, Math.max(6, Math.ceil(Math.log10(Math.max(Math.abs(x), 1e-300) / dx)) + 1));
    box.hidden = false;
    const rig = S.plane === "rig" || S.rig ? `${fmt(1 / (2 * T), 5)} Hz, stroke ${fmt(1e3 * strokeCoef() * A * T * T, 4)} mm (${fmt(A / S.g, 4)} g)<br>` : "";
    box.innerHTML = rig + (isTower() ? `(T, A) = (${fmt(T, digits)} s, ${fmt(A, 6)} m/s²)<br>`
      : `(ε, μ) = (${fmt(eps, digits)}, ${fmt(mu, 6)})<br>(T, A) = (${fmt(T, digits)} s, ${fmt(A, 6)} m/s²)<br>`) +
      `<span id="hover-verdict">${box.dataset.verdict || "…"}</span>`;
    placeHover(px, py);
    if (!(eps > 0 && mu > 0)) return;
    hoverAt = [px, py];
    hoverNext = isTower() ? { url: "/api/tower/point?" + qs({ ...towerBase(), T, A }) }
      : S.plane === "arnold" ? { eps, mu, zeta: S.zeta } : { T, A, l: S.l, g: S.g, zeta: S.zeta };
    if (!hoverBusy) hoverVerdict();
  }
  // The readout beside the pointer, flipped to its left (or above) where it would leave the chart.
  function placeHover(px, py) {
    const box = $("hover"), W = chart.canvas.clientWidth, H = chart.canvas.clientHeight, bw = box.offsetWidth, bh = box.offsetHeight;
    let left = px + 16, top = py - bh - 10;
    if (left + bw > W - 2) left = px - 16 - bw;
    if (top < 2) top = py + 18;
    box.style.left = Math.max(2, Math.min(left, W - bw - 2)) + "px";
    box.style.top = Math.max(2, Math.min(top, H - bh - 2)) + "px";
  }
  async function hoverVerdict() {
    if (!hoverNext) return;
    const q = hoverNext; hoverNext = null; hoverBusy = true;
    try {
      const rep = await getJSON(q.url || "/api/verdict?" + qs({ ...q, drive: driveText() })), w = q.url ? plainTower(rep) : plain(rep);
      const text = `<b style="color:${rep.stable ? "#1a7f37" : "#b42318"}">${w.head}</b> · ${esc(w.tech)}`;
      $("hover").dataset.verdict = text;
      const hv = $("hover-verdict"); if (hv) { hv.innerHTML = text; const b = $("hover"); if (!b.hidden && hoverAt) placeHover(hoverAt[0], hoverAt[1]); }
    } catch (e) { $("hover").dataset.verdict = ""; }
    hoverBusy = false;
    if (hoverNext) setTimeout(hoverVerdict, 30);
  }

  $("reset-view").onclick = () => {
    hideInset();
    if (isTower()) { S.views.tower = null; drawChart(); requestChart(0); return; }
    S.views[S.plane] = DEFAULT_VIEWS(S.l, S.g, muTop(driveText()), S.point)[S.plane]; drawChart(); requestChart(0); saveURL();
  };
  $("zoom-point").onclick = () => {
    if (!S.point) return;
    const v = view(), q = toPlane(S.point), cx = q.x, cy = q.y;
    const hx = (v.x1 - v.x0) / 20;
    if (S.plane === "rig") {
      const rx = Math.pow(v.x1 / v.x0, 0.05), ry = Math.pow(v.y1 / v.y0, 0.05);
      v.x0 = cx / rx; v.x1 = cx * rx; v.y0 = cy / ry; v.y1 = cy * ry;
      clampView(); drawChart(); requestChart(0); saveURL(); return;
    }
    v.x0 = cx - hx; v.x1 = cx + hx;
    if (S.plane === "arnold") { const hy = (v.y1 - v.y0) / 20; v.y0 = cy - hy; v.y1 = cy + hy; }
    else { const r = Math.pow(v.y1 / v.y0, 0.05); v.y0 = cy / r; v.y1 = cy * r; }
    clampView(); drawChart(); requestChart(0); saveURL();
  };
  function setPlane(plane) {
    S.plane = plane;
    root.querySelectorAll(".planes button").forEach((x) => x.classList.toggle("on", x.dataset.plane === plane));
    if (plane === "rig" && S.point) {  // keep the rig's point in view
      const q = toPlane(S.point), v = view();
      if (!(q.x > v.x0 && q.x < v.x1 && q.y > v.y0 && q.y < v.y1)) S.views.rig = rigView(S.l, S.g, S.point);
    }
    chart.data = null; chart.overlay = null; drawChart(); requestChart(0); saveURL(); tell();
  }
  for (const b of root.querySelectorAll(".planes button")) b.onclick = () => setPlane(b.dataset.plane);

  // "show zone n": a view of Arnold's plane framing tongue n with both edges visible. The edges are
  // asked of the server in a thin band of mu about the chosen point's mu (or 0.3); the window's width
  // is a few tongue widths, its height what keeps both slanting edges inside it.
  async function showZone(n) {
    if (S.plane !== "arnold") setPlane("arnold");
    const top = muTop(driveText());
    let mu0 = S.point ? toArnold(S.point.T, S.point.A, S.l, S.g).mu : 0.3;
    if (!(mu0 > 0.02 && mu0 < 0.95 * top)) mu0 = 0.3;
    const d = Math.min(0.01, mu0 / 4), general = !closedForm();
    const q = { plane: "arnold", eps_min: 0, eps_max: general ? 12 : 60, mu_min: mu0 - d, mu_max: mu0 + d, drive: driveText(),
      zeta: S.zeta, samples: 3, l: S.l, g: S.g };
    try {
      const c = await getJSON("/api/chart?" + qs(q)), z = c.zones.find((zz) => zz.n === n);
      if (!z || z.lo[1] === null || z.hi[1] === null) { chart.error = `zone ${n} is not in reach at μ = ${fmt(mu0, 3)}`; drawChart(); return; }
      const lo = z.lo[1], hi = z.hi[1], w = hi - lo, ys = c.y_values;
      const slope = Math.max(Math.abs(z.lo[2] - z.lo[0]), Math.abs(z.hi[2] - z.hi[0])) / (ys[2] - ys[0]);
      const hy = Math.min(mu0, top - mu0, 0.35, slope > 0 ? (0.9 * w) / slope : 0.35);
      const v = S.views.arnold;
      v.x0 = Math.max(0, lo - 1.2 * w); v.x1 = hi + 1.2 * w; v.y0 = mu0 - hy; v.y1 = mu0 + hy;
      chart.error = null; clampView(); drawChart(); requestChart(0); saveURL();
      showInset(n, hi, top);
    } catch (e) { chart.error = String(e.message || e); drawChart(); }
  }
  $("show-zone").onclick = () => showZone(parseInt($("zone-n").value, 10) || 0);

  // The magnified inset beside a framed zone, as `kapitza chart` draws its thin tongues: the zone's
  // two edges over its whole range of mu, as offsets from their midpoint in a power of ten of eps.
  async function showInset(n, hi0, top) {
    const general = !closedForm(), cap = general ? 12 : 60;
    const q = { plane: "arnold", eps_min: 0, eps_max: Math.min(cap, 4 * hi0), mu_min: 0.001, mu_max: Math.min(0.99, 0.99 * top),
      drive: driveText(), zeta: S.zeta, samples: general ? 60 : 240, l: S.l, g: S.g };
    try {
      const c = await getJSON("/api/chart?" + qs(q)), z = c.zones.find((zz) => zz.n === n);
      if (!z) { hideInset(); return; }
      const rows = [];
      c.y_values.forEach((mu, i) => {
        const a = z.lo[i], b = z.hi[i];
        if (a !== null && b !== null && Number.isFinite(a) && Number.isFinite(b) && b >= a) rows.push([mu, a, b]);
      });
      if (rows.length < 3) { hideInset(); return; }
      inset.data = { n, rows, drive: driveText(), zeta: S.zeta };
      inset.canvas.hidden = false;
      drawInset();
    } catch (e) { hideInset(); }
  }
  function hideInset() { inset.data = null; inset.canvas.hidden = true; }
  function drawInset() {
    const d = inset.data;
    if (!d || inset.canvas.hidden) return;
    if (S.plane !== "arnold" || d.drive !== driveText() || d.zeta !== S.zeta) { hideInset(); return; }
    const { ctx, w, h } = fit(inset.canvas);
    ctx.clearRect(0, 0, w, h);
    const half = Math.max(...d.rows.map(([, a, b]) => 0.5 * (b - a)), 1e-300);
    const k = Math.floor(Math.log10(half)), sc = Math.pow(10, k), xr = Math.max(half / sc, 1e-9) * 1.15;
    const L = 34, R = 8, T = 18, B = 30, pw = w - L - R, ph = h - T - B;
    const X = (x) => L + ((x / xr) + 1) * 0.5 * pw, mus = d.rows.map((r) => r[0]);
    const m0 = Math.min(...mus), m1 = Math.max(...mus), Y = (mu) => T + (1 - (mu - m0) / Math.max(m1 - m0, 1e-12)) * ph;
    ctx.fillStyle = "rgba(107,174,214,0.55)";
    ctx.beginPath();
    d.rows.forEach(([mu, a, b], i) => { const x = X((a - 0.5 * (a + b)) / sc); i ? ctx.lineTo(x, Y(mu)) : ctx.moveTo(x, Y(mu)); });
    [...d.rows].reverse().forEach(([mu, a, b]) => ctx.lineTo(X((b - 0.5 * (a + b)) / sc), Y(mu)));
    ctx.closePath(); ctx.fill();
    for (const [side, colour, dash] of [[1, d.n % 2 ? "#c0392b" : "#1f4e9c", d.n % 2 ? [5, 3] : []],
                                        [2, d.n % 2 ? "#1f4e9c" : "#c0392b", d.n % 2 ? [] : [5, 3]]]) {
      ctx.strokeStyle = colour; ctx.setLineDash(dash); ctx.lineWidth = 1.4; ctx.beginPath();
      d.rows.forEach((r, i) => { const x = X((r[side] - 0.5 * (r[1] + r[2])) / sc); i ? ctx.lineTo(x, Y(r[0])) : ctx.moveTo(x, Y(r[0])); });
      ctx.stroke();
    }
    ctx.setLineDash([]);
    ctx.strokeStyle = "#334155"; ctx.lineWidth = 1; ctx.strokeRect(L, T, pw, ph);
    ctx.fillStyle = "#0f172a"; ctx.font = "11px DejaVu Sans, sans-serif"; ctx.textAlign = "center";
    ctx.fillText(`zone ${d.n} magnified`, L + pw / 2, 12);
    ctx.fillText(`(ε − ε_mid) / 10^${k}`, L + pw / 2, h - 6);
    ctx.font = "10px DejaVu Sans, sans-serif";
    ctx.fillText(fmt(-xr / 1.15, 2), L + 0.5 * pw * (1 - 1 / 1.15), T + ph + 12);
    ctx.fillText("0", L + pw / 2, T + ph + 12);
    ctx.fillText(fmt(xr / 1.15, 2), L + 0.5 * pw * (1 + 1 / 1.15), T + ph + 12);
    ctx.textAlign = "right";
    ctx.fillText(fmt(m1, 2), L - 3, T + 8); ctx.fillText(fmt(m0, 2), L - 3, T + ph);
    ctx.save(); ctx.translate(10, T + ph / 2); ctx.rotate(-Math.PI / 2); ctx.textAlign = "center"; ctx.fillText("μ", 0, 0); ctx.restore();
  }
  inset.canvas.onclick = hideInset;

  // The projector: the real pendulum alone, large; the verdict above it.
  $("projector").onclick = () => {
    const on = shell.classList.toggle("projector");
    $("projector").textContent = on ? "back to the explorer" : "projector view";
    anim.prepare();
  };
  const onKey = (ev) => { if (ev.key === "Escape" && shell.classList.contains("projector")) $("projector").click(); };
  document.addEventListener("keydown", onKey);

  // Two fingers on the chart: pinch to zoom about their middle (the page itself does not zoom there).
  const touches = new Map();
  let pinch = null;
  chart.canvas.addEventListener("pointerdown", (ev) => {
    if (ev.pointerType !== "touch") return;
    touches.set(ev.pointerId, { x: ev.clientX, y: ev.clientY });
    if (touches.size === 2) { const [a, b] = [...touches.values()]; pinch = { d: Math.hypot(a.x - b.x, a.y - b.y), v: { ...view() } }; drag = null; }
  });
  chart.canvas.addEventListener("pointermove", (ev) => {
    if (!touches.has(ev.pointerId)) return;
    touches.set(ev.pointerId, { x: ev.clientX, y: ev.clientY });
    if (!pinch || touches.size !== 2) return;
    const [a, b] = [...touches.values()], d = Math.hypot(a.x - b.x, a.y - b.y);
    if (!(d > 0)) return;
    const r = chart.canvas.getBoundingClientRect(), ax = axes(r.width, r.height), f = pinch.d / d;
    const mx = ax.invX((a.x + b.x) / 2 - r.left), my = ax.invY((a.y + b.y) / 2 - r.top), v = view(), o = pinch.v;
    const zoom = (c, lo, hi, log) => log ? [Math.exp(Math.log(c) + (Math.log(lo) - Math.log(c)) * f), Math.exp(Math.log(c) + (Math.log(hi) - Math.log(c)) * f)]
      : [c + (lo - c) * f, c + (hi - c) * f];
    [v.x0, v.x1] = zoom(mx, o.x0, o.x1, ax.logX); [v.y0, v.y1] = zoom(my, o.y0, o.y1, ax.logY);
    clampView(); drawChart(); requestChart(120);
  });
  const endTouch = (ev) => { touches.delete(ev.pointerId); if (touches.size < 2 && pinch) { pinch = null; saveURL(); } };
  chart.canvas.addEventListener("pointerup", endTouch);
  chart.canvas.addEventListener("pointercancel", endTouch);
  $("share").onclick = async () => {
    saveURL();
    try { await navigator.clipboard.writeText(location.href); $("share").textContent = "link copied"; }
    catch (e) { $("share").textContent = "link in the address bar"; }
    setTimeout(() => ($("share").textContent = "copy link"), 1800);
  };

  // ------------------------------------------------------------------ inputs
  function setInputs() {
    $("l").value = S.l; $("l-s").value = Math.log10(S.l); $("g").value = S.g;
    $("drive").value = S.drive; syncParam();
    if (S.overlay && ![...$("overlay").options].some((o) => o.value === S.overlay)) $("overlay").add(new Option(S.overlay, S.overlay));
    $("zeta").value = S.zeta; $("overlay").value = S.overlay; $("theta0").value = S.theta0; $("theta0-s").value = S.theta0;
    $("speed").value = String(S.speed);
    $("mu-s").max = String(0.999 * muTop(driveText()));
    root.querySelectorAll(".planes button").forEach((x) => x.classList.toggle("on", x.dataset.plane === S.plane));
    $("rig-mode").checked = S.rig; shell.classList.toggle("rig-on", S.rig);
    $("rig-rod").value = S.rod; $("rig-kind").value = S.rodKind; $("rig-given").value = S.given; $("damp-unit").value = S.dampUnit;
    setDampInput();
    $("links").value = String(S.links); $("link-kind").value = S.linkKind; $("link-c").value = S.jointDamping;
    for (let k = 1; k <= 4; k++) { $(`link-L${k}`).value = S.chain[k - 1]; $(`link-m${k}`).value = S.masses[k - 1]; }
    syncTower();
    setPointInputs();
  }
  // ------------------------------------------------------------------ the tower
  // From 2 links on, the chart is the tower's band on the rig plane (the other planes are the single
  // pendulum's), the point's answers and motion are the tower's.
  const captions = [...root.querySelectorAll(".plots figcaption")].map((c) => c.textContent), titles = {};
  function syncTower() {
    const on = isTower();
    if (!towerOK) $("tower-fields").hidden = true;
    shell.classList.toggle("tower-on", on);
    root.querySelectorAll(".link-row").forEach((r) => { r.hidden = parseInt(r.dataset.k, 10) > S.links; });
    for (const id of ["plane-arnold", "plane-physical", "rig-mode", "show-zone", "zone-n", "overlay"]) {
      if (!(id in titles)) titles[id] = $(id).title;
      $(id).disabled = on; $(id).title = on ? "the tower is shown on the frequency–stroke plane (1 link: the single pendulum)" : titles[id];
    }
    // the single pendulum's own length and damping mean nothing to the tower: out of sight
    for (const id of ["l", "l-s", "zeta", "rig-rod", "rig-kind", "damp"]) {
      const el = $(id), box = el.closest("label") || el;
      box.style.display = on ? "none" : "";
    }
    $("tower-note").textContent = on ? "the chart shows the tower's band; the motion is the full (nonlinear) tower's" : "";
    const tc = [`angle of the top link θ${"₁₂₃₄"[S.links - 1]}(t), full motion`, `phase portrait of the top link`, `stroboscopic map of the top link at t = 2kT`];
    root.querySelectorAll(".plots figcaption").forEach((c, i) => { c.textContent = on ? tc[i] : captions[i]; });
  }
  const towerKey = () => JSON.stringify([S.links, S.linkKind, S.jointDamping, S.chain, S.masses]);
  function onTower() {
    const was = isTower(), before = towerKey();
    S.links = Math.max(1, Math.min(4, parseInt($("links").value, 10) || 1)); S.linkKind = $("link-kind").value;
    const c = parseFloat($("link-c").value);
    S.jointDamping = c > 0 ? c : 0;
    for (let k = 1; k <= 4; k++) {
      const L = parseFloat($(`link-L${k}`).value), mk = parseFloat($(`link-m${k}`).value);
      if (L > 0) S.chain[k - 1] = L;
      if (mk > 0) S.masses[k - 1] = mk;
    }
    if (towerKey() === before) return;  // a change event that changed nothing (e.g. a blur): keep the view and band
    if (isTower() && !was) {  // the tower stands on a shaker: the rig plane, in the rig's units
      S.rig = true; $("rig-mode").checked = true; shell.classList.add("rig-on");
      S.plane = "rig"; root.querySelectorAll(".planes button").forEach((x) => x.classList.toggle("on", x.dataset.plane === "rig"));
    }
    syncTower();
    S.views.tower = null; S.towerNew = isTower();
    chart.tower = null; chart.data = null; chart.overlay = null;
    drawChart(); requestChart(0); saveURL(); updateExports();
    if (!isTower() && was && S.point) {  // the single pendulum again, its point kept in view
      const q = toPlane(S.point), v = S.views.rig;
      if (!(q.x > v.x0 && q.x < v.x1 && q.y > v.y0 && q.y < v.y1)) S.views.rig = rigView(S.l, S.g, S.point);
      choosePoint(S.point);
    }
  }
  for (const id of ["links", "link-kind", "link-c", "link-L1", "link-L2", "link-L3", "link-L4", "link-m1", "link-m2", "link-m3", "link-m4"]) {
    $(id).addEventListener("change", onTower);
  }
  // A new tower's first band: keep the point where it lies in the band's window, else choose one in
  // the middle of the band (where the tower stands), and ask its verdict and motion.
  function towerStart(d) {
    const v = view(), q = S.point ? toPlane(S.point) : null;
    if (!(q && q.x > v.x0 && q.x < v.x1 && q.y > v.y0 && q.y < v.y1)) {
      const b = d.band, cells = [];
      b.stable.forEach((row, i) => row.forEach((on, j) => { if (on) cells.push([i, j]); }));
      if (cells.length) {
        const rows = cells.map((c) => c[0]).sort((a, c) => a - c), i = rows[Math.floor(rows.length * 0.4)];
        const js = cells.filter((c) => c[0] === i).map((c) => c[1]), j = js[Math.floor(js.length * 0.3)];
        const f = b.frequency[j], st = b.stroke[i], T = 1 / (2 * f);
        S.point = { T, A: st / (strokeCoef() * T * T) };
      }
    }
    if (S.point) choosePoint(S.point);
  }
  function setDampInput() {
    const c = 2 * S.zeta * Math.sqrt(S.g / S.l);
    $("damp").value = S.dampUnit === "zeta" ? S.zeta : Number(c.toPrecision(6));
  }
  function setPointInputs(except) {
    const P = S.point;
    const put = (id, v, d = 10) => { if (id !== except) $(id).value = P ? Number(v.toPrecision(d)) : ""; };
    if (!P) { ["T", "freq", "A", "eps", "mu", "rig-f", "rig-x"].forEach((id) => ($(id).value = "")); return; }
    const { eps, mu } = toArnold(P.T, P.A, S.l, S.g);
    put("T", P.T); put("freq", 1 / (2 * P.T)); put("A", P.A); put("eps", eps); put("mu", mu);
    const f = 1 / (2 * P.T), x = 1e3 * strokeCoef() * P.A * P.T * P.T * (S.given === "stroke" ? 1 : 0.5);
    put("rig-f", f, 6); put("rig-x", x, 6);
    if (except !== "rig-f-s") $("rig-f-s").value = Math.log10(f);
    if (except !== "rig-x-s") $("rig-x-s").value = Math.log10(x);
    $("rig-g").textContent = `A = ${fmt(P.A, 4)} m/s² = ${fmt(P.A / S.g, 4)} g`;
    if (except !== "T-s") $("T-s").value = Math.log10(P.T);
    if (except !== "A-s") $("A-s").value = Math.log10(P.A);
    if (except !== "eps-s") $("eps-s").value = eps;
    if (except !== "mu-s") $("mu-s").value = mu;
  }
  function pointFrom(id, value) {
    const P = S.point || { T: 0.15, A: 100 };
    if (!(isFinite(value) && value > 0)) return null;
    const { eps, mu } = toArnold(P.T, P.A, S.l, S.g);
    switch (id) {
      case "T": case "T-s": return { T: value, A: P.A };
      case "freq": return { T: 1 / (2 * value), A: P.A };
      case "A": case "A-s": return { T: P.T, A: value };
      case "eps": case "eps-s": return toPhysical(value, mu, S.l, S.g);
      case "mu": case "mu-s": return toPhysical(eps, value, S.l, S.g);
      case "rig-f": case "rig-f-s": {  // the frequency at this stroke
        const st = strokeCoef() * P.A * P.T * P.T, T = 1 / (2 * value);
        return { T, A: st / (strokeCoef() * T * T) };
      }
      case "rig-x": case "rig-x-s": {  // the amplitude or stroke [mm] at this frequency
        const st = (S.given === "stroke" ? 1 : 2) * value / 1e3;
        return { T: P.T, A: st / (strokeCoef() * P.T * P.T) };
      }
    }
    return null;
  }
  let pointTimer = null;
  for (const id of ["T", "freq", "A", "eps", "mu", "T-s", "A-s", "eps-s", "mu-s", "rig-f", "rig-f-s", "rig-x", "rig-x-s"]) {
    $(id).addEventListener("input", () => {
      let v = parseFloat($(id).value);
      if (["T-s", "A-s", "rig-f-s", "rig-x-s"].includes(id)) v = Math.pow(10, v);
      const P = pointFrom(id, v);
      if (!P) return;
      S.point = P; setPointInputs(id);
      if (S.plane === "rig") {  // keep the rig in view: a point leaving it re-centres the window on it
        const q = toPlane(P), v = view();
        if (!(q.x > v.x0 && q.x < v.x1 && q.y > v.y0 && q.y < v.y1)) { S.views.rig = rigView(S.l, S.g, P); requestChart(150); }
      }
      drawChart(); saveURL();
      invalidatePoint();
      clearTimeout(pointTimer); pointTimer = setTimeout(() => choosePoint(S.point, id), 180);
    });
  }
  // The current answers no longer belong to the choice: drop them and say so at once.
  function invalidatePoint() {
    if (pointAbort) pointAbort.abort();
    pointSeq++;
    if (S.point) markBusy();
  }
  async function onRig() {
    // A view left as the default follows the drive's default (mu up to its mu_max where above 1).
    const was = DEFAULT_VIEWS(S.l, S.g, muTop(driveText())), keep = {};
    for (const k of ["arnold", "physical"]) keep[k] = ["x0", "x1", "y0", "y1"].some((c) => S.views[k][c] !== was[k][c]);
    S.l = parseFloat($("l").value) > 0 ? parseFloat($("l").value) : S.l;
    S.g = parseFloat($("g").value) > 0 ? parseFloat($("g").value) : S.g;
    const before = S.drive;
    S.drive = $("drive").value;
    const dp = driveParam();  // the field holds this drive's number (another drive's field is refilled)
    if (dp && S.drive === before) { const v = parseFloat($("duty").value); S.params[S.drive] = isFinite(v) ? v : dp.default; }
    syncParam();
    S.zeta = Math.max(0, parseFloat($("zeta").value) || 0); S.overlay = $("overlay").value;
    if (S.point) invalidatePoint();  // the panel greys at once: its report is of the old choice
    await ensureInfo();  // mu_max and the rest of the drive now chosen
    const now = DEFAULT_VIEWS(S.l, S.g, muTop(driveText()));
    for (const k of ["arnold", "physical"]) if (!keep[k]) S.views[k] = now[k];
    $("mu-s").max = String(0.999 * muTop(driveText()));
    $("l-s").value = Math.log10(S.l);
    setDampInput();
    saveURL(); requestChart(100); tell();
    if (S.point) { setPointInputs(); invalidatePoint(); clearTimeout(pointTimer); pointTimer = setTimeout(() => choosePoint(S.point), 200); }
  }
  for (const id of ["l", "g", "drive", "duty", "zeta", "overlay"]) $(id).addEventListener("change", onRig);
  $("drive").addEventListener("input", onRig);
  // The rig in measured units: rod length and kind set l; the damping as zeta or c [1/s].
  function onRod() {
    const L = parseFloat($("rig-rod").value);
    if (!(L > 0)) return;
    S.rod = L; S.rodKind = $("rig-kind").value;
    $("l").value = Number((S.rodKind === "rod" ? (2 * L) / 3 : L).toPrecision(12));
    onRig();
  }
  $("rig-rod").addEventListener("change", onRod);
  $("rig-kind").addEventListener("change", onRod);
  $("rig-given").addEventListener("change", () => {
    S.given = $("rig-given").value; setPointInputs(); saveURL();
    if (S.point) { invalidatePoint(); clearTimeout(pointTimer); pointTimer = setTimeout(() => choosePoint(S.point), 200); }
  });
  $("damp-unit").addEventListener("change", () => { S.dampUnit = $("damp-unit").value; setDampInput(); saveURL(); });
  $("damp").addEventListener("change", () => {
    const v = Math.max(0, parseFloat($("damp").value) || 0);
    $("zeta").value = Number((S.dampUnit === "zeta" ? v : v / (2 * Math.sqrt(S.g / S.l))).toPrecision(8));
    onRig();
  });
  $("rig-mode").addEventListener("change", () => {
    S.rig = $("rig-mode").checked; shell.classList.toggle("rig-on", S.rig);
    if (S.rig) {
      if (Math.abs(S.l - (S.rodKind === "rod" ? (2 * S.rod) / 3 : S.rod)) > 1e-12 * S.l) { S.rodKind = "point"; S.rod = S.l; }
      $("rig-rod").value = S.rod; $("rig-kind").value = S.rodKind;
      setPlane("rig");
    }
    setPointInputs(); saveURL();
    if (S.point) { invalidatePoint(); clearTimeout(pointTimer); pointTimer = setTimeout(() => choosePoint(S.point), 200); }
  });
  $("l-s").addEventListener("input", () => { $("l").value = Number(Math.pow(10, parseFloat($("l-s").value)).toPrecision(4)); onRig(); });
  $("theta0").addEventListener("change", () => { S.theta0 = parseFloat($("theta0").value) || 0; $("theta0-s").value = S.theta0; saveURL(); tell(); renderVerdict(); fetchMotion(); });
  $("theta0-s").addEventListener("input", () => {
    S.theta0 = parseFloat($("theta0-s").value); $("theta0").value = S.theta0; saveURL(); tell(); renderVerdict();
    clearTimeout(pointTimer); pointTimer = setTimeout(fetchMotion, 150);
  });
  $("speed").addEventListener("change", () => { const t = anim.simTime(); S.speed = parseFloat($("speed").value); anim.seek(t); saveURL(); });
  $("play").onclick = () => anim.toggle();
  $("restart").onclick = () => anim.seek(0);

  // ------------------------------------------------------------------ the point: report and motion
  // A point's answers come in three requests, quickest first: the verdict (/api/verdict, the
  // multipliers alone), the report with margins and directions (/api/point), and the safe tilt
  // (/api/safe_tilt, which follows the real pendulum). The panel greys and says "computing" the moment
  // the point, the drive or the damping changes; a newer choice aborts the older requests, and an
  // answer for anything but the current choice is dropped (pointSeq).
  let pointSeq = 0, pointAbort = null;
  const PANEL = { verdict: null, report: null, safe: null };
  function pointQuery() {
    if (isTower()) return { ...towerBase(), frequency: 1 / (2 * S.point.T), stroke: strokeCoef() * S.point.A * S.point.T * S.point.T };
    const q = { T: S.point.T, A: S.point.A, l: S.l, g: S.g, drive: driveText(), zeta: S.zeta };
    if (S.rig) {  // the answers in the quantity the rig is set by (amplitude or stroke, frequency)
      const st = strokeCoef() * S.point.A * S.point.T * S.point.T;
      delete q.T; delete q.A;
      q.frequency = 1 / (2 * S.point.T);
      q[S.given] = S.given === "stroke" ? st : st / 2;
    }
    return q;
  }
  function markBusy(what = "computing …") {
    PANEL.verdict = null; PANEL.report = null; PANEL.safe = null;
    const el = $("verdict"); el.className = "verdict busy"; el.dataset.state = "busy"; el.dataset.verdict = ""; PANEL.query = null;
    el.innerHTML = `<span class="head">${what}</span><small>${esc(describeChoice())}</small>`;
    $("report").innerHTML = ""; $("report-box").classList.add("stale");
    anim.clear("computing …");
  }
  function describeChoice() {
    if (!S.point) return "";
    const f = 1 / (2 * S.point.T), st = strokeCoef() * S.point.A * S.point.T * S.point.T;
    const d = shortDrive((info() || {}).label || driveText());
    return `${isTower() ? `${S.links}-link tower · ` : ""}${d} · ${fmt(f, 4)} Hz, ${S.given === "stroke" ? "stroke " + fmt(1e3 * st, 4) : "amplitude " + fmt(500 * st, 4)} mm` +
      ` (A = ${fmt(S.point.A / S.g, 3)} g)${S.zeta > 0 ? ` · damping ζ = ${fmt(S.zeta, 3)}` : ""}`;
  }
  async function choosePoint(Pt, from) {
    S.point = { T: Pt.T, A: Pt.A };
    if (host.onPoint) host.onPoint({ ...S.point, ...toArnold(S.point.T, S.point.A, S.l, S.g) });
    setPointInputs(from); drawChart(); saveURL(); updateExports();
    if (pointAbort) pointAbort.abort();
    pointAbort = new AbortController();
    const seq = ++pointSeq, signal = pointAbort.signal, q = pointQuery();
    markBusy();
    fetchMotion();
    const current = () => seq === pointSeq;
    if (isTower()) {  // the tower: one answer (kapitza.analyze_chain), the verdict and the report together
      try {
        const r = await getJSON("/api/tower/point?" + qs(q), signal);
        if (!current()) return;
        PANEL.verdict = r; PANEL.report = r; PANEL.query = q; renderVerdict(); showReport(r);
      } catch (e) { if (e.name !== "AbortError" && current()) showError(e); }
      return;
    }
    try {
      const v = await getJSON("/api/verdict?" + qs(q), signal);
      if (!current()) return;
      PANEL.verdict = v; PANEL.query = q; renderVerdict();
      const periods = safePeriods();
      const [rep, safe] = await Promise.all([
        getJSON("/api/point?" + qs(q), signal).then((r) => { if (current()) { PANEL.report = r; renderVerdict(); showReport(r); } return r; }),
        v.stable ? getJSON("/api/safe_tilt?" + qs({ ...q, periods }), signal)
          .then((r) => { if (current()) { PANEL.safe = r; renderVerdict(); } return r; }) : null,
      ]);
    } catch (e) { if (e.name !== "AbortError" && current()) showError(e); }
  }
  // The safe tilt over the periods the motion is shown for (at most 40 where DOP853 follows it).
  function safePeriods() {
    const n = motionParams().periods, integrated = !(info() || {}).exact_motion;
    return integrated ? Math.min(n, 40) : n;
  }
  // A verdict in plain words first, the technical term after.
  function plain(v) {
    const t = v.verdict || "";
    if (v.stable) return { head: "stays up", tech: t.replace(/^stable \(zone (\d+)\)/, "stable, zone $1") };
    if (/always unstable/.test(t)) return { head: "falls", tech: "the pivot never accelerates down faster than g" };
    if (/too weak/.test(t)) return { head: "falls", tech: "the drive is too weak to hold it up (below zone 0)" };
    if (/4T|period doubling/.test(t) || v.kind === "4T") return { head: "falls", tech: "period-doubling resonance (4T-periodic, multipliers negative)" };
    if (/2T-type/.test(t)) return { head: "falls", tech: "resonance (2T-periodic, multipliers positive)" };
    return { head: "falls", tech: "unstable (multipliers real)" };
  }
  // The tower's verdict in plain words: which mode fails first and how is the technical part.
  function plainTower(v) {
    return { head: v.stable ? "stands" : "falls", tech: v.verdict || "" };
  }
  function renderTower(el, v) {
    const w = plainTower(v), info = [];
    info.push(`modes (equivalent single pendulums): l = ${v.modal_lengths.map((x) => fmt(x, 4)).join(", ")} m`);
    if (v.frequency_lo !== null && v.frequency_lo !== undefined) {
      info.push(`stands at this stroke for ${fmt(v.frequency_lo, 4)} Hz < frequency < ${v.frequency_hi === null ? "∞" : fmt(v.frequency_hi, 4) + " Hz"}` +
        (v.stroke_lo !== null && v.stroke_lo !== undefined ? `; at this frequency for ${fmt(1e3 * v.stroke_lo, 4)} mm < stroke < ${fmt(1e3 * v.stroke_hi, 4)} mm` : ""));
    }
    info.push(`<span class="nums">growth ${fmt(v.growth, 4)} per period 2T · margin ${fmt(100 * v.margin, 3)} %</span>`);
    el.innerHTML = `<span class="head">The tower ${w.head}</span> <span class="tech">(${esc(w.tech)})</span><small>${info.join("<br>")}</small>`;
  }
  function renderVerdict() {
    const el = $("verdict"), v = PANEL.report || PANEL.verdict;
    if (!v) return;
    if (isTower() && v.modal_lengths) {
      el.className = "verdict " + (v.stable ? "stable" : "unstable"); el.dataset.state = "report";
      el.dataset.verdict = v.verdict; el.dataset.drive = PANEL.query ? PANEL.query.drive : "";
      renderTower(el, v);
      return;
    }
    el.className = "verdict " + (v.stable ? "stable" : "unstable");
    el.dataset.state = PANEL.report ? "report" : "verdict";
    el.dataset.verdict = v.verdict; el.dataset.drive = PANEL.query ? PANEL.query.drive : "";
    const w = plain(v), parts = [];
    parts.push(`<span class="head">The pendulum ${w.head}</span> <span class="tech">(${esc(w.tech)})</span>`);
    const info = [];
    if (v.stable) {
      if (PANEL.safe && PANEL.safe.safe_tilt > 0) {
        const th = PANEL.safe.safe_tilt, deg = (th * 180) / Math.PI;
        info.push(`<span id="safe-tilt" data-safe="${th}">stands for starting tilts below <b>${angle(th)} rad</b> (${angle(deg)}°)` +
          ` over ${PANEL.safe.periods} periods</span>`);
        if (Math.abs(S.theta0) > th) {
          info.push(`<span class="warn" id="will-fall">This start (θ₀ = ${fmt(S.theta0, 3)} rad) will fall, although the small-tilt verdict is stable: ` +
            `the real pendulum stands only for tilts below ${angle(th)} rad. <button id="set-safe">set θ₀ = ${angle(safeStart(th))} rad</button></span>`);
        }
      } else if (PANEL.safe) info.push(`<span id="safe-tilt" data-safe="0">no starting tilt above ${"1e-9"} rad stays up over ${PANEL.safe.periods} periods</span>`);
      else info.push(`<span class="pending">safe starting tilt: computing …</span>`);
    }
    if (PANEL.report && PANEL.report.directions && PANEL.report.directions.length) {
      const dirs = PANEL.report.directions.map((d) => `<li>${esc(d.text)}</li>`).join("");
      info.push(`<span class="dirs-title">${v.stable ? "room before it falls:" : "to make it stand:"}</span><ul class="dirs">${dirs}</ul>`);
    } else if (!PANEL.report) info.push(`<span class="pending">margins and ranges: computing …</span>`);
    info.push(`<span class="nums">ε = ${fmt(v.eps, 8)}, μ = ${fmt(v.mu, 8)} · growth ${fmt(v.growth, 4)} per period 2T</span>`);
    el.innerHTML = parts.join("") + `<small>${info.join("<br>")}</small>`;
    const b = $("set-safe");
    if (b) b.onclick = () => { setTheta0(safeStart(PANEL.safe.safe_tilt)); };
  }
  // A small angle as a teacher reads it: 0.23, 0.0042, 3.5 × 10⁻⁶.
  function angle(th) {
    if (th >= 1e-3) return fmt(th, 2);
    const e = Math.floor(Math.log10(th)), m = th / Math.pow(10, e);
    const sup = String(e).replace(/-/g, "⁻").replace(/\d/g, (c) => "⁰¹²³⁴⁵⁶⁷⁸⁹"[+c]);
    return `${fmt(m, 2)} × 10${sup}`;
  }
  // A start comfortably inside the safe tilt: half of it, rounded down to two digits.
  function safeStart(th) { const x = 0.5 * th, p = Math.pow(10, Math.floor(Math.log10(x)) - 1); return Math.floor(x / p) * p; }
  function setTheta0(v) {
    S.theta0 = Number(v.toPrecision(3)); $("theta0").value = S.theta0; $("theta0-s").value = S.theta0;
    saveURL(); tell(); renderVerdict(); fetchMotion();
  }
  function showReport(rep) {
    $("report-box").classList.remove("stale");
    $("report").innerHTML = rep.lines.map(([k, v]) => `<tr><th>${esc(k)}</th><td>${esc(v)}</td></tr>`).join("");
  }
  function showError(e) {
    const el = $("verdict"); el.className = "verdict none"; el.dataset.state = "error"; el.textContent = String(e.message || e);
  }
  const esc = (s) => String(s).replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" })[c]);

  function motionParams() {
    const P = S.point, periods = Math.max(20, Math.min(200, Math.round(8 / (2 * P.T))));
    return { T: P.T, A: P.A, l: S.l, g: S.g, drive: driveText(), zeta: S.zeta, theta0: S.theta0, periods, points_per_period: 60 };
  }
  let motionSeq = 0, motionAbort = null;
  async function fetchMotion() {
    if (!S.point) return;
    if (motionAbort) motionAbort.abort();
    motionAbort = new AbortController();
    const seq = ++motionSeq;
    anim.clear("computing the motion …");
    try {
      if (isTower()) {
        const m = await getJSON("/api/tower/motion?" + qs({ ...towerBase(), T: S.point.T, A: S.point.A, theta0: S.theta0 }), motionAbort.signal);
        if (seq !== motionSeq) return;
        anim.load(towerMotion(m));
        return;
      }
      const m = await getJSON("/api/motion?" + qs(motionParams()), motionAbort.signal);
      if (seq !== motionSeq) return;
      anim.load(m);
    } catch (e) { if (e.name !== "AbortError" && seq === motionSeq) { anim.clear(String(e.message || e)); } }
    updateExports();
  }

  // The tower's motion as the plots read a motion: the top link's angle (every link's for the stage)
  // and the stroboscopic points at t = 2kT.
  function towerMotion(m) {
    const top = m.n_links - 1, every = m.points_per_period;
    m.tower = true; m.thetas = m.theta; m.theta = m.thetas[top]; m.dtheta = m.dtheta[top];
    m.l = m.lengths.reduce((a, b) => a + b, 0);
    const st = { t: [], theta: [], dtheta: [] };
    for (let j = 0; j < m.t.length; j += every) { st.t.push(m.t[j]); st.theta.push(m.theta[j]); st.dtheta.push(m.dtheta[j]); }
    m.strobe = st;
    return m;
  }

  // ------------------------------------------------------------------ the animation
  const wrap = (th) => th - 2 * Math.PI * Math.round(th / (2 * Math.PI));
  const anim = {
    m: null, t0: performance.now(), offset: 0, playing: true, frames: 0, fps: 0, fpsT: performance.now(), fpsN: 0,
    last: -1, note: "",
    load(m) {
      this.m = m; this.note = "";
      const n = m.t.length;
      m.thw = m.theta.map(wrap);
      m.pmax = Math.max(...m.pivot.map(Math.abs), 1e-9);
      const lim = (arr) => { let a = 0; for (const x of arr) if (isFinite(x)) a = Math.max(a, Math.abs(x)); return a; };
      m.thMax = Math.max(lim(m.theta), 0.05) * 1.1;
      m.omMax = Math.max(lim(m.dtheta), 0.05) * 1.1;
      m.n = n; this.prepare(); this.seek(0);
    },
    clear(note) {
      this.m = null; this.note = note; this.prepare();
      for (const p of plots) { const { ctx, w, h } = fit(p.canvas); ctx.clearRect(0, 0, w, h); }  // no old motion beside a new choice
    },
    simTime() { return this.playing ? ((performance.now() - this.t0) / 1000) * S.speed + this.offset : this.offset; },
    seek(t) { this.offset = t; this.t0 = performance.now(); this.last = -1; for (const p of plots) p.reset(); },
    toggle() {
      this.offset = this.simTime(); this.t0 = performance.now(); this.playing = !this.playing;
      $("play").textContent = this.playing ? "pause" : "play";
    },
    prepare() { for (const p of plots) p.prepare(this.m); },
  };
  function index(m, t) {
    // samples are evenly spaced
    const dt = m.t[1] - m.t[0], f = Math.min(Math.max(t / dt, 0), m.n - 1), i = Math.min(Math.floor(f), m.n - 2);
    return { i, f: f - i };
  }
  const lerp = (a, k) => a[k.i] + (a[k.i + 1] - a[k.i]) * k.f;

  function drawStage(t) {
    const { ctx, w, h } = fit($("stage")), m = anim.m;
    ctx.clearRect(0, 0, w, h);
    if (!m) { ctx.fillStyle = "#6b7685"; ctx.font = "15px DejaVu Sans, sans-serif"; ctx.textAlign = "center";
      ctx.fillText(anim.note || "choose a point on the chart", w / 2, h / 2); return; }
    // A pivot travelling far more than the rod is long is drawn shortened (said under the picture),
    // so the rod stays large enough to see.
    if (m.tower) { drawTower(ctx, w, h, m, t); return; }
    const kp = Math.min(1, (0.6 * m.l) / m.pmax), pmax = m.pmax * kp;
    const k = index(m, t), piv = lerp(m.pivot, k) * kp;
    const th = lerp(m.theta, k), thl = m.theta_linear ? lerp(m.theta_linear, k) : null;
    const solo = shell.classList.contains("projector");
    const L = m.l, s = Math.min((solo ? w : w / 2) * 0.4 / L, (h - 60) / (2.15 * L + 2 * pmax));
    const baseY = 28 + (L + pmax) * s;
    const scene = (cx, theta, title, color, note, linear) => {
      // rail of the shaker and the pivot's travel
      ctx.strokeStyle = "#c9d1dc"; ctx.lineWidth = 6; ctx.lineCap = "round";
      ctx.beginPath(); ctx.moveTo(cx, baseY - pmax * s - 14); ctx.lineTo(cx, baseY + pmax * s + 14); ctx.stroke();
      const py = baseY - piv * s;
      ctx.setLineDash([4, 4]); ctx.strokeStyle = "#b8c2cf"; ctx.lineWidth = 1;
      ctx.beginPath(); ctx.moveTo(cx, py); ctx.lineTo(cx, py - L * s * 1.08); ctx.stroke(); ctx.setLineDash([]);
      if (theta === null) { ctx.fillStyle = "#6b7685"; ctx.font = "13px DejaVu Sans"; ctx.textAlign = "center"; ctx.fillText(note, cx, h / 2); return; }
      // The linear model's angle may grow without bound: drawn at most lying flat (|theta| <= pi/2 shown
      // as it is, beyond that the rod lies on the side it went).
      const shown = linear ? Math.max(-Math.PI / 2, Math.min(Math.PI / 2, theta)) : theta;
      const bx = cx + Math.sin(shown) * L * s, by = py - Math.cos(shown) * L * s;
      ctx.strokeStyle = "#2d3540"; ctx.lineWidth = 4; ctx.beginPath(); ctx.moveTo(cx, py); ctx.lineTo(bx, by); ctx.stroke();
      ctx.fillStyle = color; ctx.beginPath(); ctx.arc(bx, by, Math.max(7, 0.07 * L * s), 0, 2 * Math.PI); ctx.fill();
      ctx.fillStyle = "#16263d"; ctx.fillRect(cx - 16, py - 6, 32, 12);
      ctx.fillStyle = "#fff"; ctx.beginPath(); ctx.arc(cx, py, 3, 0, 2 * Math.PI); ctx.fill();
      const fs = solo ? 22 : w < 520 ? 12 : 14;
      ctx.fillStyle = "#16263d"; ctx.font = `600 ${fs}px DejaVu Sans, sans-serif`; ctx.textAlign = "center"; ctx.textBaseline = "top";
      fitText(ctx, title, cx, 6, solo ? w - 20 : w / 2 - 12);
      ctx.font = `${solo ? 18 : 12.5}px DejaVu Sans, sans-serif`; ctx.textBaseline = "bottom";
      const big = Math.abs(theta) > (linear ? Math.PI / 2 : Math.PI);
      const fallen = !linear && Math.abs(wrap(theta)) > Math.PI / 2;
      ctx.fillText(`θ = ${fmt(theta, 4)} rad${big && !linear ? " (turned over)" : fallen ? " (fallen)" : ""}`, cx, h - 6);
      if (big && linear) {
        // Linearly stable motion is bounded, but e^(w_h T) can make it enormous within each period;
        // unstable motion grows without bound. Say which.
        const st = PANEL.verdict && PANEL.verdict.stable;
        ctx.fillStyle = st ? "#6b4e00" : "#b42318"; ctx.font = `${w < 520 ? 11 : 12.5}px DejaVu Sans, sans-serif`;
        fitText(ctx, st ? "bounded, but far beyond small angles within each period" : "grows without bound (unstable)", cx, h - 24, w / 2 - 12);
      }
    };
    if (kp < 1) {
      ctx.fillStyle = "#6b7685"; ctx.font = `${solo ? 15 : 11}px DejaVu Sans, sans-serif`; ctx.textAlign = "right"; ctx.textBaseline = "bottom";
      ctx.fillText(`pivot travel drawn ${fmt(kp, 2)}× to scale`, w - 6, solo ? h - 30 : h - 40);
    }
    if (solo) {
      scene(w * 0.5, th, "the real pendulum", COLORS.nonlinear, "", false);
      return;
    }
    scene(w * 0.27, thl, "small-angle (linear) model", COLORS.linear, m.summary && typeof m.summary.linear === "string" ? m.summary.linear : "", true);
    scene(w * 0.73, th, "the real pendulum", COLORS.nonlinear, "", false);
    ctx.strokeStyle = "#e4e8ee"; ctx.lineWidth = 1; ctx.beginPath(); ctx.moveTo(w / 2, 30); ctx.lineTo(w / 2, h - 26); ctx.stroke();
  }

  // The tower on its pivot: every link at its angle, one on another, as the full equations move it.
  function drawTower(ctx, w, h, m, t) {
    const solo = shell.classList.contains("projector"), k = index(m, t);
    const kp = Math.min(1, (0.3 * m.l) / m.pmax), pmax = m.pmax * kp, piv = lerp(m.pivot, k) * kp;
    const H = m.l, s = Math.min((solo ? 0.8 : 0.9) * w / (2.1 * H), (h - 70) / (1.1 * H + 2 * pmax + 0.05 * H));
    const cx = w / 2, baseY = 34 + (1.08 * H + pmax) * s, py = baseY - piv * s;
    ctx.strokeStyle = "#c9d1dc"; ctx.lineWidth = 6; ctx.lineCap = "round";
    ctx.beginPath(); ctx.moveTo(cx, baseY - pmax * s - 14); ctx.lineTo(cx, baseY + pmax * s + 14); ctx.stroke();
    ctx.setLineDash([4, 4]); ctx.strokeStyle = "#b8c2cf"; ctx.lineWidth = 1;
    ctx.beginPath(); ctx.moveTo(cx, py); ctx.lineTo(cx, py - H * s * 1.05); ctx.stroke(); ctx.setLineDash([]);
    const colors = ["#1f4e9c", "#2a7ab0", "#3d9a8b", "#7a9a3d"];
    let x = cx, y = py;
    m.thetas.forEach((th, j) => {
      const a = lerp(th, k), L = m.lengths[j] * s, x2 = x + Math.sin(a) * L, y2 = y - Math.cos(a) * L;
      ctx.strokeStyle = colors[j % 4]; ctx.lineWidth = m.links === "rod" ? Math.max(7, 0.06 * L) : 3;
      ctx.beginPath(); ctx.moveTo(x, y); ctx.lineTo(x2, y2); ctx.stroke();
      if (m.links === "point") { ctx.fillStyle = colors[j % 4]; ctx.beginPath(); ctx.arc(x2, y2, Math.max(6, 0.08 * L), 0, 2 * Math.PI); ctx.fill(); }
      ctx.fillStyle = "#fff"; ctx.strokeStyle = "#16263d"; ctx.lineWidth = 1.5;
      ctx.beginPath(); ctx.arc(x, y, 3.5, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
      x = x2; y = y2;
    });
    ctx.fillStyle = "#16263d"; ctx.fillRect(cx - 16, py - 6, 32, 12);
    ctx.fillStyle = "#fff"; ctx.beginPath(); ctx.arc(cx, py, 3, 0, 2 * Math.PI); ctx.fill();
    const fs = solo ? 22 : 14, end = m.t[m.n - 1], fell = m.toppled && t >= end - 1e-12;
    ctx.fillStyle = "#16263d"; ctx.font = `600 ${fs}px DejaVu Sans, sans-serif`; ctx.textAlign = "center"; ctx.textBaseline = "top";
    fitText(ctx, `the tower of ${m.n_links} links: full (nonlinear) motion from a tilt of ${fmt(m.theta0, 3)} rad`, cx, 6, w - 20);
    ctx.font = `${solo ? 18 : 12.5}px DejaVu Sans, sans-serif`; ctx.textBaseline = "bottom";
    const angles = m.thetas.map((th) => fmt(lerp(th, k), 3)).join(", ");
    fitText(ctx, fell ? `toppled at t = ${fmt(m.t_topple, 4)} s (a link passed ${fmt(m.tol, 3)} rad)` : `link angles ${angles} rad`, cx, h - 6, w - 20);
    if (kp < 1) {
      ctx.fillStyle = "#6b7685"; ctx.font = `${solo ? 15 : 11}px DejaVu Sans, sans-serif`; ctx.textAlign = "right";
      ctx.fillText(`pivot travel drawn ${fmt(kp, 2)}× to scale`, w - 6, h - 26);
    }
    $("stage").dataset.tower = String(m.n_links); $("stage").dataset.toppled = String(!!m.toppled);
  }

  // Text shrunk to fit a width (titles of narrow panels).
  function fitText(ctx, text, x, y, width) {
    const w = ctx.measureText(text).width;
    if (w <= width) { ctx.fillText(text, x, y); return; }
    ctx.save(); ctx.translate(x, y); ctx.scale(width / w, width / w); ctx.fillText(text, 0, 0); ctx.restore();
  }

  // Plots drawn incrementally: a base (axes and the faint whole run) and the run so far on top.
  function makePlot(id, kind) {
    const p = { canvas: $(id), base: document.createElement("canvas"), prog: document.createElement("canvas"), upto: 0, m: null };
    const pad = { l: 44, r: 8, t: 8, b: 20 };
    p.frame = () => {
      const r = p.canvas.getBoundingClientRect(), dpr = window.devicePixelRatio || 1;
      return { w: r.width, h: r.height, dpr };
    };
    p.xy = (m, j, which) => {
      if (kind === "series") return [m.t[j], which === "lin" ? m.theta_linear[j] : m.theta[j]];
      if (kind === "phase") return which === "lin" ? [m.theta_linear[j], m.dtheta_linear[j]] : [m.thw[j], m.dtheta[j]];
      return null;
    };
    p.map = (x, y) => {
      const { w, h } = p.size, R = p.range;
      return [pad.l + ((x - R.x0) / (R.x1 - R.x0)) * (w - pad.l - pad.r), h - pad.b - ((y - R.y0) / (R.y1 - R.y0)) * (h - pad.t - pad.b)];
    };
    p.prepare = (m) => {
      p.m = m;
      const { w, h, dpr } = p.frame();
      p.size = { w, h };
      for (const c of [p.base, p.prog]) { c.width = Math.max(1, Math.round(w * dpr)); c.height = Math.max(1, Math.round(h * dpr)); c.getContext("2d").setTransform(dpr, 0, 0, dpr, 0, 0); }
      const ctx = p.base.getContext("2d");
      ctx.clearRect(0, 0, w, h);
      if (!m) return;
      if (kind === "series") p.range = { x0: 0, x1: m.t[m.n - 1], y0: -m.thMax, y1: m.thMax };
      else { const a = Math.min(Math.PI, m.thMax), b = m.omMax; p.range = { x0: -a, x1: a, y0: -b, y1: b }; }
      // axes
      ctx.strokeStyle = "#d7dde5"; ctx.lineWidth = 1;
      const [zx, zy] = p.map(kind === "series" ? 0 : 0, 0);
      ctx.beginPath(); ctx.moveTo(pad.l, zy); ctx.lineTo(w - pad.r, zy); ctx.stroke();
      if (kind !== "series") { ctx.beginPath(); ctx.moveTo(zx, pad.t); ctx.lineTo(zx, h - pad.b); ctx.stroke(); }
      ctx.strokeStyle = "#34404f"; ctx.strokeRect(pad.l, pad.t, w - pad.l - pad.r, h - pad.t - pad.b);
      ctx.fillStyle = "#34404f"; ctx.font = "10.5px DejaVu Sans, sans-serif"; ctx.textAlign = "right"; ctx.textBaseline = "middle";
      const R = p.range;
      ctx.fillText(short(R.y1), pad.l - 3, pad.t + 4); ctx.fillText(short(R.y0), pad.l - 3, h - pad.b - 4);
      ctx.textAlign = "center"; ctx.textBaseline = "top";
      ctx.fillText(kind === "series" ? "0" : short(R.x0), pad.l + 8, h - pad.b + 3);
      ctx.fillText(kind === "series" ? `${short(R.x1)} s` : short(R.x1), w - pad.r - 14, h - pad.b + 3);
      ctx.fillText(kind === "series" ? "t" : "θ (mod 2π)", (pad.l + w - pad.r) / 2, h - pad.b + 3);
      ctx.save(); ctx.translate(10, (pad.t + h - pad.b) / 2); ctx.rotate(-Math.PI / 2); ctx.textBaseline = "middle";
      ctx.fillText(kind === "series" ? "θ [rad]" : "θ′ [rad/s]", 0, 0); ctx.restore();
      // the whole run, faint
      ctx.save(); ctx.beginPath(); ctx.rect(pad.l, pad.t, w - pad.l - pad.r, h - pad.t - pad.b); ctx.clip();
      if (kind !== "strobe") {
        for (const which of m.theta_linear ? ["lin", "nl"] : ["nl"]) {
          ctx.strokeStyle = which === "lin" ? "rgba(138,148,163,0.25)" : "rgba(31,78,156,0.18)"; ctx.lineWidth = 1;
          p.path(ctx, m, 0, m.n - 1, which); ctx.stroke();
        }
      }
      ctx.restore();
      p.reset();
    };
    p.path = (ctx, m, a, b, which) => {
      ctx.beginPath();
      let prev = null;
      for (let j = a; j <= b; j++) {
        const [x, y] = p.xy(m, j, which);
        const [X, Y] = p.map(x, y), Yc = Math.max(-1e4, Math.min(1e4, Y));
        if (prev !== null && (kind !== "phase" || Math.abs(x - prev) < Math.PI)) ctx.lineTo(X, Yc); else ctx.moveTo(X, Yc);
        prev = x;
      }
    };
    p.reset = () => { p.upto = 0; const { w, h } = p.size || p.frame(); p.prog.getContext("2d").clearRect(0, 0, w, h); };
    p.advance = (t) => {
      const m = p.m;
      if (!m) return;
      const ctx = p.prog.getContext("2d"), { w, h } = p.size;
      ctx.save(); ctx.beginPath(); ctx.rect(pad.l, pad.t, w - pad.l - pad.r, h - pad.t - pad.b); ctx.clip();
      if (kind === "strobe") {
        const st = m.strobe;
        while (p.upto < st.t.length && st.t[p.upto] <= t) {
          const k = p.upto++;
          if (st.theta_linear) { const [X, Y] = p.map(wrap(st.theta_linear[k]), st.dtheta_linear[k]); ctx.strokeStyle = COLORS.linear; ctx.lineWidth = 1.2; ctx.beginPath(); ctx.arc(X, Y, 3.2, 0, 2 * Math.PI); ctx.stroke(); }
          const [X, Y] = p.map(wrap(st.theta[k]), st.dtheta[k]); ctx.fillStyle = COLORS.nonlinear; ctx.beginPath(); ctx.arc(X, Y, 3, 0, 2 * Math.PI); ctx.fill();
        }
      } else {
        const j = Math.min(m.n - 1, Math.floor(t / (m.t[1] - m.t[0])));
        if (j > p.upto) {
          for (const which of m.theta_linear ? ["lin", "nl"] : ["nl"]) {
            ctx.strokeStyle = which === "lin" ? COLORS.linear : COLORS.nonlinear; ctx.lineWidth = which === "lin" ? 1.4 : 1.8;
            p.path(ctx, m, Math.max(0, p.upto - 1), j, which); ctx.stroke();
          }
          p.upto = j;
        }
      }
      ctx.restore();
    };
    p.draw = (t) => {
      const { ctx, w, h } = fit(p.canvas);
      ctx.clearRect(0, 0, w, h);
      if (!p.m) return;
      ctx.drawImage(p.base, 0, 0, w, h);
      ctx.drawImage(p.prog, 0, 0, w, h);
      const m = p.m, k = index(m, t);
      if (kind === "series") { const [X] = p.map(t, 0); ctx.strokeStyle = COLORS.point; ctx.lineWidth = 2; ctx.beginPath(); ctx.moveTo(X, pad.t); ctx.lineTo(X, h - pad.b); ctx.stroke(); }
      if (kind === "phase") { const [X, Y] = p.map(wrap(lerp(m.theta, k)), lerp(m.dtheta, k)); ctx.fillStyle = COLORS.point; ctx.strokeStyle = "#000"; ctx.beginPath(); ctx.arc(X, Y, 5, 0, 2 * Math.PI); ctx.fill(); ctx.stroke(); }
      if (kind === "series") {
        ctx.font = "10.5px DejaVu Sans, sans-serif"; ctx.textAlign = "left"; ctx.textBaseline = "top";
        ctx.textAlign = "right";
        ctx.fillStyle = COLORS.nonlinear; ctx.fillText("— nonlinear", w - pad.r - 4, pad.t + 3);
        if (m.theta_linear) { ctx.fillStyle = COLORS.linear; ctx.fillText("— linear", w - pad.r - 4, pad.t + 16); }
      }
    };
    return p;
  }
  const plots = [makePlot("series", "series"), makePlot("phase", "phase"), makePlot("strobe", "strobe")];

  function frame(now) {
    if (stopped) return;
    let t = anim.simTime();
    const m = anim.m;
    if (m) {
      const end = m.t[m.n - 1];
      if (t > end + 1.5 * S.speed) { anim.seek(0); t = 0; }  // loop after a short pause at the end
      t = Math.min(t, end);
      for (const p of plots) { if (t < anim.last) p.reset(); p.advance(t); p.draw(t); }
      anim.last = t;
    }
    drawStage(Math.max(0, t));
    anim.frames++; anim.fpsN++;
    if (now - anim.fpsT >= 1000) { anim.fps = (anim.fpsN * 1000) / (now - anim.fpsT); anim.fpsN = 0; anim.fpsT = now; }
    const P = m ? 2 * m.T : 1;
    $("clock").textContent = m ? `t = ${t.toFixed(3)} s · period ${Math.floor(t / P)} of ${Math.round(m.t[m.n - 1] / P)} · ${S.speed === 1 ? "real time" : "slowed " + Math.round(1 / S.speed) + "×"} · ${anim.fps.toFixed(0)} fps` : "";
    $("clock").dataset.t = String(t); $("clock").dataset.frames = String(anim.frames); $("clock").dataset.fps = anim.fps.toFixed(1);
    requestAnimationFrame(frame);
  }

  // ------------------------------------------------------------------ exports
  function updateExports() {
    if (host.getJSON) return;  // no HTTP API to export from (the notebook hides the links)
    if (isTower()) {  // the files are the single pendulum's: 'kapitza tower' writes the tower's
      for (const id of ["chart-png", "chart-svg", "chart-csv", "motion-png", "motion-svg", "motion-csv", "motion-json", "report-json"]) {
        const a = $(`x-${id}`); a.removeAttribute("href"); a.style.opacity = 0.45; a.title = "the tower's files: kapitza tower --out";
      }
      return;
    }
    const c = qs({ ...chartParams(driveText()), ...(S.point ? { T: S.point.T, A: S.point.A } : {}) });
    for (const f of ["png", "svg", "csv"]) { const a = $(`x-chart-${f}`); a.href = `/api/export/chart.${f}?${c}`; a.download = `kapitza-chart.${f}`; }
    const ok = !!S.point;
    for (const f of ["png", "svg", "csv", "json"]) {
      const a = $(`x-motion-${f}`);
      if (ok) { a.href = `/api/export/motion.${f}?${qs(motionParams())}`; a.download = `kapitza-motion.${f}`; a.style.opacity = 1; }
      else { a.removeAttribute("href"); a.style.opacity = 0.45; }
    }
    const r = $("x-report-json");
    if (ok) { r.href = "/api/point?" + qs({ T: S.point.T, A: S.point.A, l: S.l, g: S.g, drive: driveText(), zeta: S.zeta }); r.download = "kapitza-report.json"; r.style.opacity = 1; }
    else { r.removeAttribute("href"); r.style.opacity = 0.45; }
  }

  // ------------------------------------------------------------------ set from outside (the notebook)
  // The state a host sees and sets: the rig, the plane, the start tilt.
  function tell() {
    if (host.onState) host.onState({ l: S.l, g: S.g, drive: driveText(), zeta: S.zeta, plane: S.plane, theta0: S.theta0 });
  }
  // A drive's text form ("square", "rectangular:0.3", or any other kapitza.parse_drive reads): a listed
  // drive (with its number) is chosen in the list, another text is added to it as it is.
  function setDrive(text) {
    const [name, ...rest] = text.split(":"), d = listed(name.trim().toLowerCase()), v = parseFloat(rest[0]);
    if (d && d.parameters.length === 1 && rest.length === 1 && isFinite(v)) { S.drive = d.name; S.params[d.name] = v; return; }
    if (d && !d.parameters.length && !rest.length) { S.drive = d.name; return; }
    S.drive = text;
    if (![...$("drive").options].some((o) => o.value === text)) $("drive").add(new Option(text, text));
  }
  // A first state, before anything is drawn.
  async function applyState(o) {
    if (o.l > 0) S.l = o.l;
    if (o.g > 0) S.g = o.g;
    if (o.drive) setDrive(o.drive);
    if (o.zeta >= 0) S.zeta = o.zeta;
    if (["arnold", "physical", "rig"].includes(o.plane)) S.plane = o.plane;
    if (isFinite(o.theta0)) S.theta0 = o.theta0;
    await ensureInfo();
    S.views = DEFAULT_VIEWS(S.l, S.g, muTop(driveText()));
    if (o.point && o.point.T > 0 && o.point.A > 0) S.point = { T: o.point.T, A: o.point.A };
  }
  // A change of state while the explorer runs: as if the inputs had been changed by hand.
  function set(o) {
    if (["l", "g", "drive", "zeta"].some((k) => k in o && o[k] !== (k === "drive" ? driveText() : S[k]))) {
      if (o.l > 0) $("l").value = o.l;
      if (o.g > 0) $("g").value = o.g;
      if (o.drive) { setDrive(o.drive); $("drive").value = S.drive; syncParam(); }
      if (o.zeta >= 0) $("zeta").value = o.zeta;
      onRig();
    }
    if (["arnold", "physical", "rig"].includes(o.plane) && o.plane !== S.plane) setPlane(o.plane);
    if (isFinite(o.theta0) && o.theta0 !== S.theta0) {
      S.theta0 = o.theta0; $("theta0").value = S.theta0; $("theta0-s").value = S.theta0; renderVerdict(); fetchMotion();
    }
    const P = o.point, same = (a, b) => Math.abs(a - b) <= 1e-12 * Math.abs(b);
    if (P && P.T > 0 && P.A > 0 && !(S.point && same(P.T, S.point.T) && same(P.A, S.point.A))) choosePoint(P);
  }

  // ------------------------------------------------------------------ start
  // The drives first (the lists, and the numbers of the drive in the link or the host's state).
  async function start() {
    await loadDrives();
    if (stopped) return;
    if (useURL) await loadURL();
    if (host.state) await applyState(host.state);
    await ensureInfo();
    if (stopped) return;
    if (!S.point) S.point = { ...DEMO };  // a first view that shows something: the pendulum standing (zone 0)
    if (S.plane === "rig" && !(useURL && new URLSearchParams(location.search).has("x0"))) S.views.rig = rigView(S.l, S.g, S.point);
    clampView();
    setInputs();
    updateExports();
    drawChart();
    fetchChart();
    if (S.point) choosePoint(S.point);
  }
  const ready = start();
  const onResize = () => { drawChart(); anim.prepare(); };
  window.addEventListener("resize", onResize);
  // An embedded explorer changes width with its container (a notebook cell), not with the window
  // (its height follows its own text: no redraw for that).
  let width = null;
  const sized = host.box && typeof ResizeObserver !== "undefined" ? new ResizeObserver((seen) => {
    const w = seen[seen.length - 1].contentRect.width;
    if (w !== width) { width = w; onResize(); }
  }) : null;
  if (sized) sized.observe(host.box);
  requestAnimationFrame(frame);
  function destroy() {
    stopped = true;
    window.removeEventListener("resize", onResize);
    document.removeEventListener("keydown", onKey);
    if (sized) sized.disconnect();
    for (const c of [chartAbort, pointAbort, motionAbort]) if (c) c.abort();
  }
  // For tests, the console and the notebook: the state, where a point of the chart is on screen,
  // and the state set from outside.
  return { S, anim, chart, inset, panel: PANEL, drives: () => DRIVES, info, ready, set, destroy, pixel(x, y) { const r = chart.canvas.getBoundingClientRect(), ax = axes(r.width, r.height);
    return { x: r.left + ax.X(x), y: r.top + ax.Y(y) }; } };
}
