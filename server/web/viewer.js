// The bumprad web viewer: submit a scene, watch its refinement steps arrive, then
// re-texture the solved job with new bump parameters. Plain browser JavaScript over the
// API described at /v1/openapi.
"use strict";

const $ = (id) => document.getElementById(id);
let scene = null;  // the submitted job's scene, for its bump functions
let jobId = null;

function showError(text) {
  $("error").textContent = text || "";
}

// A problem+json answer as one line: "Invalid request: /bumps/x/type: unknown ...".
async function problemText(response) {
  try {
    const p = await response.json();
    return `${p.title}: ${p.detail}`;
  } catch {
    return `HTTP ${response.status}`;
  }
}

async function loadScenes() {
  const response = await fetch("/v1/scenes");
  const { scenes } = await response.json();
  for (const s of scenes) {
    const option = new Option(s.name, s.name);
    option.title = s.description;
    $("scene-select").add(option);
  }
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
  const shots = parseInt($("shots").value, 10);
  if (shots > 0) request.solver = { max_shots: shots };
  const every = parseInt($("preview-every").value, 10);
  if (every > 0) request.preview_every = every;
  return request;
}

async function submit() {
  showError("");
  let request;
  try {
    request = jobRequest();
  } catch (e) {
    return showError(e.message);
  }
  const response = await fetch("/v1/jobs", {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify(request),
  });
  if (response.status !== 202) return showError(await problemText(response));
  const job = await response.json();
  jobId = job.id;
  $("job").hidden = false;
  $("retexture-panel").hidden = true;
  $("job-id").textContent = job.id;
  $("live").src = `/v1/jobs/${job.id}/stream`;
  follow(job);
}

function showProgress(step) {
  $("progress").value = step.max_shots ? step.shots / step.max_shots : 0;
  $("progress-text").textContent =
    `${step.shots}/${step.max_shots} shots, ${(100 * step.unshot_fraction).toFixed(1)}% unshot`;
}

function follow(job) {
  const events = new EventSource(`/v1/jobs/${job.id}/events`);
  events.addEventListener("state", (e) => {
    $("state").textContent = JSON.parse(e.data).state;
  });
  events.addEventListener("step", (e) => {
    $("state").textContent = "running";
    showProgress(JSON.parse(e.data));
  });
  const end = (e) => {
    events.close();
    const final = JSON.parse(e.data);
    $("state").textContent = final.state;
    showProgress(final);
    if (final.state === "done") return solved(final);
    showError(final.error || `The job ended ${final.state}.`);
  };
  for (const name of ["done", "failed", "cancelled", "interrupted"]) events.addEventListener(name, end);
}

async function solved(job) {
  $("progress").value = 1;
  $("before").src = `/v1/jobs/${job.id}/image`;
  const response = await fetch(`/v1/jobs/${job.id}/scene`);
  scene = await response.json();
  const names = Object.keys(scene.bumps || {});
  $("bump-name").replaceChildren(...names.map((n) => new Option(n, n)));
  $("retexture-panel").hidden = false;
  $("retexture").disabled = names.length === 0;
  $("retexture-time").textContent = names.length ? "" : "This scene has no bump functions.";
  if (names.length) fillBump(names[0]);
}

function fillBump(name) {
  const bump = scene.bumps[name];
  $("bump-type").value = bump.type;
  $("bump-amplitude").value = bump.amplitude ?? 0.01;
  $("bump-scale").value = Array.isArray(bump.scale) ? bump.scale[0] : (bump.scale ?? 1);
}

async function retexture() {
  showError("");
  const name = $("bump-name").value;
  const bump = {
    type: $("bump-type").value,
    amplitude: parseFloat($("bump-amplitude").value),
    scale: parseFloat($("bump-scale").value),
  };
  const started = performance.now();
  const response = await fetch(`/v1/jobs/${jobId}/retexture`, {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify({ bumps: { [name]: bump } }),
  });
  if (response.status !== 200) return showError(await problemText(response));
  const blob = await response.blob();
  const old = $("after").src;
  $("after").src = URL.createObjectURL(blob);
  if (old.startsWith("blob:")) URL.revokeObjectURL(old);
  const ms = performance.now() - started;
  $("after-caption").textContent = `Re-textured: ${bump.type}, amplitude ${bump.amplitude}, scale ${bump.scale}`;
  $("retexture-time").textContent = `${ms.toFixed(0)} ms, no solve`;
}

$("use-json").addEventListener("change", () => {
  $("scene-json").hidden = !$("use-json").checked;
  $("scene-select").disabled = $("use-json").checked;
});
$("submit").addEventListener("click", submit);
$("retexture").addEventListener("click", retexture);
$("bump-name").addEventListener("change", () => fillBump($("bump-name").value));
loadScenes().catch((e) => showError(`Cannot list the scenes: ${e.message}`));
