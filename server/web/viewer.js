// The bumprad web viewer: the list of jobs, a scene editor checked as the server checks it,
// a job's live refinement stream and convergence curve, and live re-texturing: while a
// slider moves, draft re-textures (one ray a pixel, JPEG) follow it, newest first; when it
// rests, a full-quality one. Plain browser JavaScript over the API at /v1/openapi.
"use strict";

const $ = (id) => document.getElementById(id);
const state = {
  job: null,      // the job shown
  scene: null,    // its scene, for its bump functions
  curve: [],      // {shots, seconds, unshot} per step event
  started: 0,     // when its first event came (ms)
  events: null,   // its EventSource
};

function showError(text) {
  $("error").textContent = text || "";
}

// A problem+json answer as one line: "Invalid request: /bumps/x/type: unknown ...".
async function problemOf(response) {
  try {
    return await response.json();
  } catch {
    return { title: `HTTP ${response.status}`, detail: "" };
  }
}
const problemText = (p) => `${p.title}: ${p.detail}`;

async function getJson(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(problemText(await problemOf(response)));
  return response.json();
}

// ---- The list of jobs ----------------------------------------------------------------------

function link(href, text) {
  const a = document.createElement("a");
  a.href = href;
  a.textContent = text;
  return a;
}

const kPollMs = 2000;  // the job list while a job runs; the server's health always

async function refreshJobs() {
  clearTimeout(refreshJobs.timer);
  const { jobs } = await getJson("/v1/jobs");
  if (jobs.some((job) => job.state === "queued" || job.state === "running"))
    refreshJobs.timer = setTimeout(() => refreshJobs().catch(() => {}), kPollMs);
  $("no-jobs").hidden = jobs.length > 0;
  $("jobs").hidden = jobs.length === 0;
  const rows = jobs.map((job) => {
    const tr = document.createElement("tr");
    const cells = [0, 1, 2, 3, 4, 5].map(() => document.createElement("td"));
    if (job.latest_step_url) {
      const img = document.createElement("img");
      img.src = job.latest_step_url;
      img.alt = `job ${job.id}`;
      cells[0].append(img);
    }
    const open = link("#", job.id);
    open.addEventListener("click", (e) => {
      e.preventDefault();
      show(job);
    });
    cells[1].append(open);
    cells[2].textContent = job.scene;
    cells[3].textContent = job.state;
    cells[4].textContent = `${job.shots}/${job.max_shots}`;
    if (job.state === "done") {
      const base = `/v1/jobs/${job.id}`;
      cells[5].append(link(`${base}/image`, "PNG"), " ", link(`${base}/image?format=exr`, "EXR"),
                      " ", link(`${base}/solution`, "solution"), " ", link(`${base}/model.glb`, "glTF"),
                      " ", link(`${base}/scene`, "scene"));
    }
    tr.dataset.id = job.id;
    tr.append(...cells);
    return tr;
  });
  $("jobs").tBodies[0].replaceChildren(...rows);
}

// ---- The scene editor ----------------------------------------------------------------------

async function loadScenes() {
  const { scenes } = await getJson("/v1/scenes");
  for (const s of scenes) {
    const option = new Option(s.name, s.name);
    option.title = s.description;
    $("scene-select").add(option);
  }
}

function useJson(on) {
  $("use-json").checked = on;
  $("use-builtin").checked = !on;
  $("scene-json").hidden = !on;
  $("scene-select").disabled = on;
  if (!on) setCheck("", "");
}

// JSON indented for editing, with arrays of numbers (positions, colours) on one line.
function formatJson(value) {
  return JSON.stringify(value, null, 2).replace(
    /\[\s*(-?[\d.eE+-]+(?:,\s*-?[\d.eE+-]+)*)\s*\]/g,
    (_, inner) => `[${inner.split(/,\s*/).join(", ")}]`);
}

async function editExample() {
  const text = await (await fetch(`/v1/scenes/${$("scene-select").value}`)).text();
  $("scene-json").value = formatJson(JSON.parse(text));
  useJson(true);
  checkScene();
}

