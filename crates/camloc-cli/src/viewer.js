// camloc viewer: the page `camloc localize --html` and `camloc reconstruct --html` write.
// Plain JavaScript and 2D canvases, no library, no network: the data is the JSON in the
// element #data (written by crates/camloc-cli/src/html.rs):
//   { title, fps, cameras: [{label, azimuth, elevation}], landmarks: [15 names],
//     limbs: [[parent, child] x 14], groups: [{name, frames: [index]}],
//     frames: [{id, frame, person, input: [15 x [u, v] | null], reprojection: [15 x [u, v]] | null,
//               pose: [15 x [x, y, z]] | null (metres, z up, facing -x),
//               label, probabilities: [12] | null, direction: [azimuth, elevation, radius] | null
//               (degrees), smoothed: label | null, smoothed_direction: [azimuth, elevation] | null
//               (degrees), error: text | null}] }
// Panels: the 2D input (a pale band) with the reprojection (thin); the 3D skeleton and the camera
// sphere, seen from one viewpoint that a mouse drag turns and the wheel zooms; a timeline
// (play, scrub) over the frames of the chosen group (a person of a sequence, or every pose).
// When drawn, the page sets body[data-status] to "ready" and body[data-skeleton-pixels] to
// the number of 3D-panel pixels in the limb colours (the browser test reads both); a script
// error is shown in #errors and sets data-status to "error".
"use strict";

const LEFT = "#1f77b4", RIGHT = "#d62728", CENTRE = "#333333", DIRECTION = "#e6730f";

window.addEventListener("error", (e) => {
  document.getElementById("errors").textContent += e.message + "\n";
  document.body.dataset.status = "error";
});

const data = JSON.parse(document.getElementById("data").textContent);
// The shared view of the 3D and sphere panels: degrees, and a zoom factor.
const view = { azimuth: 215, elevation: 15, zoom: 1 };
let group = 0, position = 0, timer = null;

/** Colour of the limb ending at landmark `child` (by the landmark's name). */
function limbColour(child) {
  const name = data.landmarks[child];
  return name.startsWith("left") ? LEFT : name.startsWith("right") ? RIGHT : CENTRE;
}

/** The point of the unit sphere at azimuth `a` and elevation `e` (degrees), z up. */
function spherePoint(a, e) {
  const [ar, er] = [a * Math.PI / 180, e * Math.PI / 180];
  return [Math.cos(er) * Math.cos(ar), Math.cos(er) * Math.sin(ar), Math.sin(er)];
}

const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const unit = (a) => { const n = Math.hypot(...a) || 1; return a.map((c) => c / n); };

/** Screen axes of a camera on the view sphere looking at the origin (docs/conventions.md
 * section 2): right, down, and towards the scene (for depth). */
function viewAxes() {
  const z = spherePoint(view.azimuth, view.elevation).map((c) => -c);
  const x = unit(cross(z, [0, 0, 1]));
  return [x, cross(z, x), z];
}

/** Draws `points` (15 screen points or null) as limbs; as a pale wide band for the input
 * under the thin reprojection, so that the residuals show. */
function drawLimbs(ctx, points, band, width) {
  ctx.lineWidth = band ? 7 : width;
  ctx.lineCap = "round";
  ctx.globalAlpha = band ? 0.3 : 1;
  for (const [a, b] of data.limbs) {
    if (!points[a] || !points[b]) continue;
    ctx.strokeStyle = limbColour(b);
    ctx.beginPath();
    ctx.moveTo(...points[a]);
    ctx.lineTo(...points[b]);
    ctx.stroke();
  }
  ctx.globalAlpha = 1;
}

/** Rings at the `points` (15 screen points or null) of the landmarks missing in the frame's
 * input `f.input`: filled in from the pose basis, not measured. */
function ringFilled(ctx, points, f) {
  ctx.strokeStyle = "#222222";
  ctx.fillStyle = "#ffffff";
  ctx.lineWidth = 1.5;
  points.forEach((p, i) => {
    if (!p || f.input[i] !== null) return;
    ctx.beginPath();
    ctx.arc(...p, 4, 0, 2 * Math.PI);
    ctx.fill();
    ctx.stroke();
  });
}

