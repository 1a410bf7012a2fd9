// Drives the web viewer (server/web/) in Debian's headless Chromium through playwright-core:
// submit a built-in scene, see a streamed preview and the progress bar, then re-texture with
// new bump parameters and see the new image beside the old. Usage:
//   node tests/web/viewer_test.mjs BUMPRAD_BIN WORK_DIR
import { spawn } from "node:child_process";
import { mkdirSync, rmSync } from "node:fs";
import { join } from "node:path";
import { chromium } from "playwright-core";

const [bin, work] = process.argv.slice(2);
if (!bin || !work) {
  console.error("usage: node viewer_test.mjs BUMPRAD_BIN WORK_DIR");
  process.exit(2);
}
rmSync(work, { recursive: true, force: true });
mkdirSync(work, { recursive: true });

function check(condition, message) {
  if (!condition) throw new Error(`FAILED: ${message}`);
  console.log(`ok: ${message}`);
}

// The real server on a free loopback port.
const server = spawn(bin, ["serve", "--port", "0", "--data-dir", join(work, "data")], {
  stdio: ["ignore", "pipe", "inherit"],
});
const base = await new Promise((resolve, reject) => {
  server.on("exit", (code) => reject(new Error(`the server exited (${code})`)));
  server.stdout.on("data", (chunk) => {
    const m = /listening on (http:\/\/[0-9.]+:\d+)/.exec(chunk.toString());
    if (m) resolve(m[1]);
  });
});

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
  args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"],
});
let failed = false;
try {
  const page = await browser.newPage();
  const errors = [];
  page.on("pageerror", (e) => errors.push(e.message));
  await page.goto(base + "/");
  await page.waitForSelector("#scene-select option[value='wrinkled-box']", { state: "attached" });
  await page.selectOption("#scene-select", "wrinkled-box");
  await page.fill("#shots", "24");
  await page.fill("#preview-every", "6");
  await page.click("#submit");

  // The live <img> shows streamed frames; the bar fills; the job ends done.
  await page.waitForFunction(() => document.getElementById("live").naturalWidth > 0, null,
                             { timeout: 60000 });
  check(await page.$eval("#live", (img) => img.naturalWidth) === 512, "a preview frame arrived");
  await page.waitForFunction(() => document.getElementById("state").textContent === "done", null,
                             { timeout: 120000 });
  check(await page.$eval("#progress", (p) => p.value) === 1, "the progress bar is full");
  await page.waitForFunction(() => document.getElementById("before").naturalWidth > 0);
  check(await page.$eval("#bump-name", (s) => s.value) === "wrinkles",
        "the scene's bump function is offered for editing");

  // Re-texture: new type, amplitude and scale; the new image appears beside the old.
  await page.selectOption("#bump-type", "bricks");
  await page.fill("#bump-amplitude", "0.02");
  await page.fill("#bump-scale", "4");
  await page.click("#retexture");
  await page.waitForFunction(() => document.getElementById("after").naturalWidth > 0, null,
                             { timeout: 60000 });
  check(await page.$eval("#after", (img) => img.src.startsWith("blob:")), "a re-textured image appeared");
  check((await page.textContent("#retexture-time")).includes("no solve"), "the re-texture was timed");
  check((await page.textContent("#after-caption")).includes("bricks"), "the caption names the new bump");
  await page.screenshot({ path: join(work, "viewer.png"), fullPage: true });

  // A bad parameter is refused with the field named, and the page says so.
  await page.fill("#bump-scale", "-1");
  await page.click("#retexture");
  await page.waitForFunction(() => document.getElementById("error").textContent.length > 0);
  check((await page.textContent("#error")).includes("/bumps/wrinkles/scale"),
        "an invalid bump names its field");
  check(errors.length === 0, `no script errors (${errors.join("; ")})`);
} catch (e) {
  console.error(e.message);
  failed = true;
} finally {
  await browser.close();
  server.kill("SIGTERM");
}
process.exit(failed ? 1 : 0);
