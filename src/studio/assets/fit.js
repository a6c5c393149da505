// The fit panel: load a target surface, place it (shift, turn, offset from where its file
// put it), press Fit and watch the distance fall; Stop ends it, undo returns to before it.
// The server does the fitting (src/fit/); this only sends requests and shows progress.

const $ = (id) => document.getElementById(id);

export class FitPanel {
  constructor(api, showStatus, view) {
    this.api = api;
    this.say = showStatus;
    this.view = view;
    this.targetVersion = null;
  }

  send(path, body, raw) {
    return this.api(path, body, raw).catch((e) => { this.say(e.message, true); throw e; });
  }

  init() {
    $('target-file').addEventListener('change', (e) => {
      if (e.target.files[0]) this.load(e.target.files[0]);
      e.target.value = '';
    });
    const section = $('fit-section');
    // A file dropped on this section is a target, not a pattern to open.
    section.addEventListener('dragover', (e) => { e.preventDefault(); e.stopPropagation(); });
    section.addEventListener('drop', (e) => {
      e.preventDefault();
      e.stopPropagation();
      document.body.classList.remove('dropping');
      if (e.dataTransfer.files[0]) this.load(e.dataTransfer.files[0]);
    });
    for (const id of ['shift-x', 'shift-y', 'shift-z', 'turn-x', 'turn-y', 'turn-z', 'target-offset']) {
      $(id).addEventListener('change', () => this.place());
    }
    $('fit-go').addEventListener('click', () => {
      const within = $('fit-within').value === '' ? null : Number($('fit-within').value);
      this.send('/fit', within === null ? {} : { within }).catch(() => {});
    });
    $('fit-stop').addEventListener('click', () => this.send('/fit/stop', {}).catch(() => {}));
    $('target-clear').addEventListener('click', () => this.send('/target/clear', {}).catch(() => {}));
  }

  async load(file) {
    const bytes = await file.arrayBuffer();
    await this.send('/target?name=' + encodeURIComponent(file.name), bytes, true).catch(() => {});
  }

  place() {
    const n = (id) => Number($(id).value) || 0;
    this.send('/target/place', {
      shift: [n('shift-x'), n('shift-y'), n('shift-z')],
      turn: [n('turn-x'), n('turn-y'), n('turn-z')],
      offset: n('target-offset'),
    }).catch(() => {});
  }

  /** Shows the target and the fit's progress from a frame's live part. */
  update(model) {
    const live = model.live;
    if (!live) return;
    const target = live.target, fit = live.fit;
    $('target-name').textContent = target
      ? `${target.name}: ${target.triangles} triangles` : 'no target (.obj or .stl in mm; or drop one here)';
    $('fit-go').disabled = !target || (fit && fit.running);
    $('fit-stop').disabled = !(fit && fit.running);
    $('target-clear').disabled = !target;
    if (!target && this.targetVersion !== null) {
      this.targetVersion = null;
      this.view.setTarget(null);
    } else if (target && target.version !== this.targetVersion) {
      const version = target.version;
      this.targetVersion = version;
      this.api('/target').then((t) => { if (this.targetVersion === version) this.view.setTarget(t); })
        .catch((e) => this.say(e.message, true));
    }
    if (target) {
      // The inputs show the placement in force (another tab, or a refused value, may
      // have changed it) unless the user is typing in one.
      const shown = { 'shift-x': target.shift[0], 'shift-y': target.shift[1], 'shift-z': target.shift[2],
        'turn-x': target.turn[0], 'turn-y': target.turn[1], 'turn-z': target.turn[2], 'target-offset': target.offset };
      for (const [id, value] of Object.entries(shown)) {
        if (document.activeElement !== $(id)) $(id).value = Math.round(value * 1000) / 1000;
      }
    }
    const p = $('fit-progress');
    if (!fit) { p.textContent = ''; return; }
    const state = fit.running ? 'fitting' : `fit ${fit.stopped ?? 'stopped'}`;
    p.textContent = `${state}: step ${fit.steps}, largest distance ${fit.largest.toFixed(3)} mm ` +
      `(goal ${fit.goal.toFixed(3)}), RMS ${fit.rms.toFixed(3)} mm`;
    p.className = 'small ' + (fit.largest <= fit.goal ? 'met' : '');
  }
}
