// The 3D form: shaded faces, creases coloured by kind, pins and the worst element marked.
// Pressing on a vertex drags it in the plane that faces the camera through it; elsewhere
// the mouse orbits (left), pans (right) and zooms (wheel).

import * as THREE from 'three';
import { OrbitControls } from '/vendor/three/OrbitControls.js';

export const KIND_COLOURS = { M: 0xd62728, V: 0x1f5fd6, F: 0xc8c8c8, B: 0x111111 };
const PICK_PX = 14;

export class View3D {
  constructor(host, handlers) {
    this.host = host;
    this.handlers = handlers;
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xfbfaf7);
    this.camera = new THREE.PerspectiveCamera(35, 1, 0.1, 1e6);
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    host.appendChild(this.renderer.domElement);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x8a8070, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.4);
    sun.position.set(1, 2, 3);
    this.scene.add(sun);

    this.faces = new THREE.Mesh(new THREE.BufferGeometry(), new THREE.MeshLambertMaterial({
      color: 0xf1e7d0, side: THREE.DoubleSide, flatShading: true,
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
    }));
    this.creases = new THREE.LineSegments(new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ vertexColors: true }));
    this.pins = this.markers(0xff8c00, 11);
    this.anchor = this.markers(0x9a9a9a, 6);
    this.worst = this.markers(0xe0119d, 14);
    this.hover = this.markers(0x111111, 12);
    this.scene.add(this.faces, this.creases, this.pins, this.anchor, this.worst, this.hover);

    this.positions = new Float32Array(0);
    this.dragging = null;
    this.hovered = null;
    this.renderPending = false;
    this.pickPending = false;
    // Frames drawn with positions newer than the last drawn (the page benchmark's count).
    this.framesShown = 0;
    this.freshPositions = false;
    this.framed = false;
    // The folding motion shown in place of the design, if any, and its frames drawn.
    this.motionOf = null;
    this.motionFramesDrawn = 0;
    // Registered before OrbitControls so a press on a vertex can switch orbiting off
    // before the controls see it.
    const el = this.renderer.domElement;
    el.addEventListener('pointerdown', (e) => this.down(e));
    el.addEventListener('pointermove', (e) => this.moveEvent(e));
    el.addEventListener('pointerup', (e) => this.up(e));
    el.addEventListener('pointercancel', (e) => this.up(e));
    this.controls = new OrbitControls(this.camera, el);
    this.controls.addEventListener('change', () => this.render());
    new ResizeObserver(() => this.resize()).observe(host);
    this.resize();
  }

  /** Draws the fit's target surface translucent over the design (null removes it). */
  setTarget(target) {
    if (this.target) {
      this.scene.remove(this.target);
      this.target.geometry.dispose();
      this.target = null;
    }
    if (target) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(Float32Array.from(target.vertices.flat()), 3));
      g.setIndex(target.triangles.flat());
      g.computeVertexNormals();
      this.target = new THREE.Mesh(g, new THREE.MeshLambertMaterial({
        color: 0x3aa37a, transparent: true, opacity: 0.3, side: THREE.DoubleSide, depthWrite: false,
      }));
      this.target.renderOrder = 1;
      this.scene.add(this.target);
    }
    this.render();
  }

  markers(colour, size) {
    const m = new THREE.Points(new THREE.BufferGeometry(), new THREE.PointsMaterial({
      color: colour, size, sizeAttenuation: false, depthTest: false,
    }));
    m.renderOrder = 2;
    return m;
  }

  resize() {
    const w = this.host.clientWidth, h = this.host.clientHeight;
    if (!w || !h) return;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  /** Draws at the next animation frame, once however many changes ask for it. */
  render() {
    if (this.renderPending) return;
    this.renderPending = true;
    requestAnimationFrame(() => {
      this.renderPending = false;
      this.renderer.render(this.scene, this.camera);
      if (this.freshPositions) { this.framesShown++; this.freshPositions = false; }
    });
  }

  /** `attr` refilled with `values` in place when it has their length, else replaced. */
  static fill(geometry, name, values, itemSize) {
    const attr = geometry.getAttribute(name);
    if (attr && attr.array.length === values.length) {
      attr.array.set(values);
      attr.needsUpdate = true;
    } else {
      geometry.setAttribute(name, new THREE.BufferAttribute(values, itemSize));
    }
  }

  /** Each edge's colour by its kind, twice (both ends), for a LineSegments. */
  static edgeColours(edges) {
    const colours = new Float32Array(edges.length * 6);
    edges.forEach(([, , kind], i) => {
      const c = new THREE.Color(KIND_COLOURS[kind] ?? KIND_COLOURS.F);
      colours.set([c.r, c.g, c.b, c.r, c.g, c.b], i * 6);
    });
    return colours;
  }

  /** Fills `line` with both ends of every edge at positions `pos` (x, y, z each). */
  static edgeEnds(edges, pos, line) {
    edges.forEach(([a, b], i) => {
      line[i * 6] = pos[3 * a]; line[i * 6 + 1] = pos[3 * a + 1]; line[i * 6 + 2] = pos[3 * a + 2];
      line[i * 6 + 3] = pos[3 * b]; line[i * 6 + 4] = pos[3 * b + 1]; line[i * 6 + 5] = pos[3 * b + 2];
    });
  }

  /**
   * Shows frame k of a folding motion in place of the design: the motion's own faces and
   * creases (a tube folds as its strip), drawn as the design is.
   */
  showMotion(motion, k) {
    if (this.motionOf !== motion) {
      this.endMotion();
      const faces = new THREE.BufferGeometry();
      faces.setIndex(motion.faces);
      faces.setAttribute('position', new THREE.BufferAttribute(new Float32Array(motion.vertices * 3), 3));
      const lines = new THREE.BufferGeometry();
      lines.setAttribute('color', new THREE.BufferAttribute(View3D.edgeColours(motion.edges), 3));
      lines.setAttribute('position', new THREE.BufferAttribute(new Float32Array(motion.edges.length * 6), 3));
      this.motionFaces = new THREE.Mesh(faces, this.faces.material);
      this.motionLines = new THREE.LineSegments(lines, this.creases.material);
      this.scene.add(this.motionFaces, this.motionLines);
      this.motionOf = motion;
      for (const o of [this.faces, this.creases, this.pins, this.anchor, this.worst, this.hover]) o.visible = false;
    }
    const pos = this.motionFaces.geometry.getAttribute('position');
    pos.array.set(motion.frames[k]);
    pos.needsUpdate = true;
    this.motionFaces.geometry.computeBoundingSphere();
    const line = this.motionLines.geometry.getAttribute('position');
    View3D.edgeEnds(motion.edges, motion.frames[k], line.array);
    line.needsUpdate = true;
    this.motionLines.geometry.computeBoundingSphere();
    this.motionFramesDrawn++;
    this.render();
  }

  /** Points the camera at every frame of a motion (the flat sheet is the widest). */
  frameMotion(motion) {
    const box = new THREE.Box3();
    const p = new THREE.Vector3();
    for (const x of motion.frames) {
      for (let i = 0; i < x.length; i += 3) box.expandByPoint(p.set(x[i], x[i + 1], x[i + 2]));
    }
    const s = box.getBoundingSphere(new THREE.Sphere());
    this.frameSphere(s);
  }

  /** Whether a motion is shown in place of the design. */
  motionShown() { return !!this.motionOf; }

  /** Back to the design. */
  endMotion() {
    if (!this.motionOf) return;
    this.scene.remove(this.motionFaces, this.motionLines);
    this.motionFaces.geometry.dispose();
    this.motionLines.geometry.dispose();
    this.motionFaces = this.motionLines = this.motionOf = null;
    for (const o of [this.faces, this.creases, this.pins, this.anchor, this.worst, this.hover]) o.visible = true;
    this.render();
  }

  /** Rebuilds what changed from the model the server sent. */
  update(model, topologyChanged) {
    const live = model.live, topo = model.topology;
    if (!live || !topo) return;
    this.positions = Float32Array.from(live.positions);
    const g = this.faces.geometry;
    if (topologyChanged) {
      g.setIndex(topo.faces);
      this.creases.geometry.setAttribute('color', new THREE.BufferAttribute(View3D.edgeColours(topo.edges), 3));
    }
    // Buffers refilled in place; no vertex normals (flat shading takes each face's own).
    View3D.fill(g, 'position', this.positions, 3);
    this.freshPositions = true;
    if (topologyChanged || !g.boundingSphere) g.computeBoundingSphere();
    if (!this.line || this.line.length !== topo.edges.length * 6) this.line = new Float32Array(topo.edges.length * 6);
    View3D.edgeEnds(topo.edges, this.positions, this.line);
    View3D.fill(this.creases.geometry, 'position', this.line, 3);
    if (topologyChanged || !this.creases.geometry.boundingSphere) this.creases.geometry.computeBoundingSphere();
    this.setMarkers(this.pins, live.pinned);
    this.setMarkers(this.anchor, live.anchor.filter((v) => !live.pinned.includes(v)));
    let worst = [];
    if (live.worst && !live.worst.pass) {
      const el = live.worst.element;
      if (el.vertex !== undefined) worst = [el.vertex];
      else if (el.faces !== undefined) {
        // Two faces that pass through each other: mark all their corners.
        worst = el.faces.flatMap((f) => Array.from(topo.faces.slice(3 * f, 3 * f + 3)));
      } else worst = (topo.edges[el.edge] || []).slice(0, 2);
    }
    this.setMarkers(this.worst, worst);
    // The marker stays on its vertex as the vertex moves (the dragged one above all).
    const marked = this.dragging ? this.dragging.vertex : this.hovered;
    this.setMarkers(this.hover, marked === null || marked === undefined || 3 * marked >= this.positions.length ? [] : [marked]);
    if (topologyChanged || !this.framed) this.frame();
    this.render();
  }

  /** Client coordinates of the hover marker, or null when none is shown (for tests). */
  markerScreen() {
    const p = this.hover.geometry.getAttribute('position');
    if (!p || p.count === 0) return null;
    const rect = this.renderer.domElement.getBoundingClientRect();
    const v = new THREE.Vector3(p.getX(0), p.getY(0), p.getZ(0)).project(this.camera);
    return { x: rect.left + (v.x + 1) / 2 * rect.width, y: rect.top + (1 - v.y) / 2 * rect.height };
  }

  setMarkers(points, vertices) {
    const p = new Float32Array(vertices.length * 3);
    vertices.forEach((v, i) => p.set(this.positions.subarray(3 * v, 3 * v + 3), i * 3));
    points.geometry.setAttribute('position', new THREE.BufferAttribute(p, 3));
    points.geometry.computeBoundingSphere();
  }

  /** Points the camera at the whole design, seen from above and in front. */
  frame() {
    const s = this.faces.geometry.boundingSphere;
    if (s) this.frameSphere(s);
  }

  /** Points the camera at a sphere, seen from above and in front. */
  frameSphere(s) {
    const d = s.radius / Math.sin((this.camera.fov * Math.PI) / 360) * 1.05;
    this.controls.target.copy(s.center);
    this.camera.position.copy(s.center).add(new THREE.Vector3(0.15, -0.75, 0.65).normalize().multiplyScalar(d));
    this.camera.near = d / 100;
    this.camera.far = d * 100;
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.framed = true;
  }

  vertex(v) {
    return new THREE.Vector3(this.positions[3 * v], this.positions[3 * v + 1], this.positions[3 * v + 2]);
  }

  /** Client coordinates of vertex v. */
  screenOf(v) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const p = this.vertex(v).project(this.camera);
    return { x: rect.left + (p.x + 1) / 2 * rect.width, y: rect.top + (1 - p.y) / 2 * rect.height };
  }

  /** The vertex nearest the pointer within PICK_PX, the nearer to the camera on a tie. */
  pick(e) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const n = this.positions.length / 3;
    let best = null, bestScore = Infinity;
    const p = new THREE.Vector3();
    for (let v = 0; v < n; v++) {
      p.set(this.positions[3 * v], this.positions[3 * v + 1], this.positions[3 * v + 2]).project(this.camera);
      const x = rect.left + (p.x + 1) / 2 * rect.width, y = rect.top + (1 - p.y) / 2 * rect.height;
      const d = Math.hypot(x - e.clientX, y - e.clientY);
      if (d > PICK_PX) continue;
      const score = d + p.z * 1e-3;
      if (score < bestScore) { best = v; bestScore = score; }
    }
    return best;
  }

  down(e) {
    // While a motion is shown, a press orbits: its vertices are not the design's.
    if (e.button !== 0 || this.motionOf) return;
    const v = this.pick(e);
    if (v === null) return;
    this.controls.enabled = false;
    if (e.shiftKey) { this.handlers.onPin(v); return; }
    const normal = new THREE.Vector3();
    this.camera.getWorldDirection(normal);
    this.dragging = { vertex: v, plane: new THREE.Plane().setFromNormalAndCoplanarPoint(normal, this.vertex(v)) };
    this.renderer.domElement.setPointerCapture(e.pointerId);
    this.handlers.onDragStart(v);
  }

  pointerOnPlane(e, plane) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2((e.clientX - rect.left) / rect.width * 2 - 1, -(e.clientY - rect.top) / rect.height * 2 + 1);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(ndc, this.camera);
    return ray.ray.intersectPlane(plane, new THREE.Vector3());
  }

  moveEvent(e) {
    if (this.dragging) {
      const p = this.pointerOnPlane(e, this.dragging.plane);
      if (p) this.handlers.onDragMove(this.dragging.vertex, [p.x, p.y, p.z]);
      return;
    }
    if (e.buttons) return;
    // Hovering projects every vertex: once per animation frame, for the latest position.
    this.lastMove = e;
    if (this.pickPending) return;
    this.pickPending = true;
    requestAnimationFrame(() => {
      this.pickPending = false;
      const v = this.pick(this.lastMove);
      this.hovered = v;
      this.renderer.domElement.style.cursor = v === null ? 'default' : 'grab';
      this.setMarkers(this.hover, v === null ? [] : [v]);
      this.render();
    });
  }

  up(e) {
    if (this.dragging) {
      this.renderer.domElement.releasePointerCapture?.(e.pointerId);
      this.dragging = null;
      this.handlers.onDragEnd();
    }
    this.controls.enabled = true;
  }
}
