"""Interactive 3-D viewer: one self-contained HTML file that opens offline.

:func:`write_viewer` writes a page with three.js (vendored in
``hardspheres/_static``, MIT) and the run's frames embedded in it, so the file
can be mailed or opened from disk with no server and no network::

    from hardspheres.viewer import write_viewer
    write_viewer(frames, "run.html", title="2000 spheres, phi = 0.3")

In the page: drag to orbit, wheel to zoom, right-drag to pan; space plays or
pauses, the arrow keys step frames; click a sphere to see its name, mass,
radius and speed.  Spheres are drawn at their true radii in perspective,
coloured by speed or by mass (with a legend); collisions flash red and
reflections off the container flash white as they happen.

Positions go in as little-endian Float32 arrays in base64; frames are
subsampled evenly to at most ``max_frames`` (and fewer when the spheres are
so many that positions and speeds would pass ``max_values`` numbers).
In a periodic box each sphere is drawn once, at its centre wrapped into the
box.  The page sets
``window.viewerReady = true`` once it has drawn the first frame and keeps
``window.viewerState = {frame, time, playing}`` current, for tests.

:func:`screenshot` opens such a page in headless Chromium (Debian's
``chromium`` driven by the Python ``playwright`` package) and saves a PNG.
"""

import base64
import html
import json
from importlib import resources
from pathlib import Path

import numpy as np

_STATIC = ("three.core.min.js", "three.module.min.js", "OrbitControls.js")
_CORE_SPECIFIER = '"./three.core.min.js"'


def _b64(array, dtype):
    """Base64 of ``array`` as contiguous little-endian ``dtype``."""
    return base64.b64encode(np.ascontiguousarray(array, dtype=np.dtype(dtype).newbyteorder("<")).tobytes()).decode("ascii")


def _script_json(obj):
    """JSON safe inside a ``<script>`` element (no ``<`` at all)."""
    return json.dumps(obj, separators=(",", ":"), allow_nan=False).replace("<", "\\u003c")


def _vendored_js():
    """The three vendored scripts, keyed ``core``, ``module``, ``orbit``."""
    folder = resources.files("hardspheres") / "_static"
    core, module, orbit = (folder.joinpath(name).read_text(encoding="utf-8") for name in _STATIC)
    if _CORE_SPECIFIER not in module or "from 'three'" not in orbit:
        raise RuntimeError("hardspheres/_static: the vendored three.js files' import specifiers changed")
    return {"core": core, "module": module, "orbit": orbit}


