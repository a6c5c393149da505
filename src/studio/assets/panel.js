// The control panel: patterns, files, undo, solver settings, live numbers, fabrication.
// Each control sends one request; what it shows comes back in the next frame.

const $ = (id) => document.getElementById(id);

export class Panel {
  constructor(api, showStatus) {
    this.api = api;
    this.say = showStatus;
    this.meta = null;
    // Whether the user picked from the pattern list (then the page leaves it alone), and
    // the title the list was last named from.
    this.patternChosen = false;
    this.namedFor = null;
  }

  /** Sends a request; a refusal shows in the status line. */
  send(path, body, raw) {
    return this.api(path, body, raw).catch((e) => { this.say(e.message, true); throw e; });
  }

  async init() {
    this.meta = await this.api('/meta');
    const pattern = $('pattern');
    for (const p of this.meta.patterns) pattern.add(new Option(p.name, p.name));
    pattern.addEventListener('change', () => { this.patternChosen = true; this.fillPattern(); });
    this.fillPattern();
    $('generate').addEventListener('click', () => {
      const num = (id) => ($(id).value === '' ? null : Number($(id).value));
      this.send('/generate', {
        pattern: pattern.value, nx: num('nx'), ny: num('ny'), size: num('size'),
        angle: num('angle'), fold: num('gen-fold'),
      }).catch(() => {});
    });
    $('open').addEventListener('change', (e) => { if (e.target.files[0]) this.open(e.target.files[0]); e.target.value = ''; });
    document.addEventListener('dragover', (e) => { e.preventDefault(); document.body.classList.add('dropping'); });
    document.addEventListener('dragleave', () => document.body.classList.remove('dropping'));
    document.addEventListener('drop', (e) => {
      e.preventDefault();
      document.body.classList.remove('dropping');
      if (e.dataTransfer.files[0]) this.open(e.dataTransfer.files[0]);
    });
    $('undo').addEventListener('click', () => this.send('/undo', {}).catch(() => {}));
    $('redo').addEventListener('click', () => this.send('/redo', {}).catch(() => {}));
    for (const r of document.querySelectorAll('input[name=mode]')) {
      r.addEventListener('change', () => this.send('/settings', { mode: r.value }).catch(() => {}));
    }
    const box = $('conditions');
    for (const name of this.meta.families) {
      const label = document.createElement('label');
      label.innerHTML = `<input type="checkbox" value="${name}"> ${name}`;
      label.firstChild.addEventListener('change', () => {
        const chosen = [...box.querySelectorAll('input:checked')].map((c) => c.value);
        this.send('/settings', { conditions: chosen }).catch(() => {});
      });
      box.appendChild(label);
    }
    $('default-conditions').addEventListener('click', () => this.send('/settings', { conditions: [] }).catch(() => {}));
    $('alpha').addEventListener('change', (e) => this.send('/settings', { alpha: Number(e.target.value) }).catch(() => {}));
    const remesh = () => ($('remesh-on').checked
      ? { remesh: Number($('remesh').value) } : { remesh_off: true });
    $('remesh-on').addEventListener('change', () => this.send('/settings', remesh()).catch(() => {}));
    $('remesh').addEventListener('change', () => { if ($('remesh-on').checked) this.send('/settings', remesh()).catch(() => {}); });
    $('fold').addEventListener('input', (e) => { $('fold-value').value = Number(e.target.value).toFixed(2); });
    $('fold-go').addEventListener('click', () => {
      this.say('folding…');
      this.send('/fold', { amount: Number($('fold').value) }).catch(() => {});
    });
    for (const m of this.meta.machines) $('machine').add(new Option(m, m));
    $('fabricate').addEventListener('click', () => this.fabricate());
  }

  fillPattern() {
    const p = this.meta.patterns.find((q) => q.name === $('pattern').value);
    $('nx').value = p.nx; $('ny').value = p.ny; $('size').value = p.size;
    $('angle').value = p.angle; $('gen-fold').value = p.fold ?? '';
    $('gen-fold').disabled = !p.closedForm;
  }

  async open(file) {
    const bytes = await file.arrayBuffer();
    this.send('/open?name=' + encodeURIComponent(file.name), bytes, true)
      .then((r) => { if (r.notes && r.notes.length) this.say('opened with notes: ' + r.notes.join('; ')); })
      .catch(() => {});
  }

