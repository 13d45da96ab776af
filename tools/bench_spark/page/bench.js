// In-page half of bench_spark: loads one scene with Spark's SplatMesh and times
// "camera change -> sorted, finished frame" for a list of INRIA-style cameras.
// The driver (../bench_spark.mjs) calls window.benchSpark(config) and reads the result.
import * as THREE from "three";
import { SparkRenderer, SplatMesh } from "@sparkjsdev/spark";

const now = () => performance.now();

// Camera-to-world [R | position] of an INRIA/COLMAP camera (x right, y down, looking along +z)
// times diag(1, -1, -1) gives the world matrix of a three.js camera (x right, y up, looking along -z).
function cameraWorldMatrix(view) {
  const R = view.rotation;
  const p = view.position;
  return new THREE.Matrix4().set(
    R[0][0], -R[0][1], -R[0][2], p[0],
    R[1][0], -R[1][1], -R[1][2], p[1],
    R[2][0], -R[2][1], -R[2][2], p[2],
    0, 0, 0, 1,
  );
}

// Pinhole projection from pixel intrinsics (fx, fy, cx, cy at the rendered size), so that a
// world point lands on the same pixel as in PointGauss, including fx != fy after a resize
// that changes the aspect ratio. With fx == fy and a centred principal point this is a plain
// PerspectiveCamera with fov = 2*atan(H / (2*fy)) and aspect = W/H.
function applyView(camera, view, width, height, near, far) {
  const m = cameraWorldMatrix(view);
  m.decompose(camera.position, camera.quaternion, camera.scale);
  camera.updateMatrixWorld(true);
  const left = (-view.cx / view.fx) * near;
  const right = ((width - view.cx) / view.fx) * near;
  const top = (view.cy / view.fy) * near;
  const bottom = (-(height - view.cy) / view.fy) * near;
  camera.near = near;
  camera.far = far;
  camera.aspect = width / height;
  camera.fov = THREE.MathUtils.radToDeg(2 * Math.atan(height / (2 * view.fy)));
  camera.projectionMatrix.makePerspective(left, right, top, bottom, near, far);
  camera.projectionMatrixInverse.copy(camera.projectionMatrix).invert();
}

function glInfo(gl) {
  const ext = gl.getExtension("WEBGL_debug_renderer_info");
  return {
    renderer: ext ? gl.getParameter(ext.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER),
    vendor: ext ? gl.getParameter(ext.UNMASKED_VENDOR_WEBGL) : gl.getParameter(gl.VENDOR),
    version: gl.getParameter(gl.VERSION),
  };
}

// Probe the WebGL2 implementation without loading anything else (the driver checks it first).
window.benchGlInfo = () => {
  const c = document.createElement("canvas");
  const gl = c.getContext("webgl2");
  if (!gl) return null;
  return glInfo(gl);
};

window.benchSpark = async (cfg) => {
  const { width, height, near, far } = cfg;
  const canvas = document.getElementById("view");
  const renderer = new THREE.WebGLRenderer({
    canvas,
    antialias: false, // Spark's advice; splats gain nothing from MSAA
    alpha: false,
    preserveDrawingBuffer: false,
  });
  renderer.setPixelRatio(1);
  renderer.setSize(width, height, false);
  renderer.setClearColor(0x000000, 1);
  const gl = renderer.getContext();

  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(50, width / height, near, far);
  const spark = new SparkRenderer({
    renderer,
    // Updates (view-space generate + depth readback + worker sort) are driven explicitly by
    // spark.update() below, so every one is timed and none runs behind the benchmark's back.
    autoUpdate: false,
    // A plain PLY has no LoD tree; keep the LoD machinery out of the loop.
    enableLod: false,
    // Classic 3DGS screen-space dilation (+0.3 px^2, no opacity compensation), as in the
    // INRIA reference renderer and PointGauss's default; Spark's default is blurAmount 0.3
    // (Mip-Splatting style). It changes pixels, not the cost.
    preBlurAmount: 0.3,
    blurAmount: 0.0,
  });
  scene.add(spark);

  const tLoad = now();
  const mesh = new SplatMesh({ url: cfg.sceneUrl });
  scene.add(mesh);
  await mesh.initialized;
  const loadMs = now() - tLoad;
  const source = mesh.splats ?? mesh.packedSplats ?? mesh.extSplats;
  const splats = source ? source.numSplats : -1;

  // Instrument the two halves of Spark's sort without changing what it does: the GPU depth
  // readback (readRenderTargetPixelsAsync, waits on a fence) and the worker's radix sort.
  let readbackMs = 0;
  let workerMs = 0;
  const readbackDepth = spark.readbackDepth.bind(spark);
  spark.readbackDepth = async (args) => {
    const t = now();
    try {
      return await readbackDepth(args);
    } finally {
      readbackMs += now() - t;
    }
  };
  let wrappedWorker = null;
  function wrapSortWorker() {
    const w = spark.sortWorker;
    if (!w || w === wrappedWorker) return;
    const call = w.call.bind(w);
    w.call = async (name, args, options) => {
      const t = now();
      try {
        return await call(name, args, options);
      } finally {
        if (name === "sortSplats32" || name === "sortSplats") workerMs += now() - t;
      }
    };
    wrappedWorker = w;
  }

  const pixel = new Uint8Array(4);
  const pos = new THREE.Vector3();
  const dir = new THREE.Vector3();

  // One frame: camera change -> Spark update (generate, readback, sort, ordering upload) ->
  // draw -> 1-pixel readPixels, which returns only after the GPU (SwiftShader) has finished.
  async function frame(view) {
    readbackMs = 0;
    workerMs = 0;
    const t0 = now();
    applyView(camera, view, width, height, near, far);
    await spark.update({ scene, camera });
    const t1 = now();
    renderer.render(scene, camera);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
    const t2 = now();
    // Is the drawn order the one sorted for this camera? Spark records the view it sorted for.
    camera.getWorldPosition(pos);
    camera.getWorldDirection(dir);
    const sorted =
      spark.display === spark.current &&
      spark.sortedCenter.distanceTo(pos) < 1e-4 &&
      spark.sortedDir.dot(dir) > 0.99999 &&
      !spark.sorting;
    return {
      view: view.name,
      sort_ms: t1 - t0,
      draw_ms: t2 - t1,
      total_ms: t2 - t0,
      readback_ms: readbackMs,
      worker_sort_ms: workerMs,
      sorted,
      active_splats: spark.activeSplats,
    };
  }

  const views = cfg.views;
  // First frame: compiles Spark's programs and creates its sort worker; reported apart.
  const first = await frame(views[0]);
  wrapSortWorker();
  const frames = [];
  for (let f = 0; f < cfg.warmup + cfg.frames; ++f) {
    const r = await frame(views[f % views.length]);
    r.warmup = f < cfg.warmup;
    frames.push(r);
  }

  // Pictures: each view once more, sorted, encoded straight after the draw (the drawing
  // buffer is still intact within the same task).
  const images = [];
  if (cfg.save) {
    for (const view of views) {
      applyView(camera, view, width, height, near, far);
      await spark.update({ scene, camera });
      renderer.render(scene, camera);
      images.push({ name: view.name, png: canvas.toDataURL("image/png") });
    }
  }

  return {
    gl: glInfo(gl),
    three: THREE.REVISION,
    splats,
    load_ms: loadMs,
    first_frame_ms: first.total_ms,
    frames,
    images,
  };
};

window.benchModuleLoaded = true;