def frame_indices(n_frames, n_spheres, max_frames=600, max_values=12_000_000):
    """Indices of the frames the viewer keeps: evenly spaced, first and last kept.

    At most ``max_frames`` frames, and at most ``max_values`` embedded numbers
    (``frames * spheres * 4``: a position and a speed, 4 bytes each), but never
    fewer than two frames when there are two.

    >>> frame_indices(5, 10).tolist()
    [0, 1, 2, 3, 4]
    >>> frame_indices(1001, 10, max_frames=3).tolist()
    [0, 500, 1000]
    """
    if n_frames <= 0:
        return np.zeros(0, np.int64)
    cap = min(int(max_frames), int(max_values) // max(1, 4 * n_spheres))
    cap = max(cap, min(2, n_frames))
    if n_frames <= cap:
        return np.arange(n_frames)
    return np.unique(np.round(np.linspace(0, n_frames - 1, cap)).astype(np.int64))


def _payload(frames, title, max_frames, max_values, max_events, color_by):
    times = np.asarray(frames.times, dtype=np.float64)
    pos = np.asarray(frames.positions, dtype=np.float64)
    vel = np.asarray(frames.velocities, dtype=np.float64)
    radii = np.asarray(frames.radii, dtype=np.float64).reshape(-1)
    masses = np.asarray(frames.masses, dtype=np.float64).reshape(-1)
    n_frames, n = len(times), len(radii)
    if n_frames == 0:
        raise ValueError("write_viewer: no frames")
    if pos.shape != (n_frames, n, 3) or vel.shape != (n_frames, n, 3) or masses.shape != (n,):
        raise ValueError(f"write_viewer: inconsistent shapes: times {times.shape}, positions {pos.shape}, "
                         f"velocities {vel.shape}, radii {radii.shape}, masses {masses.shape}")
    if color_by not in ("speed", "mass"):
        raise ValueError("write_viewer: color_by must be 'speed' or 'mass'")

    keep = frame_indices(n_frames, n, max_frames, max_values)
    t = times[keep]
    p = pos[keep]
    box = None if frames.box is None else float(frames.box)
    container = None if frames.container is None else float(frames.container)
    if box:
        p = p - box * np.floor(p / box + 0.5)  # into [-L/2, L/2)
    speeds = np.sqrt(np.einsum("fnk,fnk->fn", vel[keep], vel[keep]))

    if container:
        extent = container
    elif box:
        extent = 0.5 * box * np.sqrt(3.0)
    else:
        extent = float(np.max(np.abs(p)) + (radii.max() if n else 0.0)) if p.size else 1.0
    extent = extent if np.isfinite(extent) and extent > 0 else 1.0

    et = np.asarray(frames.event_times, dtype=np.float64).reshape(-1)
    ek = np.asarray(frames.event_kinds).reshape(-1).astype(np.uint8)
    ei = np.asarray(frames.event_i).reshape(-1).astype(np.int32)
    ej = np.asarray(frames.event_j).reshape(-1).astype(np.int32)
    m = min(len(et), len(ek), len(ei), len(ej))
    et, ek, ei, ej = et[:m], ek[:m], ei[:m], ej[:m]
    sel = (et >= t[0]) & (et <= t[-1]) & (ei >= 0) & (ei < n) & (ej < n)
    et, ek, ei, ej = et[sel], ek[sel], ei[sel], ej[sel]
    order = np.argsort(et, kind="stable")
    et, ek, ei, ej = et[order], ek[order], ei[order], ej[order]
    events_total = int(len(et))
    counts = {"collisions": int(np.sum(ek == 1)), "reflections": int(np.sum(ek == 0))}
    if len(et) > max_events:
        pick = np.unique(np.round(np.linspace(0, len(et) - 1, max_events)).astype(np.int64))
        et, ek, ei, ej = et[pick], ek[pick], ei[pick], ej[pick]

    finite_speeds = speeds[np.isfinite(speeds)]
    speed_max = float(np.percentile(finite_speeds, 99.5)) if finite_speeds.size else 1.0
    if not speed_max > 0:
        speed_max = float(finite_speeds.max()) if finite_speeds.size and finite_speeds.max() > 0 else 1.0

    names = [str(x) for x in frames.names] if (frames.names is not None and len(frames.names) == n and n <= 20000) else None
    return {
        "title": title or f"{n} hard spheres",
        "n": n,
        "nframes": int(len(keep)),
        "nframes_total": int(n_frames),
        "container": container,
        "box": box,
        "extent": float(extent),
        "times": t.tolist(),
        "positions": _b64(p, np.float32),
        "speeds": _b64(speeds, np.float32),
        "radii": _b64(radii, np.float32),
        "masses": _b64(masses, np.float32),
        "names": names,
        "speed_range": [0.0, speed_max],
        "mass_range": [float(masses.min()), float(masses.max())] if n else [1.0, 1.0],
        "color_by": color_by,
        "events": {
            "n": int(len(et)),
            "total": events_total,
            "counts": counts,
            "times": _b64(et, np.float64),
            "kinds": _b64(ek, np.uint8),
            "i": _b64(ei, np.int32),
            "j": _b64(ej, np.int32),
        },
    }


def write_viewer(frames, path, title=None, max_frames=600, *, color_by="speed",
                 max_values=12_000_000, max_events=200_000):
    """Write an interactive, self-contained HTML viewer of ``frames``.

    Args:
        frames: a :class:`hardspheres.frames.Frames`.
        path: the ``.html`` file to write.
        title: shown in the page's corner and tab (default ``"N hard spheres"``).
        max_frames: at most this many frames are embedded, evenly spaced
            (first and last kept).
        color_by: initial colouring, ``"speed"`` or ``"mass"`` (switchable
            in the page).
        max_values: at most this many numbers (frames x spheres x 4: a
            position and a speed) are embedded, about 4/3 bytes each in the
            file; fewer frames are kept for large N (the default keeps the
            file under about 70 MB).
        max_events: at most this many events are embedded for the flashes
            (evenly spaced in the run's event list when there are more).

    Returns:
        ``path`` as a :class:`pathlib.Path`.
    """
    path = Path(path)
    data = _payload(frames, title, max_frames, max_values, max_events, color_by)
    page = (_TEMPLATE
            .replace("__TITLE__", html.escape(data["title"]))
            .replace("__JS__", _script_json(_vendored_js()))
            .replace("__DATA__", _script_json(data)))
    from .fileio import atomic_write
    with atomic_write(path, "w", encoding="utf-8") as fh:
        fh.write(page)
    return path


# Headless Chromium as Debian ships it (software WebGL through SwiftShader);
# playwright drives it, its own browser downloads are never used.
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 "--use-gl=angle", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"]


def find_chromium():
    """Path of a Chromium executable (``/usr/bin/chromium`` or on PATH), or ``None``."""
    import os
    import shutil
    if os.access("/usr/bin/chromium", os.X_OK):
        return "/usr/bin/chromium"
    return shutil.which("chromium") or shutil.which("chromium-browser")


def screenshot(html_path, png_path, size=(960, 640), play_seconds=1.0, timeout=60.0):
    """Open a viewer page in headless Chromium, play it a while, save a PNG of the page.

    Args:
        html_path: a page written by :func:`write_viewer`.
        png_path: the ``.png`` to write, ``size`` pixels.
        size: ``(width, height)`` of the browser window [pixels].
        play_seconds: how long the animation plays before the picture
            (0: the first frame).
        timeout: give up when the page has not drawn after this many seconds.

    Returns:
        ``png_path`` as a :class:`pathlib.Path`.

    Raises:
        ValueError: Chromium or the Python ``playwright`` package is
            missing, or the page did not start (the message says which).
    """
    html_path, png_path = Path(html_path).resolve(), Path(png_path)
    width, height = (int(x) for x in size)
    if width <= 0 or height <= 0:
        raise ValueError(f"screenshot: bad size {size}")
    chromium = find_chromium()
    if chromium is None:
        raise ValueError("screenshot: needs Chromium, which was not found (/usr/bin/chromium "
                         "or chromium on PATH; e.g. apt-get install chromium)")
    try:
        from playwright.sync_api import Error as PlaywrightError
        from playwright.sync_api import sync_playwright
    except ImportError:
        raise ValueError("screenshot: needs the Python package playwright "
                         "(pip install playwright; its browser download is not needed)") from None
    errors = []
    try:
        with sync_playwright() as pw:
            browser = pw.chromium.launch(executable_path=chromium, args=CHROMIUM_ARGS, headless=True)
            try:
                page = browser.new_page(viewport={"width": width, "height": height})
                page.on("pageerror", lambda exc: errors.append(str(exc)))
                page.goto(html_path.as_uri())
                page.wait_for_function("window.viewerReady === true || "
                                       "getComputedStyle(document.getElementById('message'))"
                                       ".display !== 'none'", timeout=timeout * 1000)
                if page.locator("#message").is_visible():
                    raise ValueError(f"screenshot: {page.locator('#message').inner_text()}")
                if play_seconds > 0 and page.evaluate("window.viewerState.playing") is False:
                    page.click("#play")
                    page.wait_for_timeout(play_seconds * 1000)
                    if page.evaluate("window.viewerState.playing"):
                        page.click("#play")  # pause: the picture shows the Play button
                page.wait_for_timeout(100)
                from .fileio import atomic_path
                with atomic_path(png_path) as tmp:
                    page.screenshot(path=tmp, type="png")
            finally:
                browser.close()
    except PlaywrightError as e:
        first = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
        more = f" (page errors: {'; '.join(errors)})" if errors else ""
        raise ValueError(f"screenshot: Chromium failed: {first}{more}") from None
    return png_path


_TEMPLATE = r"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<link rel="icon" href="data:,">
<title>__TITLE__</title>
<style>
  html, body { margin: 0; height: 100%; overflow: hidden; background: #0f1217; color: #dde3ea;
    font: 13px/1.35 system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; }
  #view { position: absolute; left: 0; top: 0; right: 0; bottom: 52px; }
  #view canvas { display: block; width: 100%; height: 100%; outline: none; }
  #bar { position: absolute; left: 0; right: 0; bottom: 0; height: 52px; display: flex; align-items: center;
    gap: 12px; padding: 0 12px; box-sizing: border-box; background: #181c23; border-top: 1px solid #2a303a; }
  #bar button { background: #2a3340; color: #e8edf3; border: 1px solid #3b4656; border-radius: 4px;
    padding: 5px 12px; font: inherit; cursor: pointer; min-width: 64px; }
  #bar button:hover { background: #344050; }
  #slider { flex: 1; min-width: 80px; }
  #time { font-variant-numeric: tabular-nums; min-width: 150px; white-space: nowrap; }
  #bar label { white-space: nowrap; }
  #bar select { background: #2a3340; color: #e8edf3; border: 1px solid #3b4656; border-radius: 4px; font: inherit; }
  .panel { position: absolute; background: rgba(20, 24, 31, 0.78); border: 1px solid #2a303a; border-radius: 6px;
    padding: 8px 10px; pointer-events: none; }
  #info { left: 10px; top: 10px; max-width: 360px; }
  #info h1 { font-size: 14px; margin: 0 0 4px 0; font-weight: 600; }
  #info .dim { color: #98a3b3; }
  #legend { right: 10px; top: 10px; min-width: 120px; }
  #legend .title { font-weight: 600; margin-bottom: 6px; }
  #legend .scale { display: flex; gap: 8px; align-items: stretch; }
  #legend canvas { width: 16px; height: 150px; border: 1px solid #3b4656; }
  #legend .ticks { display: flex; flex-direction: column; justify-content: space-between; font-variant-numeric: tabular-nums; }
  #legend .swatch { display: inline-block; width: 11px; height: 11px; border-radius: 50%; margin-right: 5px; vertical-align: -1px; }
  #legend .flash { margin-top: 8px; }
  #message { position: absolute; left: 50%; top: 40%; transform: translate(-50%, -50%); max-width: 70%;
    background: #3a1d22; border: 1px solid #7a2d38; border-radius: 6px; padding: 12px 16px; display: none; }
