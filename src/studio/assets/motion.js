// The folding motion: Play asks the server to fold the design from the flat sheet (the
// path `verify --path` checks, src/pipeline/motion.rs) and plays its frames in the 3D
// view; the slider shows any frame; Export downloads the motion as glTF, FOLD frames or an
// animated PNG. Every frame is the server's; this only shows them.

const $ = (id) => document.getElementById(id);
// 15 frames a second and the design held at the end, as motion.png and the glTF play.
const FRAME_MS = 67;
const HOLD_MS = 1200;

export class MotionPanel {
  constructor(api, showStatus, view) {
    this.api = api;
    this.say = showStatus;
    this.view = view;
    this.motion = null;
    this.timer = null;
    this.shown = -1;
    this.played = 0;
  }

  init() {
    $('motion-play').addEventListener('click', () => this.play());
    $('motion-frame').addEventListener('input', () => {
      this.stop();
      if (this.motion) this.show(Number($('motion-frame').value));
    });
    $('motion-format').addEventListener('change', () => {
      $('motion-export').href = `/api/motion/export?format=${$('motion-format').value}`;
    });
    // A press on the view after playing goes back to the design, which is what a drag
    // moves; while it plays, the view orbits as ever.
    this.view.renderer.domElement.addEventListener('pointerdown', () => {
      if (!this.timer) this.end();
    }, true);
  }

  async play() {
    this.stop();
    const info = $('motion-info');
    info.textContent = 'folding from the flat sheet…';
    $('motion-play').disabled = true;
    try {
      this.motion = await this.api('/motion', {});
    } catch (e) {
      info.textContent = e.message;
      this.say(e.message, true);
      return;
    } finally {
      $('motion-play').disabled = false;
    }
    const m = this.motion;
    info.textContent = m.summary;
    info.classList.toggle('blocked', m.exitCode !== 0);
    const slider = $('motion-frame');
    slider.max = m.frames.length - 1;
    slider.disabled = false;
    this.view.frameMotion(m);
    let k = 0;
    const next = () => {
      this.show(k);
      if (++k < m.frames.length) {
        this.timer = setTimeout(next, FRAME_MS);
      } else {
        this.timer = setTimeout(() => { this.played++; this.end(); }, HOLD_MS);
      }
    };
    next();
  }

  show(k) {
    const m = this.motion;
    this.view.showMotion(m, k);
    this.shown = k;
    $('motion-frame').value = k;
    $('motion-at').textContent = `${k} / ${m.frames.length - 1}`;
  }

  stop() {
    clearTimeout(this.timer);
    this.timer = null;
  }

  /** Back to the design in the view. */
  end() {
    this.stop();
    this.view.endMotion();
  }

  /** What the page shows of the motion (for tests). */
  state() {
    const m = this.motion;
    return {
      frames: m ? m.frames.length : 0, shown: this.shown, played: this.played,
      showing: this.view.motionShown(), exitCode: m ? m.exitCode : null,
      framesDrawn: this.view.motionFramesDrawn,
    };
  }
}