// Where each value of a JSON text starts, by JSON pointer ("/objects/0/size"), so that the
// server's errors can be shown at their line. Assumes the text is JSON (the server said so).
function valueOffsets(text) {
  const offsets = new Map();
  let i = 0;
  const space = () => {
    while (i < text.length && " \t\r\n".includes(text[i])) i++;
  };
  const string = () => {
    const start = i++;
    while (i < text.length && text[i] !== '"') i += text[i] === "\\" ? 2 : 1;
    i++;
    return JSON.parse(text.slice(start, i));
  };
  const value = (pointer) => {
    space();
    offsets.set(pointer, i);
    if (text[i] === "{") {
      i++;
      for (space(); text[i] !== "}" && i < text.length; space()) {
        const key = string();
        space();
        i++;  // the colon
        value(`${pointer}/${key.replaceAll("~", "~0").replaceAll("/", "~1")}`);
        space();
        if (text[i] === ",") i++;
      }
      i++;
    } else if (text[i] === "[") {
      i++;
      for (let n = 0; (space(), text[i] !== "]") && i < text.length; n++) {
        value(`${pointer}/${n}`);
        space();
        if (text[i] === ",") i++;
      }
      i++;
    } else if (text[i] === '"') {
      string();
    } else {
      while (i < text.length && !",]} \t\r\n".includes(text[i])) i++;
    }
  };
  value("");
  return offsets;
}

const lineAt = (text, offset) => text.slice(0, offset).split("\n").length;

function setCheck(text, kind) {
  $("scene-check").textContent = text;
  $("scene-check").className = kind;
}

// Sends the editor's text to POST /v1/validate exactly as a submit would send it, and shows
// the answer: the estimated cost, or the error at its line.
let checkTimer = null;
let checkSeq = 0;
function checkSceneSoon() {
  clearTimeout(checkTimer);
  checkTimer = setTimeout(checkScene, 400);
}

async function checkScene() {
  const text = $("scene-json").value;
  if (!text.trim()) return setCheck("", "");
  const prefix = '{"scene": ';
  const seq = ++checkSeq;
  const response = await fetch("/v1/validate", {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: `${prefix}${text}}`,
  });
  if (seq !== checkSeq) return;  // the text changed meanwhile
  if (response.ok) {
    const { estimate } = await response.json();
    const s = estimate.solve_s + estimate.render_s;
    return setCheck(`Valid. Estimated ${s.toFixed(1)} s of work (this server allows ${estimate.limit_s} s).`, "good");
  }
  const p = await problemOf(response);
  let line = null;
  const byte = /at byte (\d+)/.exec(p.detail || "");
  if (byte) {
    // The server counts bytes of the whole body; the editor shows characters.
    const bytes = new TextEncoder().encode(`${prefix}${text}`).slice(0, Number(byte[1]));
    const upTo = new TextDecoder().decode(bytes).length - prefix.length;
    line = lineAt(text, Math.max(0, Math.min(text.length, upTo)));
  } else if (p.field && p.field.startsWith("/scene")) {
    const offsets = valueOffsets(text);
    let pointer = p.field.slice("/scene".length);
    // A missing key is reported where it should be: show its parent.
    while (!offsets.has(pointer) && pointer) pointer = pointer.slice(0, pointer.lastIndexOf("/"));
    line = lineAt(text, offsets.get(pointer) ?? 0);
  }
  setCheck(line ? `Line ${line}: ${p.detail}` : problemText(p), "bad");
  if (line) selectLine(line);
}

function selectLine(line) {
  const lines = $("scene-json").value.split("\n");
  const start = lines.slice(0, line - 1).reduce((n, l) => n + l.length + 1, 0);
  $("scene-json").setSelectionRange(start, start + lines[line - 1].length);
}

// The form's shot budget and step size, onto a job request.
function withOptions(request) {
  const shots = parseInt($("shots").value, 10);
  if (shots > 0) request.solver = { max_shots: shots };
  const every = parseInt($("preview-every").value, 10);
  if (every > 0) request.preview_every = every;
  return request;
}

function jobRequest() {
  const request = {};
  if ($("use-json").checked) {
    try {
      request.scene = JSON.parse($("scene-json").value);
    } catch (e) {
      throw new Error(`The scene is not JSON: ${e.message}`);
    }
  } else {
    request.builtin = $("scene-select").value;
  }
  return withOptions(request);
}