/** A canvas cleared, with its 2D context and size. */
function panel(id) {
  const canvas = document.getElementById(id);
  const ctx = canvas.getContext("2d");
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  return [ctx, canvas.width, canvas.height];
}

/** The 2D panel: input (a pale band) and reprojection (thin; the input itself where there
 * is none) fitted into the canvas, v down. */
function draw2d(f) {
  const [ctx, w, h] = panel("image");
  const all = [...f.input, ...(f.reprojection || [])].filter((p) => p);
  if (!all.length) return;
  const lo = [0, 1].map((k) => Math.min(...all.map((p) => p[k])));
  const hi = [0, 1].map((k) => Math.max(...all.map((p) => p[k])));
  const s = 0.85 * Math.min(w, h) / Math.max(hi[0] - lo[0], hi[1] - lo[1], 1e-9);
  const map = (p) => p && [w / 2 + s * (p[0] - (lo[0] + hi[0]) / 2), h / 2 + s * (p[1] - (lo[1] + hi[1]) / 2)];
  drawLimbs(ctx, f.input.map(map), true, 2);
  drawLimbs(ctx, (f.reprojection || f.input).map(map), false, 2);
  if (f.reprojection) ringFilled(ctx, f.reprojection.map(map), f);
}

/** Writes `text` from (x, y) in lines no wider than `width` pixels, `step` pixels apart. */
function fillWrapped(ctx, text, x, y, width, step) {
  let line = "";
  for (const word of text.split(/\s+/)) {
    const longer = line ? `${line} ${word}` : word;
    if (line && ctx.measureText(longer).width > width) {
      ctx.fillText(line, x, y);
      y += step;
      line = word;
    } else {
      line = longer;
    }
  }
  if (line) ctx.fillText(line, x, y);
}

/** The 3D panel: the skeleton (pelvis at the centre) over a floor grid, seen from `view`. */
function draw3d(f) {
  const [ctx, w, h] = panel("skeleton");
  if (!f.pose) {
    fillWrapped(ctx, f.error || "no 3D pose", 10, 20, w - 20, 16);
    return;
  }
  const [x, y] = viewAxes();
  const s = 0.4 * Math.min(w, h) * view.zoom;
  // Centred on the pelvis horizontally and on the body's height vertically.
  const floor = Math.min(...f.pose.map((p) => p[2]));
  const middle = [0, 0, (floor + Math.max(...f.pose.map((p) => p[2]))) / 2];
  const screen = (p) => {
    const q = [p[0] - middle[0], p[1] - middle[1], p[2] - middle[2]];
    return [w / 2 + s * dot(x, q), h / 2 + s * dot(y, q)];
  };
  ctx.strokeStyle = "#dddddd";
  ctx.lineWidth = 1;
  for (let k = -4; k <= 4; k++) {
    for (const [a, b] of [[[k / 4, -1, floor], [k / 4, 1, floor]], [[-1, k / 4, floor], [1, k / 4, floor]]]) {
      ctx.beginPath();
      ctx.moveTo(...screen(a));
      ctx.lineTo(...screen(b));
      ctx.stroke();
    }
  }
  drawLimbs(ctx, f.pose.map(screen), false, 4);
  ringFilled(ctx, f.pose.map(screen), f);
}

/** The sphere panel: rings of the camera elevations, each camera sized and labelled by its
 * probability (the chosen one in red), the continuous direction and its uncertainty circle. */
