#!/usr/bin/env node
// Driver of the Spark peer benchmark: serves page/ + the needed node_modules files + the scene
// on 127.0.0.1, runs page/bench.js in headless Chromium on SwiftShader WebGL2, and reports
// milliseconds per frame (sort + draw) like `pointgauss bench render`. See README.md.
import fs from "node:fs";
import http from "node:http";
import path from "node:path";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";

const HERE = path.dirname(fileURLToPath(import.meta.url));
const NEAR = 0.2; // PointGauss's RenderSettings::near
const FAR = 1000;

const USAGE = `usage: bench_spark.sh SCENE CAMERAS.json [--width W --height H] [--views all|i,j|name,...]
                      [--frames N] [--warmup N] [--json] [--save DIR] [--chromium PATH]
                      [--any-renderer] [--timeout SEC]

Renders SCENE with Spark (three.js) in headless Chromium on SwiftShader (software WebGL2),
cycling through the chosen cameras, and reports ms per finished, sorted frame.
  --width/--height  frame size (give both; intrinsics scale with it); default: first view's size
  --views           views to cycle through: all, or indices / img_names (default 0)
  --frames          measured frames (default 20)
  --warmup          frames before measuring (default 3)
  --json            print JSON instead of a markdown table
  --save DIR        also write DIR/<img_name>.png for every chosen view (sorted, after the run)
  --chromium PATH   browser binary (default /usr/lib/chromium/chromium, else /usr/bin/chromium)
  --any-renderer    do not insist on SwiftShader (e.g. to try a GPU)
  --timeout SEC     give up after SEC seconds (default 900)`;

function fail(msg) {
  process.stderr.write(`bench_spark: ${msg}\n`);
  process.exit(2);
}

function parseArgs(argv) {
  const a = { views: "0", frames: 20, warmup: 3, json: false, anyRenderer: false, timeout: 900 };
  const pos = [];
  const intArg = (name, v, min) => {
    if (v === undefined || !/^\d+$/.test(v)) fail(`${name} needs a whole number, got '${v ?? ""}'`);
    const n = Number(v);
    if (n < min) fail(`${name} must be at least ${min}`);
    return n;
  };
  for (let i = 0; i < argv.length; ++i) {
    const arg = argv[i];
    const next = () => {
      if (i + 1 >= argv.length) fail(`${arg} needs a value`);
      return argv[++i];
    };
    switch (arg) {
      case "-h": case "--help": process.stdout.write(USAGE + "\n"); process.exit(0);
      case "--width": a.width = intArg(arg, next(), 1); break;
      case "--height": a.height = intArg(arg, next(), 1); break;
      case "--views": a.views = next(); break;
      case "--frames": a.frames = intArg(arg, next(), 1); break;
      case "--warmup": a.warmup = intArg(arg, next(), 0); break;
      case "--json": a.json = true; break;
      case "--save": a.save = next(); break;
      case "--chromium": a.chromium = next(); break;
      case "--any-renderer": a.anyRenderer = true; break;
      case "--timeout": a.timeout = intArg(arg, next(), 1); break;
      default:
        if (arg.startsWith("-")) fail(`unknown option ${arg}\n${USAGE}`);
        pos.push(arg);
    }
  }
  if (pos.length !== 2) fail(`need SCENE and CAMERAS\n${USAGE}`);
  [a.scene, a.cameras] = pos;
  if ((a.width === undefined) !== (a.height === undefined)) fail("--width/--height: give both or neither");
  if (a.width > 8192 || a.height > 8192) fail("--width/--height: at most 8192");
  return a;
}

function loadCameras(file) {
  let list;
  try {
    list = JSON.parse(fs.readFileSync(file, "utf8"));
  } catch (e) {
    fail(`cannot read cameras ${file}: ${e.message}`);
  }
  if (!Array.isArray(list) || list.length === 0) fail(`${file}: expected a non-empty list of cameras`);
  const finite = (x) => typeof x === "number" && Number.isFinite(x);
  return list.map((c, i) => {
    const where = `${file}: camera ${i}`;
    if (!c || typeof c !== "object") fail(`${where}: not an object`);
    if (!(finite(c.width) && finite(c.height) && c.width > 0 && c.height > 0)) fail(`${where}: bad width/height`);
    if (!(finite(c.fx) && finite(c.fy) && c.fx > 0 && c.fy > 0)) fail(`${where}: bad fx/fy`);
    if (!(Array.isArray(c.position) && c.position.length === 3 && c.position.every(finite)))
      fail(`${where}: position must be 3 numbers`);
    if (!(Array.isArray(c.rotation) && c.rotation.length === 3 &&
          c.rotation.every((r) => Array.isArray(r) && r.length === 3 && r.every(finite))))
      fail(`${where}: rotation must be 3 rows of 3 numbers`);
    return { ...c, name: String(c.img_name ?? c.id ?? i) };
  });
}