async function submitted(response) {
  if (response.status !== 202) return showError(problemText(await problemOf(response)));
  show(await response.json());
  refreshJobs();
}

async function submit() {
  showError("");
  let request;
  try {
    request = jobRequest();
  } catch (e) {
    return showError(e.message);
  }
  await submitted(await fetch("/v1/jobs", {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify(request),
  }));
}

// Dropped or chosen files as one job, a multipart form: a scene .json among them is the
// scene, else the scene of the one model file; every other file goes with it, by name.
const MODEL_FILE = /\.(glb|gltf|obj|fbx|dae|ply|stl|3ds|blend)$/i;
async function submitFiles(list) {
  showError("");
  const files = [...list];
  const sceneFile = files.find((f) => /\.json$/i.test(f.name));
  const model = files.find((f) => MODEL_FILE.test(f.name));
  if (!sceneFile && !model)
    return showError("Drop a model (.glb, .gltf, .obj, ...) with its files, or a scene .json with the files it names.");
  let scene;
  try {
    scene = sceneFile ? JSON.parse(await sceneFile.text()) : { objects: [{ type: "model", file: model.name }] };
  } catch (e) {
    return showError(`${sceneFile.name} is not JSON: ${e.message}`);
  }
  const form = new FormData();
  form.append("job", JSON.stringify(withOptions({ scene })));
  for (const f of files) if (f !== sceneFile) form.append("file", f, f.name);
  await submitted(await fetch("/v1/jobs", { method: "POST", body: form }));
}

function showWarnings(job) {
  const warnings = job.warnings || [];
  $("warnings").replaceChildren(...warnings.map((w) => {
    const li = document.createElement("li");
    li.textContent = w;
    return li;
  }));
  $("warnings").hidden = warnings.length === 0;
}

// ---- A job: live stream, progress, convergence --------------------------------------------

function showRemove(jobState) {
  const ended = !["queued", "running"].includes(jobState);
  $("remove-job").textContent = ended ? "Delete" : "Cancel";
}

// DELETE cancels a queued or running job and deletes an ended one.
async function removeJob() {
  const response = await fetch(`/v1/jobs/${state.job.id}`, { method: "DELETE" });
  if (!response.ok) return showError(problemText(await problemOf(response)));
  if ($("remove-job").textContent === "Delete") {
    if (state.events) state.events.close();
    $("job").hidden = true;
  }
  await refreshJobs();
}

// The banner while /healthz does not answer.
async function checkServer() {
  let up = false;
  try {
    up = (await fetch("/healthz", { cache: "no-store" })).ok;
  } catch {
    up = false;
  }
  $("offline").hidden = up;
  setTimeout(checkServer, kPollMs);
}

function show(job) {
  if (state.events) state.events.close();
  state.job = job;
  showRemove(job.state);
  state.curve = [];
  state.started = 0;
  $("job").hidden = false;
  $("retexture-panel").hidden = true;
  $("job-id").textContent = job.id;
  $("state").textContent = job.state;
  showWarnings(job);
  $("live").hidden = true;
  $("live-wait").hidden = false;
  $("live").src = `/v1/jobs/${job.id}/stream`;
  drawCurve();
  // The curve so far, as the server kept it (the list's records carry no history); steps
  // that arrive later continue it on this page's clock.
  getJson(`/v1/jobs/${job.id}`).then((record) => {
    if (state.job !== job || state.curve.length > (record.history || []).length) return;
    state.curve = (record.history || []).map(([shots, seconds, unshot]) => ({ shots, seconds, unshot }));
    const last = state.curve[state.curve.length - 1];
    if (last) state.started = performance.now() - 1000 * last.seconds;
    drawCurve();
  }).catch(() => {});
  state.target = 0.01;  // the solver's default, until the job's scene says otherwise
  getJson(`/v1/jobs/${job.id}/scene`)
    .then((scene) => { state.target = scene.solver?.unshot_fraction ?? 0.01; })
    .catch(() => {});
  follow(job);
}