function drawSphere(f) {
  const [ctx, w, h] = panel("sphere");
  const [x, y, z] = viewAxes();
  const r = 0.4 * Math.min(w, h) * view.zoom;
  const screen = (p) => [w / 2 + r * dot(x, p), h / 2 + r * dot(y, p)];
  ctx.strokeStyle = "#cccccc";
  ctx.lineWidth = 1;
  for (const e of [...new Set(data.cameras.map((c) => c.elevation))]) {
    ctx.beginPath();
    for (let k = 0; k <= 72; k++) ctx.lineTo(...screen(spherePoint(5 * k, e)));
    ctx.stroke();
  }
  // The body at the centre: a vertical line and a nose towards the front (-x).
  ctx.strokeStyle = CENTRE;
  ctx.lineWidth = 2;
  for (const [a, b] of [[[0, 0, -0.3], [0, 0, 0.3]], [[0, 0, 0.25], [-0.15, 0, 0.25]]]) {
    ctx.beginPath();
    ctx.moveTo(...screen(a));
    ctx.lineTo(...screen(b));
    ctx.stroke();
  }
  if (f.direction) {
    const [a, e, radius] = f.direction;
    const d = spherePoint(a, e);
    const across = spherePoint(a + 90, 0);
    const up = cross(d, across);
    const u = radius * Math.PI / 180;
    ctx.fillStyle = DIRECTION;
    ctx.strokeStyle = DIRECTION;
    ctx.globalAlpha = 0.25;
    ctx.beginPath();
    for (let k = 0; k <= 48; k++) {
      const phi = 2 * Math.PI * k / 48;
      ctx.lineTo(...screen([0, 1, 2].map((i) =>
        d[i] * Math.cos(u) + (across[i] * Math.cos(phi) + up[i] * Math.sin(phi)) * Math.sin(u))));
    }
    ctx.fill();
    // Its outline too: a circle seen edge-on has no area to shade.
    ctx.globalAlpha = 0.8;
    ctx.lineWidth = 1;
    ctx.stroke();
    ctx.globalAlpha = 1;
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.moveTo(...screen([0, 0, 0]));
    ctx.lineTo(...screen(d));
    ctx.stroke();
  }
  // A sequence's smoothed direction: a red line and dot, beside the frame's own orange one.
  if (f.smoothed_direction) {
    const s = screen(spherePoint(...f.smoothed_direction));
    ctx.strokeStyle = RIGHT;
    ctx.fillStyle = RIGHT;
    ctx.lineWidth = 1.5;
    ctx.setLineDash([4, 3]);
    ctx.beginPath();
    ctx.moveTo(...screen([0, 0, 0]));
    ctx.lineTo(...s);
    ctx.stroke();
    ctx.setLineDash([]);
    ctx.beginPath();
    ctx.arc(...s, 3, 0, 2 * Math.PI);
    ctx.fill();
  }
  const label = f.smoothed || f.label;
  // The cameras over the direction's disk; labels dark on a white halo, the chosen camera's
  // in bold and never faded, nor a camera of 5% or more; a frame's own camera ringed when the
  // smoothed one differs.
  data.cameras.forEach((c, i) => {
    const p = spherePoint(c.azimuth, c.elevation);
    const q = screen(p);
    const prob = f.probabilities ? f.probabilities[i] : null;
    const chosen = c.label === label;
    const radius = 3 + 12 * Math.sqrt(prob || 0);
    ctx.globalAlpha = dot(p, z) > 0 && !chosen && !(prob >= 0.05) ? 0.45 : 1;
    ctx.fillStyle = chosen ? RIGHT : "#777777";
    ctx.beginPath();
    ctx.arc(...q, radius, 0, 2 * Math.PI);
    ctx.fill();
    if (f.smoothed && f.label && c.label === f.label && f.label !== f.smoothed) {
      ctx.strokeStyle = CENTRE;
      ctx.lineWidth = 1.5;
      ctx.beginPath();
      ctx.arc(...q, radius + 3, 0, 2 * Math.PI);
      ctx.stroke();
    }
    // A pose that could not be localized has no probabilities: the labels alone.
    const percent = prob === null ? "" : ` ${(100 * prob).toFixed(0)}%`;
    const text = `${String(c.label).padStart(2, "0")}${percent}`;
    ctx.font = chosen ? "bold 12px sans-serif" : "11px sans-serif";
    ctx.fillStyle = chosen ? "#222222" : "#555555";
    ctx.lineWidth = 3;
    ctx.strokeStyle = "#ffffff";
    ctx.strokeText(text, q[0] + 9, q[1] - 8);
    ctx.fillText(text, q[0] + 9, q[1] - 8);
    ctx.globalAlpha = 1;
  });
  // What the marks are (nothing is marked for a pose that could not be localized).
  if (f.probabilities) {
    ctx.font = "11px sans-serif";
    ctx.fillStyle = "#555555";
    const legend = f.smoothed
      ? "red: the smoothed camera and direction; dots and orange: this frame's own"
      : "red: the camera; dot areas: probabilities; orange: the direction";
    ctx.fillText(legend, 8, h - 8);
  }
}

