// The lit glTF export under the Khronos glTF validator (npm gltf-validator, pinned by
// package-lock.json): solved scenes saved (two built-ins, and one whose images go into the
// file), exported with `bumprad export`, and validated with no errors and no warnings. Usage:
//   node tests/web/gltf_validate_test.mjs BUMPRAD_BIN WORK_DIR
import { execFileSync } from "node:child_process";
import { readFileSync, writeFileSync } from "node:fs";
import { join } from "node:path";
import { validateBytes } from "gltf-validator";
import { args, png } from "./harness.mjs";

const { bin, work } = args("gltf_validate_test.mjs");

// A scene whose images go into the file: an image colour texture, image heights, a normal map.
const images = join(work, "images.json");
writeFileSync(images, JSON.stringify({
  camera: { position: [0, 1, 3], look_at: [0, 0.5, 0] },
  files: { "c.png": png(8, 8, (x, y) => [30 * x, 30 * y, 100]), "n.png": png(8, 8, () => [140, 120, 250]) },
  materials: { m: { texture: { type: "image", file: "c.png" } }, lamp: { emission: 20 } },
  bumps: { h: { type: "image", file: "c.png", amplitude: 0.01 }, n: { type: "normal_map", file: "n.png" } },
  objects: [
    { type: "quad", material: "m", bump: "h", vertices: [[-1, 0, -1], [-1, 0, 1], [1, 0, 1], [1, 0, -1]] },
    { type: "quad", material: "m", bump: "n", vertices: [[-1, 0, -1], [1, 0, -1], [1, 1, -1], [-1, 1, -1]] },
    { type: "quad", material: "lamp", vertices: [[-0.2, 1.5, -0.2], [0.2, 1.5, -0.2], [0.2, 1.5, 0.2], [-0.2, 1.5, 0.2]] },
  ],
}));

for (const scene of ["builtin:wrinkled-box", "builtin:paper-room", images]) {
  const solution = join(work, "scene.bumprad"), model = join(work, "scene.glb");
  execFileSync(bin, ["render", scene, "-o", join(work, "scene.png"), "--shots", "40",
                     "--save-map", solution], { stdio: ["ignore", "ignore", "inherit"] });
  execFileSync(bin, ["export", solution, "-o", model], { stdio: ["ignore", "inherit", "inherit"] });
  const report = await validateBytes(new Uint8Array(readFileSync(model)));
  const bad = report.issues.messages.filter((m) => m.severity <= 1);
  for (const m of bad.slice(0, 10)) console.error(`${m.code} at ${m.pointer}: ${m.message}`);
  if (report.issues.numErrors || report.issues.numWarnings) {
    console.error(`FAILED: ${scene}: ${report.issues.numErrors} errors, ${report.issues.numWarnings} warnings`);
    process.exit(1);
  }
  const info = report.info;
  console.log(`ok: ${scene}: valid glTF ${info.version}, ${info.totalVertexCount} vertices, ` +
              `${info.totalTriangleCount} triangles, extensions ${info.extensionsUsed}`);
}