// The way to the solve's end: unshot power falls roughly exponentially with shots, so the
// bar follows log(unshot) from 1 down to the scene's target, or the shot cap if that comes
// first. Once either is reached the final image renders: its own phase.
function progressOf(step) {
  const byShots = step.max_shots ? step.shots / step.max_shots : 0;
  const target = state.target > 0 && state.target < 1 ? state.target : 0.01;
  const byUnshot = step.unshot_fraction > 0 ? Math.log(step.unshot_fraction) / Math.log(target) : 1;
  return Math.min(1, Math.max(byShots, byUnshot, 0));
}

function showProgress(step) {
  if (step.step > 0) {  // the stream has a frame to show
    $("live").hidden = false;
    $("live-wait").hidden = true;
  }
  const progress = progressOf(step);
  $("progress").value = progress;
  // Step events carry no state: they come while the job runs.
  const phase = progress >= 1 && (step.state ?? "running") === "running" ? "; rendering the final image" : "";
  $("progress-text").textContent =
    `${step.shots}/${step.max_shots} shots, ${(100 * step.unshot_fraction).toFixed(1)}% unshot ` +
    `(target ${(100 * state.target).toFixed(1)}%)${phase}`;
  const now = performance.now();
  if (!state.started) state.started = now;
  const last = state.curve[state.curve.length - 1];
  if (!last || step.shots > last.shots)
    state.curve.push({ shots: step.shots, seconds: (now - state.started) / 1000, unshot: step.unshot_fraction });
  drawCurve();
}

function drawCurve() {
  const svg = $("curve");
  const [w, h, left, bottom] = [svg.width.baseVal.value, svg.height.baseVal.value, 40, 24];
  const axis = $("curve-axis").value;
  const points = state.curve.filter((p) => p.unshot > 0);
  const ns = "http://www.w3.org/2000/svg";
  const el = (name, attrs, text) => {
    const e = document.createElementNS(ns, name);
    for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
    if (text !== undefined) e.textContent = text;
    return e;
  };
  const children = [el("line", { x1: left, y1: h - bottom, x2: w - 4, y2: h - bottom, stroke: "#999" }),
                    el("line", { x1: left, y1: 4, x2: left, y2: h - bottom, stroke: "#999" })];
  const xMax = Math.max(1e-9, ...points.map((p) => p[axis]));
  const yMin = Math.min(0.1, ...points.map((p) => p.unshot));
  const lo = Math.floor(Math.log10(yMin));
  const x = (v) => left + (v / xMax) * (w - left - 8);
  const y = (u) => 4 + (Math.log10(u) / lo) * (h - bottom - 8);  // log scale, 1 at the top
  for (let d = 0; d >= lo; d--)
    children.push(el("text", { x: 2, y: y(10 ** d) + 3 }, d === 0 ? "100%" : `${100 * 10 ** d}%`));
  children.push(el("text", { x: w - 60, y: h - 6 }, `${xMax.toFixed(axis === "shots" ? 0 : 1)} ${axis}`));
  if (points.length)
    children.push(el("polyline", { points: points.map((p) => `${x(p[axis])},${y(p.unshot)}`).join(" ") }));
  svg.replaceChildren(...children);
  svg.dataset.points = String(points.length);
}

function follow(job) {
  const events = new EventSource(`/v1/jobs/${job.id}/events`);
  state.events = events;
  events.addEventListener("state", (e) => {
    const record = JSON.parse(e.data);
    $("state").textContent = record.state;
    showRemove(record.state);
    if (record.step > 0) showProgress(record);
  });
  events.addEventListener("step", (e) => {
    $("state").textContent = "running";
    showProgress(JSON.parse(e.data));
  });
  const end = (e) => {
    events.close();
    const final = JSON.parse(e.data);
    $("state").textContent = final.state;
    showRemove(final.state);
    showWarnings(final);
    showProgress(final);
    refreshJobs();
    if (final.state === "done") return solved(final);
    showError(final.error || `The job ended ${final.state}.`);
  };
  for (const name of ["done", "failed", "cancelled", "interrupted"]) events.addEventListener(name, end);
}

// ---- Re-texturing ---------------------------------------------------------------------------

