// foldsim's viewer: plays a run's glTF animation (embedded as base64 in the page) with a time
// slider, play/pause and speed, an orbiting camera, panels coloured by body or by the fold
// angle of the hinge that places them, and a plot of output columns whose cursor follows the
// animation's time. Everything it needs is in the page: it works offline, from a file.
// Data: window.FOLDSIM_DATA = { title, glb (base64), times [s], plot: { names, units,
// values: [[per row]] , t: [s] }, fold: { bodies: [names], values: [[deg per frame]] },
// moment: { bodies, values: [[N·m per frame]] } (empty unless the CSV has `_M_z` columns) }.
(function () {
  const { THREE, GLTFLoader, OrbitControls } = window.FOLDSIM_THREE;
  const data = window.FOLDSIM_DATA;
  const view = (window.foldsimView = { ready: false, error: null });
  const $ = (id) => document.getElementById(id);
  document.title = data.title + " — foldsim";
  $("title").textContent = data.title;

  // Renderer, scene, camera, light. Without WebGL (switched off, or a machine without it)
  // the page says so where the structure would be, and the plot still works.
  const holder = $("scene");
  let renderer = null;
  try {
    const probe = document.createElement("canvas");
    if (!(probe.getContext("webgl2") || probe.getContext("webgl"))) throw new Error("no WebGL context");
    renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    renderer = null;
    view.error = "WebGL is not available: " + (e && e.message ? e.message : e);
    const note = document.createElement("div");
    note.id = "nowebgl";
    note.style.cssText = "padding: 2em; font-size: 15px; line-height: 1.5; color: #495057";
    note.innerHTML = "<strong>The structure cannot be drawn: this browser has no WebGL</strong> (it is switched off, " +
      "or the graphics driver does not offer it). Turn on hardware acceleration or WebGL in the browser's settings, " +
      "or open the page in another browser; the animation file (<code>foldsim animate</code>) opens in any glTF viewer. " +
      "The plot beside works without it.";
    holder.appendChild(note);
  }
  if (renderer) {
    renderer.setPixelRatio(1);
    holder.appendChild(renderer.domElement);
  }
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f5f7);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x556070, 2.2));
  const sun = new THREE.DirectionalLight(0xffffff, 1.6);
  sun.position.set(3, 10, 6);
  scene.add(sun);
  const camera = new THREE.PerspectiveCamera(40, 1, 0.01, 1e5);
  const controls = renderer ? new OrbitControls(camera, renderer.domElement) : null;
  // The camera follows the structure (framed on it at every time, so the stowed state fills
  // the view at t = 0 and the deployed one at the end) until the user moves it.
  let follow = true;
  if (controls) controls.addEventListener("start", () => { follow = false; });

  function resize() {
    const w = holder.clientWidth, h = holder.clientHeight;
    if (renderer) renderer.setSize(w, h, false);
    camera.aspect = w / Math.max(h, 1);
    camera.updateProjectionMatrix();
  }
  window.addEventListener("resize", resize);

  const bytes = Uint8Array.from(atob(data.glb), (c) => c.charCodeAt(0));
  let mixer = null, duration = data.times.length ? data.times[data.times.length - 1] : 0, time = 0, playing = true, speed = 1;
  let root = null;
  const bodies = {}; // name -> mesh material
  // Frames the camera on the structure as it stands (its bounding box at this time).
  function frame() {
    if (!root) return;
    root.updateMatrixWorld(true);
    const box = new THREE.Box3().expandByObject(root);
    const size = box.getSize(new THREE.Vector3()).length() || 1;
    const center = box.getCenter(new THREE.Vector3());
    controls.target.copy(center);
    camera.position.copy(center).add(new THREE.Vector3(0.9, 0.7, 1.1).multiplyScalar(size * 0.9));
    camera.near = size / 1000;
    camera.far = size * 100;
    camera.updateProjectionMatrix();
  }
  if (!renderer) {
    // The plot alone.
    view.duration = duration;
    $("slider").max = String(duration);
    $("slider").step = String(duration / 2000 || 0.001);
    setTimeout(() => { setTime(startTime()); if (startTime() > 0) playing = false; view.ready = true; }, 0);
  } else new GLTFLoader().parse(bytes.buffer, "", (gltf) => {
    scene.add(gltf.scene);
    gltf.scene.traverse((o) => {
      if (o.isMesh && o.material && o.parent && o.name && !o.name.endsWith(" axis") && !o.name.endsWith(" in contact")) {
        bodies[o.name] = o.material;
        o.material.userData.base = o.material.color.clone();
      }
    });
    const clip = gltf.animations[0];
    mixer = new THREE.AnimationMixer(gltf.scene);
    mixer.clipAction(clip).play();
    duration = clip.duration;
    $("slider").max = String(duration);
    $("slider").step = String(duration / 2000);
    root = gltf.scene;
    mixer.setTime(0);
    frame();
    resize();
    setTime(startTime());
    if (startTime() > 0) { playing = false; $("play").textContent = "play"; }
    view.ready = true;
    view.duration = duration;
  }, (err) => {
    view.error = String(err);
    console.error("cannot read the animation:", err);
  });

  // Colours: by body (the file's), or by fold angle (0° blue … 180° red).
  // The largest |moment| over the run, for the moment colour scale.
  let momentScale = 0;
  for (const v of data.moment.values) for (const x of v) if (Number.isFinite(x)) momentScale = Math.max(momentScale, Math.abs(x));
  function colour() {
    const mode = $("colour").value;
    const series = mode === "moment" ? data.moment : data.fold;
    const full = mode === "moment" ? momentScale || 1 : 180;
    const frame = frameAt(time);
    for (const [name, material] of Object.entries(bodies)) {
      const k = series.bodies.indexOf(name);
      if (mode !== "body" && k >= 0) {
        const a = Math.min(Math.abs(series.values[k][frame]) / full, 1);
        material.color.setHSL((1 - a) * 0.66, 0.75, 0.5);
      } else if (mode !== "body") {
        material.color.set(0x8a8f99);
      } else {
        material.color.copy(material.userData.base);
      }
    }
    $("scale").textContent = mode === "fold" ? "blue 0° … red 180°" : mode === "moment" ? "blue 0 … red " + full.toPrecision(3) + " N·m" : "";
  }
  function frameAt(t) {
    const ts = data.times;
    let lo = 0, hi = ts.length - 1;
    while (hi - lo > 1) {
      const mid = (lo + hi) >> 1;
      if (ts[mid] <= t) lo = mid; else hi = mid;
    }
    return t - ts[lo] < ts[hi] - t ? lo : hi;
  }

  // The time to show first, from the page's address: `page.html#t=1.7` opens paused at
  // t = 1.7 s (a time to send a colleague); otherwise the run plays from 0.
  function startTime() {
    const m = /(?:^#|&)t=([0-9.eE+-]+)/.exec(window.location.hash || "");
    const t = m ? Number(m[1]) : 0;
    return Number.isFinite(t) && t > 0 ? t : 0;
  }

  function setTime(t) {
    time = Math.min(Math.max(t, 0), duration);
    // A repeating clip set to its full duration wraps to its start: stop just short of it.
    if (mixer) mixer.setTime(Math.min(time, duration * (1 - 1e-7)));
    if (follow) frame();
    $("slider").value = String(time);
    $("clock").textContent = "t = " + time.toFixed(3) + " s";
    colour();
    drawPlot();
  }
  view.now = () => time;
  view.setTime = (t) => { playing = false; $("play").textContent = "play"; setTime(t); if (renderer) renderer.render(scene, camera); };

  // Plot of the chosen columns, each in a band of its own with its own axis (ticks at round
  // numbers, the column's name and unit), over a shared time axis; a cursor at the
  // animation's time.
  const plot = $("plot");
  const palette = ["#d6336c", "#1c7ed6", "#37b24d", "#f59f00", "#7048e8", "#0ca678", "#e8590c", "#495057"];
  // Round tick values covering [lo, hi]: steps of 1, 2 or 5 times a power of ten.
  function ticks(lo, hi, count) {
    const raw = (hi - lo) / Math.max(count, 1);
    const p = Math.pow(10, Math.floor(Math.log10(raw)));
    const step = [1, 2, 5, 10].map((m) => m * p).find((s) => s >= raw) || raw;
    const out = [];
    for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) out.push(Math.abs(v) < step * 1e-9 ? 0 : v);
    return out;
  }
  const label = (v) => (Math.abs(v) >= 1e4 || (Math.abs(v) < 1e-3 && v !== 0) ? v.toExponential(1) : String(Number(v.toPrecision(4))));
  function drawPlot() {
    const p = data.plot;
    const ctx = plot.getContext("2d");
    const w = (plot.width = plot.clientWidth), h = (plot.height = plot.clientHeight);
    ctx.clearRect(0, 0, w, h);
    view.plotAxes = [];
    if (!p.names.length) return;
    const left = 62, right = 10, top = 8, bottom = 30, gap = 10;
    const n = p.names.length;
    const band = (h - top - bottom - gap * (n - 1)) / n;
    const t0 = p.t[0], t1 = p.t[p.t.length - 1] || 1;
    const X = (t) => left + ((t - t0) / (t1 - t0 || 1)) * (w - left - right);
    ctx.font = "11px sans-serif";
    p.values.forEach((v, i) => {
      const y0 = top + i * (band + gap);
      let lo = Infinity, hi = -Infinity;
      for (const x of v) if (Number.isFinite(x)) { lo = Math.min(lo, x); hi = Math.max(hi, x); }
      if (!Number.isFinite(lo)) { lo = -1; hi = 1; }
      if (!(hi > lo)) { const d = Math.abs(lo) * 0.1 || 1; hi = lo + d; lo -= d; }
      const Y = (x) => y0 + (1 - (x - lo) / (hi - lo)) * band;
      const colour = palette[i % palette.length];
      ctx.strokeStyle = "#adb5bd"; ctx.strokeRect(left, y0, w - left - right, band);
      const marks = ticks(lo, hi, Math.max(2, Math.floor(band / 28)));
      ctx.fillStyle = "#343a40"; ctx.textAlign = "right";
      for (const m of marks) {
        ctx.strokeStyle = "#e9ecef"; ctx.beginPath(); ctx.moveTo(left, Y(m)); ctx.lineTo(w - right, Y(m)); ctx.stroke();
        ctx.strokeStyle = "#495057"; ctx.beginPath(); ctx.moveTo(left - 4, Y(m)); ctx.lineTo(left, Y(m)); ctx.stroke();
        ctx.fillText(label(m), left - 6, Y(m) + 4);
      }
      ctx.textAlign = "left";
      ctx.strokeStyle = colour; ctx.beginPath();
      let pen = false;
      v.forEach((x, k) => {
        if (!Number.isFinite(x)) { pen = false; return; }
        if (pen) ctx.lineTo(X(p.t[k]), Y(x)); else ctx.moveTo(X(p.t[k]), Y(x));
        pen = true;
      });
      ctx.stroke();
      ctx.fillStyle = colour;
      const name = p.names[i] + (p.units[i] ? " (" + p.units[i] + ")" : "");
      ctx.fillText(name, left + 6, y0 + 13);
      view.plotAxes.push({ name: p.names[i], unit: p.units[i], ticks: marks });
    });
    // The shared time axis.
    ctx.fillStyle = "#343a40"; ctx.strokeStyle = "#495057"; ctx.textAlign = "center";
    for (const m of ticks(t0, t1, Math.max(2, Math.floor((w - left - right) / 70)))) {
      ctx.beginPath(); ctx.moveTo(X(m), h - bottom); ctx.lineTo(X(m), h - bottom + 4); ctx.stroke();
      ctx.fillText(label(m), X(m), h - bottom + 15);
    }
    ctx.fillText("t (s)", left + (w - left - right) / 2, h - 3);
    ctx.textAlign = "left";
    ctx.strokeStyle = "#000"; ctx.beginPath(); ctx.moveTo(X(time), top); ctx.lineTo(X(time), h - bottom); ctx.stroke();
  }

  // Controls.
  $("play").addEventListener("click", () => { playing = !playing; $("play").textContent = playing ? "pause" : "play"; });
  $("speed").addEventListener("change", () => { speed = Number($("speed").value); });
  $("slider").addEventListener("input", () => { playing = false; $("play").textContent = "play"; setTime(Number($("slider").value)); });
  $("colour").addEventListener("change", colour);
  if (!data.fold.bodies.length) $("colour").querySelector("[value=fold]").disabled = true;
  if (!data.moment.bodies.length) $("colour").querySelector("[value=moment]").disabled = true;

  // A small, coarse luminance image of the canvas (for tests): 64 × 48 values in 0…255.
  view.pixels = () => {
    if (!renderer) return [];
    renderer.render(scene, camera);
    const c = document.createElement("canvas");
    c.width = 64; c.height = 48;
    const g = c.getContext("2d");
    g.drawImage(renderer.domElement, 0, 0, 64, 48);
    const d = g.getImageData(0, 0, 64, 48).data;
    const out = [];
    for (let i = 0; i < d.length; i += 4) out.push(Math.round(0.299 * d[i] + 0.587 * d[i + 1] + 0.114 * d[i + 2]));
    return out;
  };

  let before = performance.now();
  function step() {
    const now = performance.now();
    const dt = (now - before) / 1000;
    before = now;
    if ((mixer || !renderer) && playing && duration > 0) {
      let t = time + dt * speed;
      if (t > duration) t = 0;
      setTime(t);
    }
    if (renderer) {
      controls.update();
      renderer.render(scene, camera);
    } else {
      requestAnimationFrame(step);
    }
  }
  // With WebGL the renderer drives the loop; without it the plot's cursor still plays.
  if (renderer) renderer.setAnimationLoop(step); else requestAnimationFrame(step);
})();
