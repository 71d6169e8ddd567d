// The notebook explorer (kapitza.widgets.Explorer): the page's explorer (explorer.js, above in
// this module, with the page's MARKUP and STYLE) in a shadow root of the cell, asking the kernel
// instead of a server, and linked to the widget's traits: point, drive, zeta, l, g, plane, theta0.

// Page-only parts hidden: the link to share (an address bar) and the exports (files of the server).
// The page's layout follows the window; a cell's follows the cell: one column in a narrow one.
const CELL_STYLE = `
.kapitza-explorer { background: var(--bg); border-radius: 8px; overflow: hidden; container-type: inline-size; }
#share, .exports { display: none !important; }
header { flex-wrap: wrap; }
@container (max-width: 1100px) {
  main { grid-template-columns: minmax(0, 1fr); }
  #chart-wrap { height: 460px; }
  #stage-wrap { height: 280px; }
}
`;
const TRAITS = ["l", "g", "drive", "zeta", "plane", "theta0"];

function render({ model, el }) {
  const shadow = el.shadowRoot || el.attachShadow({ mode: "open" });
  shadow.innerHTML = `<style>${STYLE}${CELL_STYLE}</style><div class="kapitza-explorer">${MARKUP}</div>`;
  const box = shadow.querySelector(".kapitza-explorer");

  // Requests to the kernel: {kind: "ask", id, url} answered by {id, ok, json | detail}; an aborted
  // request is dropped there ({kind: "drop", id}). Ids carry this view's own prefix: every view of
  // the widget hears every answer.
  const view = Math.random().toString(36).slice(2), waiting = new Map();
  let count = 0;
  const onMessage = (msg) => {
    const w = msg && waiting.get(msg.id);
    if (!w) return;
    waiting.delete(msg.id);
    if (msg.ok) w.resolve(JSON.parse(msg.json)); else w.reject(new Error(msg.detail));
  };
  model.on("msg:custom", onMessage);
  const getJSON = (url, signal) => new Promise((resolve, reject) => {
    const id = `${view}:${++count}`;
    waiting.set(id, { resolve, reject });
    model.send({ kind: "ask", id, url });
    if (signal) signal.addEventListener("abort", () => {
      if (waiting.delete(id)) { model.send({ kind: "drop", id }); reject(new DOMException("aborted", "AbortError")); }
    });
  });

  // Changes made here are told to Python; changes made in Python are set here. `quiet` keeps a
  // change that came from Python from being sent back.
  let quiet = false;
  const state = () => {
    const o = { point: model.get("point") };
    for (const k of TRAITS) o[k] = model.get(k);
    return o;
  };
  quiet = true;  // the first point is Python's own (chosen once the drives have come)
  const ctl = mount(shadow, {
    getJSON, url: false, box, state: state(), tower: true,
    onPoint(p) { if (quiet) return; model.set("point", p); model.save_changes(); },
    onState(s) {
      if (quiet) return;
      let changed = false;
      for (const k of TRAITS) if (s[k] !== model.get(k)) { model.set(k, s[k]); changed = true; }
      if (changed) model.save_changes();
    },
  });
  ctl.ready.finally(() => { quiet = false; });
  const fromPython = () => { quiet = true; try { ctl.set(state()); } finally { quiet = false; } };
  const events = ["change:point", ...TRAITS.map((k) => `change:${k}`)];
  for (const e of events) model.on(e, fromPython);
  shadow.getElementById("report-box").open = false;  // a compact cell: the report on a click (or w.report())
  el.kapitza = ctl;  // for tests and the browser's console
  return () => {
    for (const e of events) model.off(e, fromPython);
    model.off("msg:custom", onMessage);
    ctl.destroy();
  };
}

export default { render };