// Each type's own parameters, as sliders; amplitude and scale are every type's.
const PARAMS = {
  common: [{ key: "amplitude", min: 0, max: 0.05, step: 0.0005, value: 0.01 },
           { key: "scale", min: 0.5, max: 20, step: 0.5, value: 4 }],
  noise: [{ key: "octaves", min: 1, max: 8, step: 1, value: 4 }, { key: "seed", min: 0, max: 99, step: 1, value: 1 }],
  wrinkles: [{ key: "direction_deg", min: 0, max: 180, step: 1, value: 0 }],
  cylinder: [{ key: "direction_deg", min: 0, max: 180, step: 1, value: 0 }],
  bricks: [{ key: "mortar", min: 0.02, max: 0.4, step: 0.01, value: 0.1 }],
  tiles: [{ key: "mortar", min: 0.02, max: 0.4, step: 0.01, value: 0.1 }],
  dimples: [{ key: "radius", min: 0.05, max: 0.5, step: 0.01, value: 0.35 }],
};

async function solved(job) {
  $("progress").value = 1;
  $("before").src = `/v1/jobs/${job.id}/image`;
  $("after").hidden = true;
  state.scene = await getJson(`/v1/jobs/${job.id}/scene`);
  const names = Object.keys(state.scene.bumps || {});
  $("bump-name").replaceChildren(...names.map((n) => new Option(n, n)));
  // Nothing to re-texture in a scene without bump functions.
  $("retexture-panel").hidden = names.length === 0;
  $("retexture-time").textContent = "";
  if (names.length) fillBump(names[0]);
  openWalk(job).catch((e) => showError(`walkthrough: ${e.message}`));
}

// Sliders for the bump's type, set from `bump` where it has the value; a new type keeps the
// amplitude and scale the sliders had.
function fillBump(name, type) {
  const bump = state.scene.bumps[name];
  type = type || bump.type;
  $("bump-type").value = type;
  const own = type === bump.type ? { ...bump } : {};
  for (const p of PARAMS.common) {
    const slider = $(`param-${p.key}`);
    if (slider && type !== bump.type) own[p.key] = Number(slider.value);
  }
  const sliders = [...PARAMS.common, ...(PARAMS[type] || [])].map((p) => {
    const label = document.createElement("label");
    const input = Object.assign(document.createElement("input"), {
      type: "range", id: `param-${p.key}`, min: p.min, max: p.max, step: p.step,
    });
    let v = own[p.key] ?? p.value;
    if (Array.isArray(v)) v = v[0];
    input.value = v;
    const shown = document.createElement("output");
    shown.textContent = input.value;
    input.addEventListener("input", () => {
      shown.textContent = input.value;
      walk.view?.setBump($("bump-name").value, currentBump());
      render("draft");
      settleSoon();
    });
    // A slider let go where it started fires no change event: the settle timer still ends
    // the drafts with a full-quality image.
    input.addEventListener("change", () => render("final"));
    label.append(`${p.key.replace("_deg", " (deg)")} `, input, " ", shown);
    return label;
  });
  $("bump-params").replaceChildren(...sliders);
}

function currentBump() {
  const bump = { type: $("bump-type").value };
  for (const input of $("bump-params").querySelectorAll("input")) bump[input.id.slice(6)] = Number(input.value);
  return bump;
}

// Newest first: at most one re-texture in flight; while it renders, later slider positions
// replace each other, and the newest is sent when it returns.
const live = { pending: null, busy: false, frames: [], drafts: 0, finals: 0, settle: 0 };
window.viewerStats = live;

const kSettleMs = 300;  // after the last slider move, the full-quality image

function render(quality) {
  if (quality === "final") clearTimeout(live.settle);
  live.pending = { quality, name: $("bump-name").value, bump: currentBump() };
  pump();
}

function settleSoon() {
  clearTimeout(live.settle);
  live.settle = setTimeout(() => render("final"), kSettleMs);
}