</style>
</head>
<body>
<div id="view"></div>
<div id="info" class="panel"><h1 id="title"></h1><div id="facts" class="dim"></div><div id="counts"></div><div id="picked"></div></div>
<div id="legend" class="panel"></div>
<div id="bar">
  <button id="play" type="button" title="play / pause (space)">&#9654; Play</button>
  <input id="slider" type="range" min="0" max="0" step="1" value="0" aria-label="frame">
  <span id="time">t = 0</span>
  <label>speed <input id="speed" type="range" min="-2" max="2" step="0.05" value="0" style="width:90px" aria-label="playback speed"> <span id="speedval">&times;1</span></label>
  <label>colour <select id="colorby"><option value="speed">speed</option><option value="mass">mass</option></select></label>
  <label title="interpolate positions between stored frames"><input id="smooth" type="checkbox" checked> smooth</label>
  <label><input id="loop" type="checkbox" checked> loop</label>
  <button id="reset" type="button" title="reset the camera">view</button>
</div>
<div id="message"></div>
<script id="hs-js" type="application/json">__JS__</script>
<script id="hs-data" type="application/json">__DATA__</script>
<script type="module">
window.viewerReady = false;
window.viewerState = { frame: 0, time: 0, playing: false };
const $ = (id) => document.getElementById(id);
function fail(err) {
  const box = $('message');
  box.style.display = 'block';
  box.textContent = 'The viewer could not start: ' + (err && err.message ? err.message : err);
  console.error(err);
}
function decode(b64, Type) {
  const bin = atob(b64);
  const bytes = new Uint8Array(bin.length);
  for (let k = 0; k < bin.length; k++) bytes[k] = bin.charCodeAt(k);
  return new Type(bytes.buffer);
}
function fmt(x) {
  if (!isFinite(x)) return String(x);
  const a = Math.abs(x);
  if (a === 0) return '0';
  if (a >= 1e5 || a < 1e-3) return x.toExponential(3);
  return x.toPrecision(5);
}
function num(x) {                  // fmt without trailing zeros
  return fmt(x).replace(/(\.\d*?)0+(e|$)/, '$1$2').replace(/\.(e|$)/, '$1');
}
function upper(arr, x) {            // first index with arr[k] > x
  let lo = 0, hi = arr.length;
  while (lo < hi) { const mid = (lo + hi) >> 1; if (arr[mid] > x) hi = mid; else lo = mid + 1; }
  return lo;
}

