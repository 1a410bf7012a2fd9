// What the browser and Node tests share: their arguments (the bumprad binary and a work
// directory, emptied), a check that logs what held, the real server on a free loopback port,
// a run in Debian's headless Chromium with SwiftShader's WebGL (no GPU needed), and PNGs
// for scenes to carry.
import { spawn } from "node:child_process";
import { mkdirSync, rmSync } from "node:fs";
import { join } from "node:path";
import { crc32, deflateSync } from "node:zlib";
import { chromium } from "playwright-core";

// [BUMPRAD_BIN, WORK_DIR] from the command line; `script` names the usage.
export function args(script) {
  const [bin, work] = process.argv.slice(2);
  if (!bin || !work) {
    console.error(`usage: node ${script} BUMPRAD_BIN WORK_DIR`);
    process.exit(2);
  }
  rmSync(work, { recursive: true, force: true });
  mkdirSync(work, { recursive: true });
  return { bin, work };
}

export function check(condition, message) {
  if (!condition) throw new Error(`FAILED: ${message}`);
  console.log(`ok: ${message}`);
}

// `bumprad serve` on a free port with its data in WORK_DIR/data; resolves to the process and
// its base URL once it listens.
export async function startServer(bin, work) {
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
  return { server, base };
}

function launchBrowser() {
  return chromium.launch({
    executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
    args: ["--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
           "--disable-quic", "--no-first-run", "--disable-background-networking",
           "--disable-component-update", "--disable-sync"],
  });
}

// Runs `body(browser)` in a fresh headless Chromium, then closes it and stops `server`; exits
// 1 when the body threw (its message printed), else 0.
export async function inBrowser(server, body) {
  const browser = await launchBrowser();
  let failed = false;
  try {
    await body(browser);
  } catch (e) {
    console.error(e.message);
    failed = true;
  } finally {
    await browser.close();
    server.kill("SIGTERM");
  }
  process.exit(failed ? 1 : 0);
}

// An 8-bit RGB PNG of `pixel(x, y)` ([r, g, b] in 0..255), base64 for a scene's "files".
export function png(width, height, pixel) {
  const raw = Buffer.alloc((3 * width + 1) * height);
  for (let y = 0; y < height; ++y)
    for (let x = 0; x < width; ++x) raw.set(pixel(x, y), y * (3 * width + 1) + 1 + 3 * x);
  const chunk = (type, data) => {
    const body = Buffer.concat([Buffer.from(type), data]);
    const out = Buffer.alloc(body.length + 8);  // length, type and data, CRC
    out.writeUInt32BE(data.length, 0);
    body.copy(out, 4);
    out.writeUInt32BE(crc32(body), 4 + body.length);
    return out;
  };
  const header = Buffer.alloc(13);
  header.writeUInt32BE(width, 0);
  header.writeUInt32BE(height, 4);
  header[8] = 8;  // bits a channel
  header[9] = 2;  // RGB
  return Buffer.concat([Buffer.from([137, 80, 78, 71, 13, 10, 26, 10]), chunk("IHDR", header),
                        chunk("IDAT", deflateSync(raw)), chunk("IEND", Buffer.alloc(0))]).toString("base64");
}
