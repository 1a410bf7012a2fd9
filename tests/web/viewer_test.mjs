// Drives the web viewer (server/web/) in Debian's headless Chromium through playwright-core:
// the first screen, the scene editor's checks at the offending line, a submitted job's
// stream, progress and convergence curve, the job list's downloads, then a dragged slider
// re-texturing live and a split before/after view, and a model dropped on the page. Usage:
//   node tests/web/viewer_test.mjs BUMPRAD_BIN WORK_DIR
import { readFileSync } from "node:fs";
import { join } from "node:path";
import { args, check, inBrowser, startServer } from "./harness.mjs";

const { bin, work } = args("viewer_test.mjs");
const { server, base } = await startServer(bin, work);
await inBrowser(server, async (browser) => {
  const page = await browser.newPage();
  const errors = [];
  page.on("pageerror", (e) => errors.push(e.message));
  await page.goto(base + "/");
  await page.waitForSelector("#scene-select option[value='wrinkled-box']", { state: "attached" });
  check(await page.isVisible("#no-jobs"), "the first screen says there are no jobs yet");
  check(!(await page.isVisible("#after")), "no broken image where the re-texture will go");

  // The editor: an example scene loads and is valid; errors are shown at their line.
  await page.selectOption("#scene-select", "wrinkled-box");
  await page.click("#edit-example");
  await page.waitForFunction(() => document.getElementById("scene-check").textContent.startsWith("Valid"));
  check(true, "an example scene loads into the editor and the server finds it valid");
  check((await page.inputValue("#scene-json")).includes('"position": [0.6, 1.55, 1.9]'),
        "the example keeps a position's numbers on one line");
  const scene = [
    "{",
    '  "camera": {"position": [0, 1, -3], "look_at": [0, 1, 0]},',
    '  "materials": {"m": {"reflectance": 0.5}},',
    '  "objects": [',
    '    {"type": "box", "material": "m",',
    '     "center": [0, 1, 0],',
    '     "size": [1, -2, 1]}',
    "  ]",
    "}",
  ].join("\n");
  await page.fill("#scene-json", scene);
  await page.waitForFunction(() => document.getElementById("scene-check").textContent.startsWith("Line"));
  let said = await page.textContent("#scene-check");
  check(said.startsWith("Line 7: /scene/objects/0/size/1: must be greater than 0"),
        `an invalid value is shown at its line (${said})`);
  await page.fill("#scene-json", scene.replace('"m",', '"m"'));
  await page.waitForFunction(() => /^Line \d+: malformed/.test(document.getElementById("scene-check").textContent));
  said = await page.textContent("#scene-check");
  check(/^Line 5: malformed JSON at byte \d+: a comma is missing after this value/.test(said),
        `a missing comma is shown at the line that needs it (${said})`);

  // Submit a built-in scene: the first frame, the progress bar, the convergence curve.
  await page.check("#use-builtin");
  await page.fill("#shots", "24");
  await page.fill("#preview-every", "6");
  await page.click("#submit");
  await page.waitForFunction(() => document.getElementById("live").naturalWidth > 0, null,
                             { timeout: 60000 });
  check(await page.$eval("#live", (img) => img.naturalWidth) === 512, "a preview frame arrived");
  await page.waitForFunction(() => document.getElementById("state").textContent === "done", null,
                             { timeout: 120000 });
  check(await page.$eval("#progress", (p) => p.value) === 1, "the progress bar is full");
  const solvedId = await page.textContent("#job-id");
  // Progress is the way down to the unshot target (log scale), or the shot cap if nearer.
  const halfway = await page.evaluate(() => {
    state.target = 0.01;
    return [progressOf({ shots: 10, max_shots: 1000, unshot_fraction: 0.1 }),
            progressOf({ shots: 900, max_shots: 1000, unshot_fraction: 0.5 })];
  });
  check(Math.abs(halfway[0] - 0.5) < 1e-9 && Math.abs(halfway[1] - 0.9) < 1e-9,
        `progress follows the unshot power to its target, or the shot cap (${halfway})`);
  check(Number(await page.$eval("#curve", (s) => s.dataset.points)) >= 2,
        "the convergence curve has a point per step");
  await page.selectOption("#curve-axis", "seconds");
  check((await page.textContent("#curve")).includes("seconds"), "the curve can be drawn against seconds");
  await page.waitForFunction(() => document.querySelector("#jobs tbody tr td:nth-child(4)")?.textContent === "done");
  const links = await page.$$eval("#jobs tbody a", (as) => as.map((a) => a.getAttribute("href")));
  check(links.some((h) => h.endsWith("/solution")) && links.some((h) => h.endsWith("format=exr")),
        "the job list links the image, the EXR and the solution");
  const solution = await page.evaluate(async (href) => (await fetch(href)).status,
                                       links.find((h) => h.endsWith("/solution")));
  check(solution === 200, "the solution downloads");
  await page.waitForFunction(() => document.getElementById("before").naturalWidth > 0);
  check(await page.$eval("#bump-name", (s) => s.value) === "wrinkles",
        "the scene's bump function is offered for editing");
  // The walkthrough opens on the done job (its accuracy: walkthrough_test.mjs); a slider
  // moves it too, and its view renders on the server on request.
  await page.waitForSelector("#walk-panel", { state: "visible" });
  const walkFrames = () => page.evaluate(() => window.walk.view.drawn);
  const framesBefore = await walkFrames();

  // Drag the amplitude slider: drafts follow it, a full-quality image ends it. The drag goes
  // on (back and forth, at most 30 s) until a second draft came, however slow this machine
  // renders them: one second of dragging had seen one draft on a loaded 2-core machine.
  const t0 = Date.now();
  await page.evaluate(async () => {
    const slider = document.getElementById("param-amplitude");
    for (let i = 0; i <= 30 || (window.viewerStats.drafts < 2 && i < 900); i++) {
      slider.value = String(0.002 + (i % 60 < 30 ? i % 30 : 30 - (i % 30)) * 0.001);
      slider.dispatchEvent(new Event("input"));
      await new Promise((r) => setTimeout(r, 33));
    }
    slider.dispatchEvent(new Event("change"));
  });
  await page.waitForFunction(() => window.viewerStats.finals >= 1 && !window.viewerStats.busy,
                             null, { timeout: 60000 });
  const stats = await page.evaluate(() => ({ drafts: window.viewerStats.drafts }));
  const seconds = (Date.now() - t0) / 1000;
  console.log(`info: ${stats.drafts} drafts in ${seconds.toFixed(1)} s of dragging and settling`);
  check(stats.drafts >= 2, "drafts followed the slider");
  check((await walkFrames()) > framesBefore + 20, "the walkthrough drew a frame at each slider move");
  await page.click("#walk-render");
  await page.waitForFunction(() => document.getElementById("walk-server").naturalWidth > 0);
  check(true, "the server renders the walkthrough's view on request");
  check(await page.isVisible("#after"), "the re-textured image is shown");
  check((await page.textContent("#retexture-time")).startsWith("full quality"),
        "the image at rest is full quality");
  // The drag runs past 30 steps on a loaded machine (until two drafts came), so its last
  // value is read, not assumed (it was 0.032 only when the drag stopped at step 30).
  const last = await page.evaluate(() => document.getElementById("param-amplitude").value);
  check((await page.textContent("#after-caption")).includes(`amplitude ${last}`),
        `the image at rest shows the slider's last value (${last})`);
  // Back to where it started with no change event (a drag let go at its starting point): the
  // image at rest is still full quality.
  const finals = await page.evaluate(() => window.viewerStats.finals);
  await page.evaluate(async () => {
    const slider = document.getElementById("param-amplitude");
    const start = slider.value;
    slider.value = "0.02";
    slider.dispatchEvent(new Event("input"));
    await new Promise((r) => setTimeout(r, 33));
    slider.value = start;
    slider.dispatchEvent(new Event("input"));
  });
  await page.waitForFunction((n) => window.viewerStats.finals > n && !window.viewerStats.busy,
                             finals, { timeout: 60000 });
  check((await page.textContent("#retexture-time")).startsWith("full quality"),
        "a slider let go where it started ends with a full-quality image");
  await page.selectOption("#bump-type", "bricks");
  check(await page.isVisible("#param-mortar"), "a type's own parameters get sliders");
  await page.waitForFunction(() => document.getElementById("after-caption").textContent.includes("bricks"));
  await page.fill("#split", "30");
  await page.dispatchEvent("#split", "input");
  check((await page.$eval("#after", (img) => img.style.clipPath)).includes("30%"),
        "the split slider moves the before/after boundary");

  // A model dropped on the page: the real test glTF (.gltf, .bin, texture) as one job, with
  // what its importer assumed listed beside it.
  const box = "/usr/share/assimp/models/glTF2/BoxTextured-glTF";
  const dropped = ["BoxTextured.gltf", "BoxTextured0.bin", "CesiumLogoFlat.png"].map((name) => ({
    name, base64: readFileSync(join(box, name)).toString("base64"),
  }));
  const before = await page.textContent("#job-id");
  await page.evaluate((files) => {
    const transfer = new DataTransfer();
    for (const f of files)
      transfer.items.add(new File([Uint8Array.from(atob(f.base64), (c) => c.charCodeAt(0))], f.name));
    document.getElementById("drop").dispatchEvent(
      new DragEvent("drop", { dataTransfer: transfer, bubbles: true, cancelable: true }));
  }, dropped);
  await page.waitForFunction((old) => document.getElementById("job-id").textContent !== old &&
                                      document.getElementById("state").textContent === "done",
                             before, { timeout: 60000 });
  const warned = await page.textContent("#warnings");
  check(warned.includes("\"BoxTextured.gltf\": material \"Texture\": base colour above 0.99"),
        `a dropped glTF with its files solves, its importer's warnings shown (${warned})`);
  await page.screenshot({ path: join(work, "viewer.png"), fullPage: true });

  // Reopened from the list, a job draws the curve the server kept with it.
  await page.evaluate(() => { state.curve = []; drawCurve(); });
  await page.click(`#jobs tbody tr[data-id='${solvedId}'] td:nth-child(2) a`);
  await page.waitForFunction(() => Number(document.getElementById("curve").dataset.points) >= 2);
  check(true, "a reopened job's convergence curve is drawn from its history");

  // Delete the ended job from its panel: it leaves the list.
  const dropId = await page.textContent("#job-id");
  check((await page.textContent("#remove-job")) === "Delete", "an ended job offers Delete");
  await page.click("#remove-job");
  await page.waitForFunction((id) => ![...document.querySelectorAll("#jobs tbody tr")]
                                       .some((tr) => tr.dataset.id === id), dropId);
  check(!(await page.isVisible("#job")), "a deleted job leaves the list and its panel closes");
  check(errors.length === 0, `no script errors (${errors.join("; ")})`);

  // The server gone: a banner says so.
  check(!(await page.isVisible("#offline")), "no banner while the server answers");
  server.kill("SIGTERM");
  await page.waitForSelector("#offline", { state: "visible", timeout: 15000 });
  check(true, "a banner says when the server cannot be reached");
});