async function loadThree() {
  const S = JSON.parse($('hs-js').textContent);
  const url = (src) => URL.createObjectURL(new Blob([src], { type: 'text/javascript' }));
  const coreURL = url(S.core);
  const threeURL = url(S.module.split('"./three.core.min.js"').join(JSON.stringify(coreURL)));
  const orbitURL = url(S.orbit.replace(/from\s*'three'/g, 'from ' + JSON.stringify(threeURL)));
  const THREE = await import(threeURL);
  const { OrbitControls } = await import(orbitURL);
  return { THREE, OrbitControls };
}

// viridis, sRGB
const VIRIDIS = ['#440154', '#472d7b', '#3b528b', '#2c728e', '#21918c', '#28ae80', '#5ec962', '#addc30', '#fde725'];
function hexRGB(h) { const v = parseInt(h.slice(1), 16); return [(v >> 16) / 255, ((v >> 8) & 255) / 255, (v & 255) / 255]; }
function cmapSRGB(x) {
  x = Math.min(1, Math.max(0, x)) * (VIRIDIS.length - 1);
  const k = Math.min(VIRIDIS.length - 2, Math.floor(x)), f = x - k;
  const a = hexRGB(VIRIDIS[k]), b = hexRGB(VIRIDIS[k + 1]);
  return [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])];
}
const toLinear = (c) => (c <= 0.04045 ? c / 12.92 : Math.pow((c + 0.055) / 1.055, 2.4));
const LUT = new Float32Array(256 * 3);
for (let k = 0; k < 256; k++) { const c = cmapSRGB(k / 255); for (let q = 0; q < 3; q++) LUT[3 * k + q] = toLinear(c[q]); }
const FLASH = { 1: { css: '#ff3b30', lin: hexRGB('#ff3b30').map(toLinear), label: 'collision' },
                0: { css: '#ffffff', lin: [1, 1, 1], label: 'reflection' } };
