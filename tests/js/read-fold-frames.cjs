// Rabbit Ear opens a FOLD file's frame 0 and each frame after it (a frame that inherits
// takes what it does not say from its parent, FOLD's frame_inherit): prints, per frame,
// its classes, whether Rabbit Ear finds it a folded form, whether it validates, and its
// vertices, as JSON.
const ear = require('rabbit-ear');
const fs = require('fs');

const file = JSON.parse(fs.readFileSync(process.argv[2], 'utf8'));
const frames = [file, ...(file.file_frames || [])];
const resolved = (k) => {
  const own = Object.assign({}, frames[k]);
  delete own.file_frames;
  if (k === 0 || !own.frame_inherit) return own;
  return Object.assign({}, resolved(own.frame_parent || 0), own);
};
const out = frames.map((_, k) => {
  const graph = ear.graph(resolved(k));
  return {
    classes: graph.frame_classes,
    folded: ear.graph.isFoldedForm(graph),
    valid: ear.graph.validate(graph),
    faces: (graph.faces_vertices || []).length,
    edges: (graph.edges_vertices || []).length,
    vertices: graph.vertices_coords,
  };
});
console.log(JSON.stringify(out));
