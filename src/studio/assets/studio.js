// crease studio: the page. It draws what the server publishes and sends what the user
// does; every piece of geometry is computed by the server (see src/studio/).
//
//   window.crease.state()      -> Promise of GET /api/state
//   window.crease.screenOf(v)  -> {x, y}: client coordinates of vertex v in the 3D view
//   window.crease.ready        -> true once the first frame is drawn
//   window.crease.framesShown() -> frames drawn with new positions so far (benchmarks)
//   window.crease.motion()     -> the folding motion shown: frames, shown, played, …

import { View3D } from '/view3d.js';
import { PatternPane, XrayPane } from '/panes.js';
import { Panel } from '/panel.js';
import { FitPanel } from '/fit.js';
import { MotionPanel } from '/motion.js';

/** JSON request; a 4xx/5xx rejects with the server's one-line message. */
export async function api(path, body, raw) {
  const init = body === undefined ? {} : {
    method: 'POST',
    headers: { 'Content-Type': raw ? 'application/octet-stream' : 'application/json' },
    body: raw ? body : JSON.stringify(body),
  };
  const r = await fetch('/api' + path, init);
  const text = await r.text();
  let value;
  try { value = JSON.parse(text); } catch { value = { error: text }; }
  if (!r.ok) throw new Error(value.error || `${r.status} ${r.statusText}`);
  return value;
}

const model = {
  instance: null, version: 0, topologyVersion: null, patternVersion: null,
  topology: null, pattern: null, live: null,
};

const panel = new Panel(api, showStatus);
const view = new View3D(document.getElementById('view3d'), {
  onDragStart: (v) => drags.start(v),
  onDragMove: (v, p) => drags.move(v, p),
  onDragEnd: () => drags.end(),
  onPin: (v) => {
    const pinned = !(model.live && model.live.pinned.includes(v));
    api('/pin', { vertex: v, pinned }).catch((e) => showStatus(e.message, true));
  },
});
const fitPanel = new FitPanel(api, showStatus, view);
const motionPanel = new MotionPanel(api, showStatus, view);
const cpPane = new PatternPane(document.getElementById('cp'));
const xrayPane = new XrayPane(document.getElementById('xray'), document.getElementById('xray-reason'));

/** Drag messages go one at a time, newest target first: the server merges them anyway. */
const drags = {
  inFlight: null, pending: null, vertex: null,
  start(v) { this.vertex = v; },
  move(v, p) {
    this.pending = { vertex: v, target: p };
    if (!this.inFlight) this.flush();
  },
  flush() {
    const next = this.pending;
    this.pending = null;
    if (!next) { this.inFlight = null; return; }
    this.inFlight = api('/drag', next)
      .catch((e) => showStatus(e.message, true))
      .then(() => this.flush());
  },
  async end() {
    while (this.inFlight) await this.inFlight;
    this.vertex = null;
    await api('/release', {}).catch((e) => showStatus(e.message, true));
  },
};

let statusOverride = null;
function showStatus(text, bad) {
  statusOverride = { text, bad, until: performance.now() + 4000 };
  paintStatus();
}

function paintStatus() {
  const el = document.getElementById('status');
  const live = model.live;
  if (statusOverride && performance.now() < statusOverride.until) {
    el.textContent = statusOverride.text;
    el.classList.toggle('blocked', !!statusOverride.bad);
    return;
  }
  statusOverride = null;
  if (!live) return;
  el.textContent = live.blocked || live.message;
  el.classList.toggle('blocked', !!live.blocked);
}

let framesApplied = 0;
function apply(frame) {
  framesApplied++;
  // Another session (the studio restarted on this port) sends everything afresh.
  model.instance = frame.instance;
  model.version = frame.version;
  if (frame.topology) {
    model.topology = frame.topology;
    model.topologyVersion = frame.topologyVersion;
  }
  if (frame.pattern) {
    model.pattern = frame.pattern;
    model.patternVersion = frame.patternVersion;
  }
  model.live = frame.live;
  view.update(model, !!frame.topology);
  if (frame.topology || frame.pattern) {
    cpPane.draw(model);
    xrayPane.draw(model);
  }
  panel.update(model);
  fitPanel.update(model);
  paintStatus();
}

async function poll() {
  for (;;) {
    const q = `after=${model.version}` +
      (model.instance !== null ? `&instance=${model.instance}` : '') +
      (model.topologyVersion !== null ? `&topology=${model.topologyVersion}` : '') +
      (model.patternVersion !== null ? `&pattern=${model.patternVersion}` : '');
    try {
      const frame = await api('/frame?' + q);
      apply(frame);
      window.crease.ready = true;
    } catch (e) {
      showStatus('lost the studio server (' + e.message + '); retrying…', true);
      await new Promise((r) => setTimeout(r, 1000));
    }
  }
}

window.crease = {
  ready: false,
  state: () => api('/state'),
  screenOf: (v) => view.screenOf(v),
  markerScreen: () => view.markerScreen(),
  framesShown: () => view.framesShown,
  framesApplied: () => framesApplied,
  motion: () => motionPanel.state(),
};

window.addEventListener('resize', () => { cpPane.draw(model); xrayPane.draw(model); });
window.addEventListener('keydown', (e) => {
  if (e.target.tagName === 'INPUT' || !(e.ctrlKey || e.metaKey) || e.key.toLowerCase() !== 'z') return;
  e.preventDefault();
  api(e.shiftKey ? '/redo' : '/undo', {}).catch((err) => showStatus(err.message, true));
});
setInterval(paintStatus, 1000);

fitPanel.init();
motionPanel.init();
panel.init().then(poll);