const FLASH_SECONDS = 0.35;

async function main() {
  const D = JSON.parse($('hs-data').textContent);
  const { THREE, OrbitControls } = await loadThree();

  const N = D.n, F = D.nframes, times = D.times;
  const P = decode(D.positions, Float32Array), SPEED = decode(D.speeds, Float32Array);
  const R = decode(D.radii, Float32Array), M = decode(D.masses, Float32Array);
  const EV = D.events;
  const evT = decode(EV.times, Float64Array), evK = decode(EV.kinds, Uint8Array);
  const evI = decode(EV.i, Int32Array), evJ = decode(EV.j, Int32Array);
  const cumColl = new Int32Array(evT.length + 1);
  for (let k = 0; k < evT.length; k++) cumColl[k + 1] = cumColl[k] + (evK[k] === 1 ? 1 : 0);
  const L = D.box, t0 = times[0], t1 = times[F - 1], span = t1 - t0;

  // ---- page text
  document.title = D.title;
  $('title').textContent = D.title;
  const where = D.container ? `spherical container, radius ${num(D.container)}`
              : D.box ? `periodic box, edge ${num(D.box)}` : 'open space';
  let facts = `${N} spheres · ${where}<br>${F} frames`;
  if (F < D.nframes_total) facts += ` (of ${D.nframes_total}, evenly subsampled)`;
  facts += ` · t ${num(t0)} … ${num(t1)}`;
  if (EV.total > EV.n) facts += `<br>${EV.n} of ${EV.total} events flashed (evenly subsampled)`;
  $('facts').innerHTML = facts;

  // ---- renderer, scene, camera
  const view = $('view');
  let renderer;
  try {
    renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    throw new Error('WebGL is not available in this browser (' + e.message + ')');
  }
  renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
  renderer.setClearColor(0x0f1217, 1);
  view.appendChild(renderer.domElement);
  renderer.domElement.tabIndex = 0;
  const scene = new THREE.Scene();
  const ext = D.extent;
  const camera = new THREE.PerspectiveCamera(40, 1, ext * 0.01, ext * 40);
  scene.add(camera);
  scene.add(new THREE.HemisphereLight(0xdde6ff, 0x30343c, 1.6));
  const key = new THREE.DirectionalLight(0xffffff, 2.2);
  key.position.set(1, 1.5, 2);
  camera.add(key);             // the light follows the view
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.enableDamping = true;
  controls.dampingFactor = 0.12;
  function resetCamera() {
    const d = ext / Math.sin((camera.fov / 2) * Math.PI / 180) * 1.08;
    const dir = new THREE.Vector3(1.0, 0.55, 1.35).normalize();
    camera.position.copy(dir.multiplyScalar(d));
    camera.up.set(0, 1, 0);
    controls.target.set(0, 0, 0);
    controls.update();
  }
  resetCamera();
  function resize() {
    const w = Math.max(1, view.clientWidth), h = Math.max(1, view.clientHeight);
    renderer.setSize(w, h, false);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    dirty = true;
  }

  // ---- container
  const wireMat = new THREE.LineBasicMaterial({ color: 0x9fb4cc, transparent: true, opacity: 0.28, depthWrite: false });
  if (D.container) {
    const r = D.container, pts = [], seg = 96;
    for (let m = 0; m < 12; m++) {                       // meridians
      const ph = (m / 12) * 2 * Math.PI;
      for (let s = 0; s < seg; s++) {
        for (const u of [s, s + 1]) {
          const th = (u / seg) * Math.PI;
          pts.push(r * Math.sin(th) * Math.cos(ph), r * Math.cos(th), r * Math.sin(th) * Math.sin(ph));
        }
      }
    }
    for (let q = 1; q < 8; q++) {                        // parallels
      const th = (q / 8) * Math.PI;
      for (let s = 0; s < seg; s++) {
        for (const u of [s, s + 1]) {
          const ph = (u / seg) * 2 * Math.PI;
          pts.push(r * Math.sin(th) * Math.cos(ph), r * Math.cos(th), r * Math.sin(th) * Math.sin(ph));
        }
      }
    }
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(pts, 3));
    scene.add(new THREE.LineSegments(g, wireMat));
  } else if (D.box) {
    scene.add(new THREE.LineSegments(new THREE.EdgesGeometry(new THREE.BoxGeometry(L, L, L)), wireMat));
  }

  // ---- spheres
  const detail = N <= 2000 ? [32, 20] : N <= 20000 ? [16, 10] : N <= 200000 ? [10, 6] : [7, 5];
  const geom = new THREE.SphereGeometry(1, detail[0], detail[1]);
  const mat = new THREE.MeshStandardMaterial({ roughness: 0.45, metalness: 0.05 });
  const mesh = new THREE.InstancedMesh(geom, mat, Math.max(N, 1));
  mesh.count = N;
  mesh.frustumCulled = false;
  mesh.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
  const MX = mesh.instanceMatrix.array;
  for (let i = 0; i < N; i++) { const o = 16 * i; MX[o] = MX[o + 5] = MX[o + 10] = R[i]; MX[o + 15] = 1; }
  const COL = new Float32Array(Math.max(N, 1) * 3);
  mesh.instanceColor = new THREE.InstancedBufferAttribute(COL, 3);
  mesh.instanceColor.setUsage(THREE.DynamicDrawUsage);
  scene.add(mesh);
  const ring = new THREE.Mesh(new THREE.SphereGeometry(1, 16, 10),
    new THREE.MeshBasicMaterial({ color: 0xffd60a, wireframe: true, transparent: true, opacity: 0.8 }));
  ring.visible = false;
  scene.add(ring);

  // ---- state
  const state = window.viewerState;
  let t = t0, playing = false, frame = 0, dirty = true, selected = -1;
  let colorBy = D.color_by, smooth = true, loop = true, rate = 1;
  const flashAt = new Float64Array(N).fill(-1e9), flashKind = new Uint8Array(N);
  const baseRate = span > 0 ? span / 20 : 0;      // the whole run in 20 s at x1

  // ---- legend
  function legend() {
    const el = $('legend');
    const [lo, hi] = colorBy === 'speed' ? D.speed_range : D.mass_range;
    const unit = colorBy === 'speed' ? 'speed' : 'mass';
    let h = `<div class="title">${unit}</div>`;
    if (hi > lo) {
      h += `<div class="scale"><canvas id="ramp" width="16" height="150"></canvas><div class="ticks">` +
           `<span>${fmt(hi)}${colorBy === 'speed' ? '+' : ''}</span><span>${fmt((lo + hi) / 2)}</span><span>${fmt(lo)}</span></div></div>`;
    } else {
      const c = cmapSRGB(0.5).map((v) => Math.round(v * 255));
      h += `<div><span class="swatch" style="background:rgb(${c})"></span>${fmt(lo)} (all equal)</div>`;
    }
    if (EV.n > 0) {
      h += '<div class="flash">flashes:<br>';
      for (const k of [1, 0]) if (EV.counts[k === 1 ? 'collisions' : 'reflections'] > 0)
        h += `<div><span class="swatch" style="background:${FLASH[k].css}"></span>${FLASH[k].label}</div>`;
      h += '</div>';
    }
    el.innerHTML = h;
    const ramp = $('ramp');
    if (ramp) {
      const g = ramp.getContext('2d');
      for (let y = 0; y < ramp.height; y++) {
        const c = cmapSRGB(1 - y / (ramp.height - 1)).map((v) => Math.round(v * 255));
        g.fillStyle = `rgb(${c})`;
        g.fillRect(0, y, ramp.width, 1);
      }
    }
  }

  // ---- drawing
  function frameAt(time) {           // index of the last frame at or before time
    return Math.max(0, Math.min(F - 1, upper(times, time) - 1));
  }
  function update(now) {
    let f = frameAt(t), a = 0;
    if (smooth && f < F - 1 && times[f + 1] > times[f]) a = Math.min(1, Math.max(0, (t - times[f]) / (times[f + 1] - times[f])));
    const o0 = f * N * 3, o1 = (f + 1) * N * 3;
    for (let i = 0; i < N; i++) {
      let x = P[o0 + 3 * i], y = P[o0 + 3 * i + 1], z = P[o0 + 3 * i + 2];
      if (a > 0) {
        let dx = P[o1 + 3 * i] - x, dy = P[o1 + 3 * i + 1] - y, dz = P[o1 + 3 * i + 2] - z;
        if (L) { dx -= L * Math.round(dx / L); dy -= L * Math.round(dy / L); dz -= L * Math.round(dz / L); }
        x += a * dx; y += a * dy; z += a * dz;
        if (L) { x -= L * Math.round(x / L); y -= L * Math.round(y / L); z -= L * Math.round(z / L); }
      }
      const o = 16 * i;
      MX[o + 12] = x; MX[o + 13] = y; MX[o + 14] = z;
    }
    mesh.instanceMatrix.needsUpdate = true;
    const [lo, hi] = colorBy === 'speed' ? D.speed_range : D.mass_range;
    const scale = hi > lo ? 255 / (hi - lo) : 0;
    const vals = colorBy === 'speed' ? SPEED : M, vo = colorBy === 'speed' ? f * N : 0;
    for (let i = 0; i < N; i++) {
      const k = scale ? Math.max(0, Math.min(255, Math.round((vals[vo + i] - lo) * scale))) : 128;
      let r = LUT[3 * k], g = LUT[3 * k + 1], b = LUT[3 * k + 2];
      const age = now - flashAt[i];
      if (age < FLASH_SECONDS) {
        const w = 1 - age / FLASH_SECONDS, c = FLASH[flashKind[i]].lin;
        r += w * (c[0] - r); g += w * (c[1] - g); b += w * (c[2] - b);
      }
      COL[3 * i] = r; COL[3 * i + 1] = g; COL[3 * i + 2] = b;
    }
    mesh.instanceColor.needsUpdate = true;
    if (selected >= 0) {
      ring.visible = true;
      ring.position.set(MX[16 * selected + 12], MX[16 * selected + 13], MX[16 * selected + 14]);
      ring.scale.setScalar(R[selected] * 1.18 + ext * 0.002);
      const nm = D.names ? D.names[selected] : `#${selected}`;
      const s = SPEED[f * N + selected];
      $('picked').innerHTML = `<br><b>${nm.replace(/[<&]/g, (c) => (c === '<' ? '&lt;' : '&amp;'))}</b> · mass ${fmt(M[selected])} · radius ${fmt(R[selected])}<br>` +
        `speed ${fmt(s)} · at (${fmt(ring.position.x)}, ${fmt(ring.position.y)}, ${fmt(ring.position.z)})`;
    } else {
      ring.visible = false;
      $('picked').innerHTML = '';
    }
    frame = f;
    state.frame = f; state.time = t; state.playing = playing;
    $('time').textContent = `t = ${fmt(t)} / ${fmt(t1)}`;
    const slider = $('slider');
    if (document.activeElement !== slider || playing) slider.value = String(f);
    const ke = upper(evT, t), coll = cumColl[ke], refl = ke - coll;
    const approx = EV.total > EV.n ? '~' : '';
    const sc = EV.total > EV.n ? EV.total / EV.n : 1;
    $('counts').textContent = evT.length || EV.total
      ? `up to now: ${approx}${Math.round(coll * sc)} collisions, ${approx}${Math.round(refl * sc)} reflections` : '';
  }
  let lastFlash = -1e9;
  function flash(ta, tb, now) {       // events in (ta, tb]
    let a = upper(evT, ta), b = upper(evT, tb);
    if (b > a) lastFlash = now;
    if (b - a > 50000) a = b - 50000;
    for (let k = a; k < b; k++) {
      const kind = evK[k] === 1 ? 1 : 0;
      flashAt[evI[k]] = now; flashKind[evI[k]] = kind;
      if (evJ[k] >= 0) { flashAt[evJ[k]] = now; flashKind[evJ[k]] = kind; }
    }
  }

  // ---- controls
  function setPlaying(p) {
    playing = p && F > 1;
    $('play').innerHTML = playing ? '&#10074;&#10074; Pause' : '&#9654; Play';
    state.playing = playing;
    dirty = true;
  }
  $('play').addEventListener('click', () => {
    if (!playing && t >= t1 && span > 0) t = t0;
    setPlaying(!playing);
  });
  const slider = $('slider');
  slider.max = String(F - 1);
  slider.addEventListener('input', () => { t = times[Math.max(0, Math.min(F - 1, +slider.value))]; dirty = true; });
  $('speed').addEventListener('input', (e) => {
    rate = Math.pow(10, +e.target.value);
    $('speedval').textContent = '\u00d7' + (rate >= 10 ? rate.toFixed(0) : rate >= 1 ? rate.toFixed(1) : rate.toFixed(2));
  });
  const sel = $('colorby');
  sel.value = colorBy;
  sel.addEventListener('change', () => { colorBy = sel.value; legend(); dirty = true; });
  $('smooth').addEventListener('change', (e) => { smooth = e.target.checked; dirty = true; });
  $('loop').addEventListener('change', (e) => { loop = e.target.checked; });
  $('reset').addEventListener('click', () => { resetCamera(); dirty = true; });
  controls.addEventListener('change', () => { dirty = true; });
  window.addEventListener('keydown', (e) => {
    if (e.target && (e.target.tagName === 'SELECT' || (e.target.tagName === 'INPUT' && e.target.type !== 'range' && e.target.type !== 'checkbox'))) return;
    if (e.code === 'Space') { e.preventDefault(); $('play').click(); }
    else if (e.code === 'ArrowRight' || e.code === 'ArrowLeft') {
      e.preventDefault();
      const f = Math.max(0, Math.min(F - 1, frameAt(t) + (e.code === 'ArrowRight' ? 1 : -1)));
      t = times[f]; dirty = true;
    }
  });
  const raycaster = new THREE.Raycaster();
  let down = null;
  renderer.domElement.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
  renderer.domElement.addEventListener('pointerup', (e) => {
    if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) { down = null; return; }
    down = null;
    const rect = renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((e.clientX - rect.left) / rect.width) * 2 - 1, -((e.clientY - rect.top) / rect.height) * 2 + 1);
    raycaster.setFromCamera(ndc, camera);
    mesh.computeBoundingSphere();
    const hits = N ? raycaster.intersectObject(mesh, false) : [];
    selected = hits.length ? hits[0].instanceId : -1;
    dirty = true;
  });
  new ResizeObserver(resize).observe(view);

  // ---- loop
  legend();
  resize();
  let last = performance.now();
  function tick(ms) {
    const now = ms / 1000, dt = Math.min(0.25, Math.max(0, now - last / 1000));
    last = ms;
    if (playing) {
      const tPrev = t;
      t += dt * rate * baseRate;
      if (t >= t1) {
        flash(tPrev, t1, now);
        if (loop) { t = t0 + ((t - t0) % span); } else { t = t1; setPlaying(false); }
      } else {
        flash(tPrev, t, now);
      }
      dirty = true;
    }
    const flashing = N > 0 && now - lastFlash < FLASH_SECONDS + 0.05;
    const damping = controls.update();
    if (dirty || flashing || damping) {
      update(now);
      renderer.render(scene, camera);
      dirty = false;
      if (!window.viewerReady) window.viewerReady = true;
    }
    requestAnimationFrame(tick);
  }
  update(performance.now() / 1000);
  renderer.render(scene, camera);
  window.viewerReady = true;
  requestAnimationFrame(tick);
}
main().catch(fail);
</script>
</body>
</html>
"""
