// The viewer's WebGL walkthrough (server/web/walkthrough.js) in Debian's headless Chromium
// (SwiftShader's WebGL, no GPU) against the server: wrinkled-box solved the paper's way
// (`direct_light: radiosity`), its exported model drawn at the scene's camera, compared with
// the server's render of the same job; then a bump slider's change shows in the next frame,
// and frames a second while the slider moves are measured. Usage:
//   node tests/web/walkthrough_test.mjs BUMPRAD_BIN WORK_DIR
import { readFileSync } from "node:fs";
import { args, check, inBrowser, startServer } from "./harness.mjs";

const { bin, work } = args("walkthrough_test.mjs");
const { server, base } = await startServer(bin, work);

// wrinkled-box at 256 x 256 with 4 x 4 rays a pixel, its direct light in the radiosity (the
// paper's way, which is what vertex shading can show).
const scene = JSON.parse(readFileSync(new URL("../../scenes/wrinkled-box.json", import.meta.url)));
scene.camera.width = scene.camera.height = 256;
scene.camera.antialias = 4;
scene.solver.direct_light = "radiosity";
const submitted = await fetch(`${base}/v1/jobs`, {
  method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify({ scene }),
});
const job = await submitted.json();
for (;;) {
  const state = (await (await fetch(`${base}/v1/jobs/${job.id}`)).json()).state;
  if (state === "done") break;
  if (["failed", "cancelled", "interrupted"].includes(state)) throw new Error(`the job ended ${state}`);
  await new Promise((r) => setTimeout(r, 200));
}

await inBrowser(server, async (browser) => {
  const page = await browser.newPage();
  const errors = [];
  page.on("pageerror", (e) => errors.push(e.message));
  // three.js reports shader errors on the console.
  page.on("console", (m) => m.type() === "error" && !m.text().startsWith("Failed to load resource") &&
          errors.push(m.text()));
  await page.goto(base + "/");
  await page.waitForFunction(() => window.Walkthrough);

  // The walkthrough's frames at the scene's camera, drawn at 4 x 4 per pixel and averaged
  // (the job's camera samples 4 x 4 a pixel), against the server's images of the same job:
  // relative RMS over all pixels, in linear radiance.
  const bricks = { type: "bricks", amplitude: 0.02, scale: 4, mortar: 0.1 };
  const result = await page.evaluate(async ({ id, bricks }) => {
    const size = 256;
    const canvas = document.createElement("canvas");
    document.body.append(canvas);
    const walk = new window.Walkthrough(canvas);
    await walk.open(id, size, size, 4);
    // A source's linear radiance at size x size, a larger one box-filtered down (as the
    // server averages its rays) after its sRGB is decoded.
    const linear = (v) => { v /= 255; return v <= 0.04045 ? v / 12.92 : ((v + 0.055) / 1.055) ** 2.4; };
    const pixels = (source) => {
      const w = source.width, k = w / size;
      const c = Object.assign(document.createElement("canvas"), { width: w, height: w });
      const g = c.getContext("2d");
      g.drawImage(source, 0, 0);
      const full = g.getImageData(0, 0, w, w).data, out = new Float32Array(size * size * 3);
      for (let y = 0; y < size; ++y)
        for (let x = 0; x < size; ++x)
          for (let ch = 0; ch < 3; ++ch) {
            let sum = 0;
            for (let j = 0; j < k; ++j)
              for (let i = 0; i < k; ++i) sum += linear(full[((y * k + j) * w + x * k + i) * 4 + ch]);
            out[(y * size + x) * 3 + ch] = sum / (k * k);
          }
      return out;
    };
    const rms = (ours, theirs) => {
      let diff = 0, sum = 0;
      for (let i = 0; i < ours.length; ++i) {
        diff += (ours[i] - theirs[i]) ** 2;
        sum += theirs[i] ** 2;
      }
      return Math.sqrt(diff / sum);
    };
    const decoded = async (url) => {
      const image = new Image();
      image.src = url;
      await image.decode();
      return pixels(image);
    };
    const asSolved = await decoded(`/v1/jobs/${id}/image`);
    const before = pixels(canvas);
    // The same job re-textured with bricks, by the server and in the walkthrough.
    const response = await fetch(`/v1/jobs/${id}/retexture`, {
      method: "POST", headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ bumps: { wrinkles: bricks }, format: "png" }),
    });
    const serverBricks = await decoded(URL.createObjectURL(await response.blob()));
    walk.setBump("wrinkles", bricks);
    const after = pixels(canvas);
    // Frames a second while a slider moves, at 1280 x 720, one sample a pixel; reading a
    // pixel back makes each frame finish before the next.
    walk.renderer.setPixelRatio(1);
    walk.renderer.setSize(1280, 720, true);
    walk.view.camera.aspect = 1280 / 720;
    walk.view.camera.updateProjectionMatrix();
    const gl = walk.renderer.getContext();
    const one = new Uint8Array(4);
    const frames = 20, started = performance.now();
    for (let k = 0; k < frames; ++k) {
      walk.setBump("wrinkles", { amplitude: 0.01 + 0.0005 * k });
      gl.readPixels(640, 360, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, one);
    }
    const fps = frames / ((performance.now() - started) / 1000);
    const info = gl.getExtension("WEBGL_debug_renderer_info");
    return {
      solved: rms(before, asSolved), bricks: rms(after, serverBricks), unlike: rms(after, asSolved), fps,
      renderer: info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : "unknown",
    };
  }, { id: job.id, bricks });
  const percent = (x) => `${(100 * x).toFixed(2)} %`;
  console.log(`walkthrough on ${result.renderer}: relative RMS against the server's render ` +
              `${percent(result.solved)} as solved, ${percent(result.bricks)} with bricks ` +
              `(${percent(result.unlike)} between the bricks and the solved image); ` +
              `${result.fps.toFixed(1)} frames/s at 1280 x 720 while a bump changes`);
  check(result.solved < 0.02, "the walkthrough's frame is within 2 % of the server's render as solved");
  check(result.bricks < 0.02, "with new bumps too (re-textured by the server, live in the walkthrough)");
  check(result.unlike > 0.025, "and the bumps' change is larger than that bound");
  check(errors.length === 0, `no page errors (${errors.join("; ")})`);
});
