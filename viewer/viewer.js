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

  // Renderer, scene, camera, light.
  const holder = $("scene");
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  holder.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f5f7);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x556070, 2.2));
  const sun = new THREE.DirectionalLight(0xffffff, 1.6);
  sun.position.set(3, 10, 6);
  scene.add(sun);
  const camera = new THREE.PerspectiveCamera(40, 1, 0.01, 1e5);
  const controls = new OrbitControls(camera, renderer.domElement);

  function resize() {
    const w = holder.clientWidth, h = holder.clientHeight;
    renderer.setSize(w, h, false);
    camera.aspect = w / Math.max(h, 1);
    camera.updateProjectionMatrix();
  }
  window.addEventListener("resize", resize);

  const bytes = Uint8Array.from(atob(data.glb), (c) => c.charCodeAt(0));
  let mixer = null, duration = 0, time = 0, playing = true, speed = 1;
  const bodies = {}; // name -> mesh material
  new GLTFLoader().parse(bytes.buffer, "", (gltf) => {
    scene.add(gltf.scene);
    gltf.scene.traverse((o) => {
      if (o.isMesh && o.material && o.parent && o.name && !o.name.endsWith(" axis")) {
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
    // Frame the camera on the structure over the whole run (start and end).
    const box = new THREE.Box3();
    for (const t of [0, duration / 2, duration]) {
      mixer.setTime(Math.min(t, duration * (1 - 1e-7)));
      gltf.scene.updateMatrixWorld(true);
      box.expandByObject(gltf.scene);
    }
    mixer.setTime(0);
    const size = box.getSize(new THREE.Vector3()).length() || 1;
    const center = box.getCenter(new THREE.Vector3());
    controls.target.copy(center);
    camera.position.copy(center).add(new THREE.Vector3(0.9, 0.7, 1.1).multiplyScalar(size * 0.9));
    camera.near = size / 1000;
    camera.far = size * 100;
    resize();
    setTime(0);
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

  function setTime(t) {
    time = Math.min(Math.max(t, 0), duration);
    // A repeating clip set to its full duration wraps to its start: stop just short of it.
    if (mixer) mixer.setTime(Math.min(time, duration * (1 - 1e-7)));
    $("slider").value = String(time);
    $("clock").textContent = "t = " + time.toFixed(3) + " s";
    colour();
    drawPlot();
  }
  view.setTime = (t) => { playing = false; $("play").textContent = "play"; setTime(t); renderer.render(scene, camera); };

  // Plot of the chosen columns, with a cursor at the animation's time.
  const plot = $("plot");
  const palette = ["#d6336c", "#1c7ed6", "#37b24d", "#f59f00", "#7048e8", "#0ca678", "#e8590c", "#495057"];
  function drawPlot() {
    const p = data.plot;
    const ctx = plot.getContext("2d");
    const w = (plot.width = plot.clientWidth), h = (plot.height = plot.clientHeight);
    ctx.clearRect(0, 0, w, h);
    if (!p.names.length) return;
    const left = 56, right = 10, top = 10, bottom = 26;
    let lo = Infinity, hi = -Infinity;
    for (const v of p.values) for (const x of v) if (Number.isFinite(x)) { lo = Math.min(lo, x); hi = Math.max(hi, x); }
    if (!(hi > lo)) { hi = lo + 1; lo -= 1; }
    const t0 = p.t[0], t1 = p.t[p.t.length - 1] || 1;
    const X = (t) => left + ((t - t0) / (t1 - t0 || 1)) * (w - left - right);
    const Y = (v) => top + (1 - (v - lo) / (hi - lo)) * (h - top - bottom);
    ctx.strokeStyle = "#adb5bd"; ctx.strokeRect(left, top, w - left - right, h - top - bottom);
    ctx.fillStyle = "#343a40"; ctx.font = "11px sans-serif";
    ctx.fillText(hi.toPrecision(4), 4, top + 10); ctx.fillText(lo.toPrecision(4), 4, h - bottom);
    ctx.fillText(t0.toFixed(2) + " s", left, h - 8); ctx.fillText(t1.toFixed(2) + " s", w - right - 50, h - 8);
    p.values.forEach((v, i) => {
      ctx.strokeStyle = palette[i % palette.length]; ctx.beginPath();
      let pen = false;
      v.forEach((x, k) => {
        if (!Number.isFinite(x)) { pen = false; return; }
        if (pen) ctx.lineTo(X(p.t[k]), Y(x)); else ctx.moveTo(X(p.t[k]), Y(x));
        pen = true;
      });
      ctx.stroke();
      ctx.fillStyle = palette[i % palette.length];
      ctx.fillText(p.names[i] + (p.units[i] ? " (" + p.units[i] + ")" : ""), left + 8, top + 14 + 13 * i);
    });
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
  renderer.setAnimationLoop(() => {
    const now = performance.now();
    const dt = (now - before) / 1000;
    before = now;
    if (mixer && playing) {
      let t = time + dt * speed;
      if (t > duration) t = 0;
      setTime(t);
    }
    controls.update();
    renderer.render(scene, camera);
  });
})();
