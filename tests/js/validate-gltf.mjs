// The Khronos glTF validator on one .glb or .gltf (its .bin read from beside it):
// prints the validator's counts and first messages as JSON.
import validator from 'gltf-validator';
import fs from 'fs';
import path from 'path';

const file = process.argv[2];
const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
  uri: path.basename(file),
  externalResourceFunction: (uri) =>
    new Promise((resolve, reject) => {
      try {
        resolve(new Uint8Array(fs.readFileSync(path.join(path.dirname(file), decodeURIComponent(uri)))));
      } catch (e) {
        reject(e.toString());
      }
    }),
});
console.log(JSON.stringify({
  errors: report.issues.numErrors,
  warnings: report.issues.numWarnings,
  animations: report.info.animationCount,
  morphed: report.info.hasMorphTargets,
  messages: report.issues.messages.slice(0, 10),
}));
