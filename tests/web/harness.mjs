// What the browser and Node tests share: their arguments (the bumprad binary and a work
// directory, emptied), a check that logs what held, the real server on a free loopback port,
// and a run in Debian's headless Chromium with SwiftShader's WebGL (no GPU needed).
import { spawn } from "node:child_process";
import { mkdirSync, rmSync } from "node:fs";
import { join } from "node:path";
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