function selectViews(spec, cams) {
  if (spec === "all") return cams.map((_, i) => i);
  const out = [];
  for (const tok of spec.split(",").map((s) => s.trim()).filter(Boolean)) {
    let idx = /^\d+$/.test(tok) ? Number(tok) : -1;
    if (idx >= cams.length) idx = -1;
    if (idx < 0) idx = cams.findIndex((c) => c.name === tok);
    if (idx < 0) fail(`--views: no camera '${tok}' (${cams.length} cameras)`);
    out.push(idx);
  }
  if (out.length === 0) fail("--views: empty");
  return out;
}

// Intrinsics at the rendered size, scaled per axis exactly like pg::data::Camera::resized
// (fx, cx by W/width; fy, cy by H/height). INRIA cameras.json has no principal point: centre.
function viewAt(c, W, H) {
  const sx = W / c.width;
  const sy = H / c.height;
  const cx = Number.isFinite(c.cx) ? c.cx : c.width / 2;
  const cy = Number.isFinite(c.cy) ? c.cy : c.height / 2;
  return {
    name: c.name, position: c.position, rotation: c.rotation,
    fx: c.fx * sx, fy: c.fy * sy, cx: cx * sx, cy: cy * sy,
  };
}

const TYPES = {
  ".html": "text/html; charset=utf-8", ".js": "text/javascript; charset=utf-8",
  ".mjs": "text/javascript; charset=utf-8", ".json": "application/json", ".map": "application/json",
  ".wasm": "application/wasm",
};

// Static server: /page/*, three's and Spark's package folders, and /scene/<name> (the scene).
function startServer(scenePath) {
  const roots = [
    ["/page/", path.join(HERE, "page")],
    ["/node_modules/three/", path.join(HERE, "node_modules", "three")],
    ["/node_modules/@sparkjsdev/spark/", path.join(HERE, "node_modules", "@sparkjsdev", "spark")],
  ];
  const sceneUrl = "/scene/" + encodeURIComponent(path.basename(scenePath));
  const server = http.createServer((req, res) => {
    const url = decodeURIComponent(new URL(req.url, "http://x").pathname);
    let file = null;
    if (url === decodeURIComponent(sceneUrl)) file = scenePath;
    for (const [prefix, dir] of roots) {
      if (file || !url.startsWith(prefix)) continue;
      const f = path.resolve(dir, "." + url.slice(prefix.length - 1));
      if (f.startsWith(dir + path.sep)) file = f;
    }
    let st = null;
    try { st = file && fs.statSync(file); } catch { st = null; }
    if (!st || !st.isFile()) {
      res.writeHead(404, { "Content-Type": "text/plain" });
      res.end("not found\n");
      return;
    }
    res.writeHead(200, {
      "Content-Type": TYPES[path.extname(file)] ?? "application/octet-stream",
      "Content-Length": st.size,
      "Cache-Control": "no-store",
    });
    fs.createReadStream(file).pipe(res);
  });
  return new Promise((resolve, reject) => {
    server.on("error", reject);
    server.listen(0, "127.0.0.1", () => resolve({ server, port: server.address().port, sceneUrl }));
  });
}

const round3 = (x) => Math.round(x * 1000) / 1000;

