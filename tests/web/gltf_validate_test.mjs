// The lit glTF export under the Khronos glTF validator (npm gltf-validator, pinned by
// package-lock.json): a solved built-in scene saved, exported with `bumprad export`, and
// validated with no errors and no warnings. Usage:
//   node tests/web/gltf_validate_test.mjs BUMPRAD_BIN WORK_DIR
import { execFileSync } from "node:child_process";
import { readFileSync } from "node:fs";
import { join } from "node:path";
import { validateBytes } from "gltf-validator";
import { args } from "./harness.mjs";

const { bin, work } = args("gltf_validate_test.mjs");

for (const scene of ["builtin:wrinkled-box", "builtin:paper-room"]) {
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