  async fabricate() {
    const out = $('fab-result');
    out.textContent = 'fabricating…';
    const num = (id) => ($(id).value === '' ? null : Number($(id).value));
    try {
      const r = await this.send('/fabricate', {
        machine: $('machine').value, media: $('media').value || null, width: num('width'),
        fit: $('fab-fit').checked, margin: num('margin'), tile: $('tile').checked,
        force: $('force').checked,
      });
      const stamp = Date.now();
      const s = r.report.sheet || {};
      out.innerHTML = '';
      const summary = document.createElement('div');
      summary.className = 'small';
      summary.textContent = `${s.strokes ?? '?'} strokes, pen-up travel ${Math.round(s.pen_up_travel_mm ?? 0)} mm`;
      out.appendChild(summary);
      for (const name of r.files.filter((n) => n !== 'preview.svg')) {
        const a = document.createElement('a');
        a.href = `/api/fab/${name}?t=${stamp}`;
        a.download = name;
        a.textContent = name;
        out.appendChild(a);
      }
      if (r.files.includes('preview.svg')) {
        // The toolpath drawn to be seen: cut black, mountain red, valley blue, on the media.
        const img = document.createElement('img');
        img.id = 'fab-preview';
        img.alt = 'the scored sheet on its media';
        img.src = `/api/fab/preview.svg?t=${stamp}`;
        out.appendChild(img);
      }
    } catch (e) {
      out.textContent = e.message;
    }
  }

  /** Shows in the pattern list what the design titled `title` was made from. */
  nameThePattern(title) {
    const [kind, cells] = title.split(' ');
    const made = /^\d+x\d+$/.test(cells || '')
      ? this.meta.patterns.find((p) => p.name === kind) : undefined;
    const list = $('pattern');
    let opened = list.querySelector('option[data-opened]');
    if (made) {
      if (opened) opened.remove();
      if (list.value !== made.name) { list.value = made.name; this.fillPattern(); }
    } else {
      if (!opened) {
        opened = new Option('', '');
        opened.dataset.opened = '1';
        opened.disabled = true;
        list.add(opened, 0);
      }
      opened.textContent = `(open: ${title})`;
      list.value = '';
    }
  }

  update(model) {
    const live = model.live;
    if (!live) return;
    $('title').textContent = live.title;
    // Until the user picks one, the pattern list shows what the design was made from,
    // or, for an opened file, names the file.
    // A generated design is titled "KIND NXxNY"; the kind is matched whole
    // (waterbomb-tube is not waterbomb), and an opened file (miura-bent) matches none.
    // The list is named once per design (when the title changes), not on every frame:
    // a frame must not undo what the list shows between a choice and a click on New.
    if (!this.patternChosen && live.title !== this.namedFor) {
      this.namedFor = live.title;
      this.nameThePattern(live.title);
    }
    $('vertex-count').textContent = live.vertices;
    $('steps').textContent = Math.round(live.stepsPerSecond);
    const verdict = $('verdict');
    verdict.textContent = live.verdict || '…';
    verdict.className = live.verdict === 'PASS' ? 'pass' : live.verdict === 'UNDECIDED' ? 'undecided' : 'fail';
    $('undo').disabled = live.undo === 0;
    $('redo').disabled = live.redo === 0;
    for (const r of document.querySelectorAll('input[name=mode]')) r.checked = r.value === live.mode;
    for (const c of $('conditions').querySelectorAll('input')) {
      c.checked = live.conditions.includes(c.value);
      c.disabled = live.mode === 'simulation';
    }
    if (document.activeElement !== $('alpha')) $('alpha').value = live.alpha;
    $('remesh-on').checked = live.remesh !== null;
    if (live.remesh !== null && document.activeElement !== $('remesh')) $('remesh').value = live.remesh;
    $('fold-row').style.display = live.mode === 'simulation' ? '' : 'none';
    // The table and its note are rebuilt only when what they show changed.
    const shown = JSON.stringify([live.residuals, live.worst]);
    if (shown === this.residualsShown) return;
    this.residualsShown = shown;
    const body = $('residuals').tBodies[0];
    body.innerHTML = '';
    for (const f of live.residuals) {
      const tr = body.insertRow();
      tr.className = !f.judged ? 'info' : f.pass ? '' : 'fail';
      tr.insertCell().textContent = f.name;
      const max = tr.insertCell();
      max.className = 'num';
      max.textContent = f.max === null ? '–' : f.max.toExponential(1);
      tr.insertCell().textContent = !f.judged ? 'reported' : f.pass ? '✓' : '✗ ' + (f.worst || '');
    }
    $('worst').textContent = live.worst && !live.worst.pass
      ? `worst: ${live.worst.family} at ${describeElement(live.worst.element)} (marked magenta)`
      : '';
  }
}

/** A report element in words: a vertex, an edge, or two faces that cross. */
function describeElement(el) {
  if (el.vertex !== undefined) return `vertex ${el.vertex}`;
  if (el.faces !== undefined) return `faces ${el.faces[0]} and ${el.faces[1]}`;
  return `edge ${el.edge}`;
}
