// The two flat views: the crease pattern as it changes, and the x-ray of the pattern
// folded flat (every ±180° crease folded; overlapping layers darken).

const CSS = { M: '#d62728', V: '#1f5fd6', F: '#c8c8c8', B: '#111111' };

/** Fits points (flat [x0, y0, x1, y1, …]) into the canvas, y up, and returns the mapping. */
function fit(canvas, coords) {
  const dpr = window.devicePixelRatio || 1;
  const w = canvas.clientWidth, h = canvas.clientHeight;
  canvas.width = Math.max(1, Math.round(w * dpr));
  canvas.height = Math.max(1, Math.round(h * dpr));
  const ctx = canvas.getContext('2d');
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  ctx.clearRect(0, 0, w, h);
  let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
  for (let i = 0; i < coords.length; i += 2) {
    x0 = Math.min(x0, coords[i]); x1 = Math.max(x1, coords[i]);
    y0 = Math.min(y0, coords[i + 1]); y1 = Math.max(y1, coords[i + 1]);
  }
  const pad = 22;
  const s = Math.min((w - 2 * pad) / Math.max(x1 - x0, 1e-9), (h - 2 * pad) / Math.max(y1 - y0, 1e-9));
  const ox = (w - s * (x1 - x0)) / 2, oy = (h - s * (y1 - y0)) / 2;
  return { ctx, at: (x, y) => [ox + s * (x - x0), h - oy - s * (y - y0)] };
}

export class PatternPane {
  constructor(canvas) { this.canvas = canvas; }

  draw(model) {
    const cp = model.pattern && model.pattern.creasePattern;
    if (!cp || !model.topology) return;
    const { ctx, at } = fit(this.canvas, cp);
    // A curved crease is drawn as its smooth curve (the one the cutter scores), not as
    // the chords the mesh holds.
    const curves = model.pattern.curves || [];
    const onCurve = new Set(curves.flatMap((c) => c.edges));
    // Flat lines first, so mountains and valleys stay on top.
    const order = { F: 0, B: 1, V: 2, M: 2 };
    // A tube's pattern is its strip, with creases of its own (the seam's vertices twice).
    const edges = (model.pattern.edges || model.topology.edges)
      .filter((_, i) => !onCurve.has(i))
      .sort((a, b) => order[a[2]] - order[b[2]]);
    ctx.lineWidth = 1.2;
    for (const [a, b, kind] of edges) {
      ctx.strokeStyle = CSS[kind] || CSS.F;
      ctx.beginPath();
      ctx.moveTo(...at(cp[2 * a], cp[2 * a + 1]));
      ctx.lineTo(...at(cp[2 * b], cp[2 * b + 1]));
      ctx.stroke();
    }
    for (const c of curves) {
      ctx.strokeStyle = CSS[c.kind] || CSS.F;
      ctx.beginPath();
      ctx.moveTo(...at(c.start[0], c.start[1]));
      const p = c.pieces;
      for (let i = 0; i + 5 < p.length; i += 6) {
        ctx.bezierCurveTo(...at(p[i], p[i + 1]), ...at(p[i + 2], p[i + 3]), ...at(p[i + 4], p[i + 5]));
      }
      ctx.stroke();
    }
  }
}

export class XrayPane {
  constructor(canvas, reasonEl) { this.canvas = canvas; this.reason = reasonEl; }

  draw(model) {
    const xray = model.pattern && model.pattern.xray;
    if (!xray) return;
    if (xray.reason) {
      this.canvas.getContext('2d').clearRect(0, 0, this.canvas.width, this.canvas.height);
      this.reason.textContent = 'No flat-folded state: ' + xray.reason + '.';
      return;
    }
    // Closed layers come as one image per vertex; otherwise as each face's corners.
    let t = xray.triangles;
    if (!t) {
      const faces = model.pattern.faces || model.topology.faces, p = xray.points;
      t = new Float64Array(faces.length * 2);
      faces.forEach((v, i) => { t[2 * i] = p[2 * v]; t[2 * i + 1] = p[2 * v + 1]; });
    }
    const { ctx, at } = fit(this.canvas, t);
    ctx.lineWidth = 0.6;
    for (let f = 0; f < t.length / 6; f++) {
      ctx.beginPath();
      ctx.moveTo(...at(t[6 * f], t[6 * f + 1]));
      ctx.lineTo(...at(t[6 * f + 2], t[6 * f + 3]));
      ctx.lineTo(...at(t[6 * f + 4], t[6 * f + 5]));
      ctx.closePath();
      ctx.fillStyle = xray.flipped[f] ? 'rgba(31, 95, 214, 0.10)' : 'rgba(214, 120, 39, 0.10)';
      ctx.fill();
      ctx.strokeStyle = 'rgba(40, 40, 40, 0.25)';
      ctx.stroke();
    }
    this.reason.textContent = xray.closes === false
      ? `The layers do not close: images of vertex ${xray.worstVertex} disagree by ${xray.mismatch.toFixed(3)} mm (the pattern is not flat-foldable there).`
      : '';
  }
}