// Median (mean of the middle two for an even count, as PointGauss's median()), min, max.
function stats(values) {
  const v = [...values].sort((x, y) => x - y);
  const n = v.length;
  if (n === 0) return { median: 0, min: 0, max: 0 };
  const median = n % 2 ? v[(n - 1) / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  return { median: round3(median), min: round3(v[0]), max: round3(v[n - 1]) };
}

function chromiumPath(given) {
  if (given) return given;
  for (const p of ["/usr/lib/chromium/chromium", "/usr/bin/chromium"]) if (fs.existsSync(p)) return p;
  fail("no Chromium found; apt-get install chromium (or pass --chromium PATH)");
}

async function main() {
  const a = parseArgs(process.argv.slice(2));
  if (!fs.existsSync(a.scene) || !fs.statSync(a.scene).isFile()) fail(`no scene file ${a.scene}`);
  const cams = loadCameras(a.cameras);
  const chosen = selectViews(a.views, cams);
  const W = a.width ?? cams[chosen[0]].width;
  const H = a.height ?? cams[chosen[0]].height;
  const views = chosen.map((i) => viewAt(cams[i], W, H));
  const sparkVersion = JSON.parse(
    fs.readFileSync(path.join(HERE, "node_modules", "@sparkjsdev", "spark", "package.json"), "utf8")).version;

  const { server, port, sceneUrl } = await startServer(path.resolve(a.scene));
  const browser = await chromium.launch({
    executablePath: chromiumPath(a.chromium),
    headless: true,
    args: [
      "--use-gl=angle",
      "--use-angle=swiftshader",
      "--enable-unsafe-swiftshader",
      "--ignore-gpu-blocklist",
      "--no-sandbox", // root in a container
    ],
  });
  const watchdog = setTimeout(() => {
    process.stderr.write(`bench_spark: gave up after ${a.timeout} s\n`);
    browser.close().finally(() => process.exit(1));
  }, a.timeout * 1000);
  try {
    const page = await browser.newPage({ viewport: { width: W, height: H }, deviceScaleFactor: 1 });
    const errors = [];
    page.on("pageerror", (e) => errors.push(String(e)));
    page.on("console", (m) => {
      if (m.type() === "error") errors.push(m.text());
    });
    await page.goto(`http://127.0.0.1:${port}/page/index.html`);
    await page.waitForFunction(() => window.benchModuleLoaded === true, null, { timeout: 60000 })
      .catch(() => fail(`page did not load: ${errors.join("; ") || "timeout"}`));
    const gl = await page.evaluate(() => window.benchGlInfo());
    if (!gl) fail("no WebGL2 context in Chromium");
    if (!a.json) process.stderr.write(`WebGL renderer: ${gl.renderer}\n`);
    if (!a.anyRenderer && !/swiftshader/i.test(gl.renderer))
      fail(`WebGL renderer is not SwiftShader: ${gl.renderer} (pass --any-renderer to allow it)`);

    const r = await page.evaluate((cfg) => window.benchSpark(cfg), {
      sceneUrl, width: W, height: H, near: NEAR, far: FAR, views,
      frames: a.frames, warmup: a.warmup, save: Boolean(a.save),
    }).catch((e) => fail(`benchmark failed in the page: ${e.message}\n${errors.join("\n")}`));

    if (a.save) {
      fs.mkdirSync(a.save, { recursive: true });
      for (const img of r.images) {
        const b64 = img.png.slice(img.png.indexOf(",") + 1);
        fs.writeFileSync(path.join(a.save, `${img.name.replace(/[^\w.-]/g, "_")}.png`), Buffer.from(b64, "base64"));
      }
    }

    const measured = r.frames.filter((f) => !f.warmup);
    const unsorted = measured.filter((f) => !f.sorted).length;
    const parts = ["sort_ms", "draw_ms", "total_ms", "readback_ms", "worker_sort_ms"];
    const s = Object.fromEntries(parts.map((k) => [k, stats(measured.map((f) => f[k]))]));
    const out = {
      renderer: "Spark",
      spark: sparkVersion,
      three: r.three,
      browser: `Chromium ${browser.version()}`,
      webgl_renderer: r.gl.renderer,
      webgl_vendor: r.gl.vendor,
      webgl_version: r.gl.version,
      scene: a.scene,
      gaussians: r.splats,
      width: W,
      height: H,
      views: views.map((v) => v.name),
      frames: a.frames,
      warmup: a.warmup,
      load_ms: round3(r.load_ms),
      first_frame_ms: round3(r.first_frame_ms),
      unsorted_frames: unsorted,
      active_splats: stats(measured.map((f) => f.active_splats)).median,
      ms: s,
      per_frame: measured.map(({ view, sort_ms, draw_ms, total_ms, readback_ms, worker_sort_ms }) =>
        ({ view, sort_ms: round3(sort_ms), draw_ms: round3(draw_ms), total_ms: round3(total_ms),
          readback_ms: round3(readback_ms), worker_sort_ms: round3(worker_sort_ms) })),
    };
    if (a.json) {
      process.stdout.write(JSON.stringify(out, null, 2) + "\n");
    } else {
      const f = (x) => x.toFixed(2);
      const row = (label, k) => `| ${label} | ${f(s[k].median)} | ${f(s[k].min)} | ${f(s[k].max)} |`;
      const lines = [
        `renderer   Spark ${sparkVersion} (three r${r.three}), ${out.browser}`,
        `WebGL      ${r.gl.renderer}`,
        `scene      ${a.scene} (${r.splats} Gaussians), ${W}x${H}, views ${out.views.join(",")}`,
        `frames     ${a.frames} after ${a.warmup} warm-up; load ${r.load_ms.toFixed(0)} ms, first frame ${r.first_frame_ms.toFixed(0)} ms`,
        `splats     ${out.active_splats} drawn after culling (median)`,
        "",
        "| part | median ms | min ms | max ms |",
        "|---|---:|---:|---:|",
        row("sort: generate + depth readback + worker sort + upload", "sort_ms"),
        row("  of which depth readback", "readback_ms"),
        row("  of which worker sort", "worker_sort_ms"),
        row("draw (render + finish)", "draw_ms"),
        row("**total per frame**", "total_ms"),
      ];
      if (unsorted) lines.push("", `WARNING: ${unsorted} measured frame(s) were not drawn in the order sorted for their own view`);
      process.stdout.write(lines.join("\n") + "\n");
    }
  } finally {
    clearTimeout(watchdog);
    await browser.close();
    server.close();
  }
}

main().catch((e) => {
  process.stderr.write(`bench_spark: ${e.stack ?? e}\n`);
  process.exit(1);
});