async function pump() {
  if (live.busy || !live.pending) return;
  const { quality, name, bump } = live.pending;
  live.pending = null;
  live.busy = true;
  showError("");
  const started = performance.now();
  try {
    const draft = quality === "draft";
    const response = await fetch(`/v1/jobs/${state.job.id}/retexture`, {
      method: "POST",
      headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ bumps: { [name]: bump }, quality, format: draft ? "jpeg" : "png" }),
    });
    if (response.status !== 200) {
      showError(problemText(await problemOf(response)));
    } else {
      const url = URL.createObjectURL(await response.blob());
      const old = $("after").src;
      $("after").src = url;
      $("after").hidden = false;
      if (old.startsWith("blob:")) URL.revokeObjectURL(old);
      const now = performance.now();
      if (draft) {
        live.drafts++;
        live.frames = [...live.frames.filter((t) => now - t < 1000), now];
      } else {
        live.finals++;
      }
      const rate = draft ? `, ${live.frames.length} frames in the last second` : "";
      $("retexture-time").textContent =
        `${draft ? "draft" : "full quality"}: ${(now - started).toFixed(0)} ms, no solve${rate}`;
      $("after-caption").textContent =
        `Left of the split: as solved. Right: ${bump.type}, amplitude ${bump.amplitude}, scale ${bump.scale}` +
        (draft ? " (draft)" : "");
    }
  } finally {
    live.busy = false;
    pump();
  }
}

// ---- Walkthrough (walkthrough.js, a module: it may load after this script) -------------------

const walk = { view: null };
window.walk = walk;

function walkthroughLoaded() {
  if (window.Walkthrough) return Promise.resolve();
  return new Promise((resolve) => window.addEventListener("walkthrough-ready", resolve, { once: true }));
}

// The job's model in WebGL at the scene camera's size, fitted to the page's width.
async function openWalk(job) {
  await walkthroughLoaded();
  const camera = state.scene.camera || {};
  let width = camera.width || 512, height = camera.height || 512;
  const fit = Math.min(1, 960 / width);
  width = Math.round(width * fit);
  height = Math.round(height * fit);
  walk.view = walk.view || new window.Walkthrough($("walk"));
  await walk.view.open(job.id, width, height);
  walk.job = job.id;
  $("walk-panel").hidden = false;
  $("walk-info").textContent = `${width} x ${height}`;
}

async function renderHere() {
  const body = { camera: walk.view.cameraChanges(), format: "png" };
  if ($("bump-name").value) body.bumps = { [$("bump-name").value]: currentBump() };
  const response = await fetch(`/v1/jobs/${walk.job}/retexture`, {
    method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body),
  });
  if (response.status !== 200) return showError(problemText(await problemOf(response)));
  const old = $("walk-server").src;
  $("walk-server").src = URL.createObjectURL(await response.blob());
  $("walk-server").hidden = false;
  if (old.startsWith("blob:")) URL.revokeObjectURL(old);
}

function split() {
  $("after").style.clipPath = `inset(0 0 0 ${$("split").value}%)`;
}

// ---- Wiring ---------------------------------------------------------------------------------

$("use-json").addEventListener("change", () => useJson(true));
$("use-builtin").addEventListener("change", () => useJson(false));
$("edit-example").addEventListener("click", () => editExample().catch((e) => showError(e.message)));
$("scene-json").addEventListener("input", checkSceneSoon);
$("submit").addEventListener("click", submit);
$("model-files").addEventListener("change", (e) => submitFiles(e.target.files));
$("drop").addEventListener("dragover", (e) => {
  e.preventDefault();
  $("drop").classList.add("over");
});
$("drop").addEventListener("dragleave", () => $("drop").classList.remove("over"));
$("drop").addEventListener("drop", (e) => {
  e.preventDefault();
  $("drop").classList.remove("over");
  submitFiles(e.dataTransfer.files);
});
$("refresh-jobs").addEventListener("click", refreshJobs);
$("remove-job").addEventListener("click", () => removeJob().catch((e) => showError(e.message)));
$("curve-axis").addEventListener("change", drawCurve);
$("bump-name").addEventListener("change", () => fillBump($("bump-name").value));
$("bump-type").addEventListener("change", () => {
  fillBump($("bump-name").value, $("bump-type").value);
  render("final");
});
$("split").addEventListener("input", split);
$("walk-reset").addEventListener("click", () => walk.view?.reset());
$("walk-render").addEventListener("click", () => renderHere().catch((e) => showError(e.message)));
split();
loadScenes().catch((e) => showError(`Cannot list the scenes: ${e.message}`));
refreshJobs().catch((e) => showError(`Cannot list the jobs: ${e.message}`));
checkServer();