/** The text under the panels for frame `f`. */
function describe(f) {
  const parts = [f.id];
  if (f.frame !== null) parts.push(`frame ${f.frame}`);
  if (f.person !== null) parts.push(`person ${f.person}`);
  if (f.label) parts.push(`camera ${String(f.label).padStart(2, "0")} (p = ${f.probabilities[f.label - 1].toFixed(3)})`);
  if (f.smoothed) parts.push(`smoothed camera ${String(f.smoothed).padStart(2, "0")}`);
  if (f.direction) parts.push(`direction: azimuth ${f.direction[0].toFixed(1)}, elevation ${f.direction[1].toFixed(1)}, +- ${f.direction[2].toFixed(1)} deg`);
  if (f.smoothed_direction) parts.push(`smoothed direction: azimuth ${f.smoothed_direction[0].toFixed(1)}, elevation ${f.smoothed_direction[1].toFixed(1)} deg`);
  // A landmark missing in the input but reconstructed was filled in from the pose basis.
  const filled = f.pose ? data.landmarks.filter((_, i) => f.input[i] === null) : [];
  if (filled.length) parts.push(`filled in (rings): ${filled.join(", ")}`);
  if (f.error) parts.push(`error: ${f.error}`);
  return parts.join("; ");
}

/** Draws the current frame of the current group. */
function draw() {
  const frames = data.groups[group].frames;
  const f = data.frames[frames[position]];
  document.getElementById("scrub").max = frames.length - 1;
  document.getElementById("scrub").value = position;
  document.getElementById("position").textContent = `${position + 1} / ${frames.length}`;
  document.getElementById("caption").textContent = describe(f);
  draw2d(f);
  draw3d(f);
  drawSphere(f);
}

/** Counts the 3D panel's pixels in the limb colours (for the browser test). */
function skeletonPixels() {
  const canvas = document.getElementById("skeleton");
  const pixels = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
  let n = 0;
  for (let i = 0; i < pixels.length; i += 4) {
    const [r, g, b, a] = [pixels[i], pixels[i + 1], pixels[i + 2], pixels[i + 3]];
    if (a > 200 && ((b > 150 && r < 80) || (r > 180 && g < 80 && b < 80))) n++;
  }
  return n;
}

/** Starts or stops playing at the data's frame rate. */
function togglePlay() {
  const button = document.getElementById("play");
  if (timer) {
    clearInterval(timer);
    timer = null;
    button.textContent = "play";
    return;
  }
  button.textContent = "pause";
  timer = setInterval(() => {
    position = (position + 1) % data.groups[group].frames.length;
    draw();
  }, 1000 / data.fps);
}

function start() {
  document.getElementById("title").textContent = data.title;
  const select = document.getElementById("group");
  data.groups.forEach((g, i) => select.add(new Option(g.name, i)));
  select.hidden = data.groups.length < 2;
  select.onchange = () => { group = +select.value; position = 0; draw(); };
  document.getElementById("scrub").oninput = (e) => { position = +e.target.value; draw(); };
  document.getElementById("play").onclick = togglePlay;
  // One frame only: no timeline.
  document.getElementById("timeline").hidden = data.frames.length < 2;
  for (const id of ["skeleton", "sphere"]) {
    const canvas = document.getElementById(id);
    let last = null;
    canvas.onmousedown = (e) => { last = [e.clientX, e.clientY]; };
    window.addEventListener("mouseup", () => { last = null; });
    canvas.onmousemove = (e) => {
      if (!last) return;
      view.azimuth -= 0.5 * (e.clientX - last[0]);
      view.elevation = Math.max(-89, Math.min(89, view.elevation + 0.5 * (e.clientY - last[1])));
      last = [e.clientX, e.clientY];
      draw();
    };
    canvas.onwheel = (e) => {
      e.preventDefault();
      view.zoom = Math.max(0.2, Math.min(8, view.zoom * Math.exp(-0.001 * e.deltaY)));
      draw();
    };
  }
  draw();
  document.body.dataset.skeletonPixels = skeletonPixels();
  if (document.body.dataset.status !== "error") document.body.dataset.status = "ready";
}

start();
