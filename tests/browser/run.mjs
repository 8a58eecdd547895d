#!/usr/bin/env node
// Headless browser test of `ridge serve`: its web pages (web/cesium.html, web/maplibre.html) drawn
// by CesiumJS and MapLibre GL in Debian's chromium (WebGL on SwiftShader), and its tiles decoded
// independently of both viewers.
//
//   node tests/browser/run.mjs --ridge build/ridge --archive everest.ridge --out DIR
//                              [--timeout 480] [--phases cesium,decoder,maplibre,rgb]
//
// The archive is meant to be `ridge build tests/data/everest_crop.tif -o DIR/everest.ridge --patch 33`:
// the camera looks at Everest. Phases:
//   cesium    cesium.html?test=1 at a fixed camera: terrain drawn, no holes under the skyline, and
//             the skyline matches `ridge render` from the same camera
//   decoder   quantized-mesh tiles decoded by @here/quantized-mesh-decoder: every vertex within the
//             tile's X-Ridge-Claimed-Error of `ridge query`, shared edges identical, headers sane
//   maplibre  maplibre.html?test=1 (mapbox PNG, terrarium WebP): the tile URLs its TileJSON gives,
//             terrain drawn, no holes
//   rgb       terrain-RGB tiles decoded pixel by pixel against `ridge query`, within X-Ridge-Step/2
//             (+ X-Ridge-Archive-Error)
// Writes DIR/cesium.png, DIR/render.png, DIR/maplibre.png, DIR/maplibre-terrarium-webp.png.
// Exit status: 0 every check passed, 1 a check failed (or the run broke or timed out), 2 usage
// error, 77 chromium or web/node_modules missing (scripts/install-web-deps.sh), so a harness can skip.
// Time: at most --timeout seconds, then up to 25 s to close chromium and stop the server, which is
// stopped (SIGTERM, SIGKILL 15 s later) on every way out: success, failure, time limit, SIGINT/SIGTERM.
import { spawn } from 'node:child_process';
import { existsSync, mkdirSync, readFileSync } from 'node:fs';
import { request } from 'node:http';
import { createRequire } from 'node:module';
import { basename, dirname, join, resolve } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { parseArgs } from 'node:util';
import { gunzipSync } from 'node:zlib';

const repo = resolve(dirname(fileURLToPath(import.meta.url)), '../..');
const webDir = join(repo, 'web');

// ---------------------------------------------------------------------------------------------
// The view and the tolerances (measured figures and reasons in the comments).

const VIEWPORT = { width: 1280, height: 720 };
const EVEREST = { lon: 86.925, lat: 27.988 };
// South-west of Everest, inside the fixture (so the near edge of the view is over data), looking
// at the summit and 20° down: the skyline is the Everest massif and the fixture's north-east edges.
const CAMERA = { lon: 86.8, lat: 27.86, height: 12000, pitch: -20 };
CAMERA.heading = bearingDegrees(CAMERA, EVEREST);

// The page must be non-magenta (terrain) on at least this fraction of the viewport: ridge render
// draws terrain on 58.2 % of this view, CesiumJS on 58.3 %, MapLibre on 57.8 % (its fov is 36.9°,
// Cesium's 36.0°); an empty or half-drawn view is far below.
const MIN_TERRAIN_FRACTION = 0.5;
// Magenta pixels allowed under each column's skyline. The footprint seen from a camera above it is
// one connected surface in every column (a column's plane cuts the rectangle in one segment that
// starts under the camera), so any background below the first terrain pixel is a hole; multisampled
// edges blend into the terrain colour and never read as pure magenta.
const MAX_HOLE_PIXELS = 0;
// Skyline rows, CesiumJS vs ridge render (same camera, same vertical fov, both on the WGS 84
// ellipsoid): each draws the surface within its own error (Cesium's tiles within X-Ridge-Claimed-
// Error, ~37 m at zoom 11, ~2 px at the 18 km to the massif; ridge render within ε = 2 px), so they
// may be ~4 px apart where both err opposite ways. Measured: median 1 px, p95 2 px, max 4 px (with
// ridge render on its flat frame instead: p95 3 px, Cesium 0.8 px lower on average, the Earth's
// curvature). A camera or fov mismatch (e.g. Cesium's horizontal 60° taken as vertical) is tens.
const SKYLINE_MEDIAN_PX = 2;
const SKYLINE_P95_PX = 4;
// ridge render --no-sky clears to clear_colour (0.62, 0.74, 0.88) = RGB (158, 189, 224).
const RENDER_SKY = [158, 189, 224];
// Slack on top of the server's stated bounds, for its float32 heights (half an ulp is 0.24 mm at
// 4096-8192 m, 0.49 mm above): terrain-RGB pixels measured up to 0.47 mm beyond step/2.
const HEIGHT_SLACK = 1e-3;

// CesiumJS's Accept header for a provider asked for all three extensions (CesiumTerrainProvider).
const CESIUM_ACCEPT =
  'application/vnd.quantized-mesh;extensions=octvertexnormals-watermask-metadata,application/octet-stream;q=0.9,*/*;q=0.01';

// The chromium flags that give WebGL without a GPU: ANGLE on SwiftShader's Vulkan.
const CHROMIUM_ARGS = ['--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'];
const CHROMIUM_PATHS = ['/usr/lib/chromium/chromium', '/usr/bin/chromium']; // the binary, then Debian's wrapper script

// ---------------------------------------------------------------------------------------------
// Reporting: every check prints one line; the exit status is 1 if any failed.

const failures = [];
const t0 = Date.now();
const seconds = (ms) => `${(ms / 1000).toFixed(1)} s`;

function check(name, ok, detail) {
  console.log(`${ok ? 'PASS' : 'FAIL'} ${name}: ${detail}`);
  if (!ok) failures.push(name);
  return ok;
}

async function phase(name, body) {
  const start = Date.now();
  console.log(`--- ${name}`);
  try {
    await body();
  } catch (e) {
    check(`${name} phase`, false, e.stack ?? String(e));
  }
  console.log(`--- ${name}: ${seconds(Date.now() - start)}`);
}

function usage(message) {
  console.error(`run.mjs: ${message}\nusage: node tests/browser/run.mjs --ridge PATH --archive PATH.ridge --out DIR [--timeout SECONDS] [--phases LIST]`);
  process.exit(2);
}

function skip(message) {
  console.log(`SKIP ${message}`);
  process.exit(77);
}

// ---------------------------------------------------------------------------------------------
// Processes: the server, ridge render, ridge query.

// Runs a command to completion; `input` is written to its stdin.
function run(command, args, input) {
  return new Promise((resolveRun, reject) => {
    const child = spawn(command, args, { stdio: ['pipe', 'pipe', 'pipe'] });
    const out = [];
    const err = [];
    child.stdout.on('data', (d) => out.push(d));
    child.stderr.on('data', (d) => err.push(d));
    child.on('error', reject);
    child.on('close', (code) => resolveRun({ code, stdout: Buffer.concat(out).toString(), stderr: Buffer.concat(err).toString() }));
    child.stdin.end(input ?? '');
  });
}

// `ridge serve --port 0` prints its URL as the first stdout line; its log (stderr) is kept for
// the report when something fails.
function startServer(ridge, archive) {
  const child = spawn(ridge, ['serve', '--port', '0', '--pages', webDir, archive], { stdio: ['ignore', 'pipe', 'pipe'] });
  const log = [];
  child.stderr.on('data', (d) => log.push(...d.toString().split('\n').filter(Boolean)));
  const url = new Promise((resolveUrl, reject) => {
    let text = '';
    const timer = setTimeout(() => reject(new Error('ridge serve printed no URL in 30 s')), 30_000);
    child.stdout.on('data', (d) => {
      text += d;
      const lines = text.split('\n');
      if (lines.length > 1) {
        clearTimeout(timer);
        resolveUrl(lines[0].trim());
      }
    });
    child.on('exit', (code) => reject(new Error(`ridge serve exited (${code}): ${log.slice(-5).join(' | ')}`)));
    child.on('error', reject);
  });
  return { child, url, log };
}

// SIGTERM must stop the server cleanly (exit 0) within STOP_S; after STOP_KILL_S it is killed.
const STOP_S = 5;
const STOP_KILL_S = 15;
async function stopServer(server) {
  if (server.child.exitCode !== null || server.child.signalCode !== null) return;
  const start = Date.now();
  const exited = new Promise((r) => server.child.once('exit', (code, signal) => r({ code, signal })));
  server.child.kill('SIGTERM');
  const result = await Promise.race([exited, new Promise((r) => setTimeout(() => r(null), STOP_KILL_S * 1000))]);
  if (result === null) {
    server.child.kill('SIGKILL');
    check('ridge serve stops on SIGTERM', false, `still running after ${STOP_KILL_S} s; killed`);
  } else {
    const ms = Date.now() - start;
    check('ridge serve stops on SIGTERM', result.code === 0 && ms <= STOP_S * 1000, `exit ${result.code ?? result.signal} after ${seconds(ms)} (at most ${STOP_S} s)`);
  }
}

// Archive heights (bilinear, the surface between the finest samples) at lon/lat points; null off
// the raster. ridge query exits 1 when some point has no height, so the JSON is what counts.
async function archiveHeights(ridge, archive, points) {
  const input = points.map(([lon, lat]) => `${lon} ${lat}\n`).join('');
  const { code, stdout, stderr } = await run(ridge, ['query', archive, '--lonlat', '-r', 'bilinear', '--json'], input);
  let doc;
  try {
    doc = JSON.parse(stdout);
  } catch {
    throw new Error(`ridge query (exit ${code}) printed no JSON: ${stderr.trim()}`);
  }
  if (doc.points.length !== points.length) throw new Error(`ridge query answered ${doc.points.length} of ${points.length} points`);
  return doc.points.map((p) => p.height);
}

// ---------------------------------------------------------------------------------------------
// HTTP and geometry.

function httpGet(url, headers = {}) {
  return new Promise((resolveGet, reject) => {
    request(url, { headers }, (res) => {
      const chunks = [];
      res.on('data', (c) => chunks.push(c));
      res.on('end', () => resolveGet({ status: res.statusCode, headers: res.headers, body: Buffer.concat(chunks) }));
      res.on('error', reject);
    }).on('error', reject).end();
  });
}

async function getJson(url) {
  const r = await httpGet(url);
  if (r.status !== 200) throw new Error(`${url}: HTTP ${r.status}`);
  return JSON.parse(r.body.toString());
}

function bearingDegrees(from, to) {
  const rad = Math.PI / 180;
  const [f1, f2, dl] = [from.lat * rad, to.lat * rad, (to.lon - from.lon) * rad];
  const y = Math.sin(dl) * Math.cos(f2);
  const x = Math.cos(f1) * Math.sin(f2) - Math.sin(f1) * Math.cos(f2) * Math.cos(dl);
  return ((Math.atan2(y, x) / rad) + 360) % 360;
}

const WGS84 = { a: 6378137, b: 6356752.314245179 };
function ecef(lon, lat, h) {
  const rad = Math.PI / 180;
  const e2 = 1 - (WGS84.b * WGS84.b) / (WGS84.a * WGS84.a);
  const [sl, cl, sp, cp] = [Math.sin(lon * rad), Math.cos(lon * rad), Math.sin(lat * rad), Math.cos(lat * rad)];
  const n = WGS84.a / Math.sqrt(1 - e2 * sp * sp);
  return [(n + h) * cp * cl, (n + h) * cp * sl, (n * (1 - e2) + h) * sp];
}

// Horizon culling as CesiumJS does it, in the ellipsoid-scaled space the tile header's horizon
// occlusion point is given in: a point is hidden when it lies beyond the tangent cone from the
// camera to the (unit) scaled ellipsoid.
function scaledPointVisible(cameraEcef, point) {
  const c = [cameraEcef[0] / WGS84.a, cameraEcef[1] / WGS84.a, cameraEcef[2] / WGS84.b];
  const vh2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2] - 1;
  const vt = [point[0] - c[0], point[1] - c[1], point[2] - c[2]];
  const vtDotVc = -(vt[0] * c[0] + vt[1] * c[1] + vt[2] * c[2]);
  const vt2 = vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2];
  return !(vtDotVc > vh2 && (vtDotVc * vtDotVc) / vt2 > vh2);
}

function percentile(sorted, p) {
  return sorted[Math.min(sorted.length - 1, Math.floor(p * sorted.length))];
}

// ---------------------------------------------------------------------------------------------
// Images: decoded by the browser (createImageBitmap, no colour conversion, then getImageData), the
// same way MapLibre reads terrain-RGB tiles; WebP needs it anyway.

async function decodeImage(decoder, bytes, mime) {
  const { width, height, rgba } = await decoder.evaluate(async ({ b64, mime }) => {
    const bytes = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
    const bitmap = await createImageBitmap(new Blob([bytes], { type: mime }), { colorSpaceConversion: 'none', premultiplyAlpha: 'none' });
    const ctx = new OffscreenCanvas(bitmap.width, bitmap.height).getContext('2d', { willReadFrequently: true });
    ctx.drawImage(bitmap, 0, 0);
    const data = ctx.getImageData(0, 0, bitmap.width, bitmap.height).data;
    let binary = '';
    for (let i = 0; i < data.length; i += 0x8000) binary += String.fromCharCode.apply(null, data.subarray(i, i + 0x8000));
    return { width: bitmap.width, height: bitmap.height, rgba: btoa(binary) };
  }, { b64: bytes.toString('base64'), mime });
  return { width, height, data: Buffer.from(rgba, 'base64') };
}

// The pages clear to exactly (255, 0, 255); pixels that multisampling blends at the skyline are terrain.
const isMagenta = (d, i) => d[i] >= 250 && d[i + 1] <= 5 && d[i + 2] >= 250;
const isColour = ([r, g, b]) => (d, i) => Math.abs(d[i] - r) <= 2 && Math.abs(d[i + 1] - g) <= 2 && Math.abs(d[i + 2] - b) <= 2;

// Per column, the first row from the top that is not background (-1: none); the background pixels
// below it (holes); the fraction of the image that is not background.
function analyse(img, isBackground) {
  const skyline = new Int32Array(img.width).fill(-1);
  let holes = 0;
  let drawn = 0;
  for (let x = 0; x < img.width; x++) {
    for (let y = 0; y < img.height; y++) {
      const background = isBackground(img.data, (y * img.width + x) * 4);
      if (!background) drawn++;
      if (skyline[x] < 0) {
        if (!background) skyline[x] = y;
      } else if (background) {
        holes++;
      }
    }
  }
  const emptyColumns = skyline.filter((y) => y < 0).length;
  return { skyline, holes, emptyColumns, fraction: drawn / (img.width * img.height) };
}

function checkDrawn(name, a) {
  check(`${name}: terrain drawn`, a.fraction >= MIN_TERRAIN_FRACTION,
    `${(100 * a.fraction).toFixed(1)} % of the viewport not magenta (at least ${100 * MIN_TERRAIN_FRACTION} %)`);
  check(`${name}: no holes`, a.holes <= MAX_HOLE_PIXELS && a.emptyColumns === 0,
    `${a.holes} magenta pixels under the skyline (at most ${MAX_HOLE_PIXELS}), ${a.emptyColumns} columns without terrain`);
}

// ---------------------------------------------------------------------------------------------
// Pages.

function cameraQuery(camera) {
  return ['lon', 'lat', 'height', 'heading', 'pitch'].map((k) => `${k}=${camera[k]}`).join('&');
}

// Opens a page and waits until window.ridgeStatus says ready (or gives an error).
async function openViewer(context, name, url, timeoutMs) {
  const page = await context.newPage();
  const messages = []; // the page's errors and warnings, printed when it fails
  page.on('console', (m) => { if (m.type() === 'error' || m.type() === 'warning') messages.push(`${m.type()}: ${m.text()}`); });
  page.on('pageerror', (e) => messages.push(`pageerror: ${e.message}`));
  const start = Date.now();
  await page.goto(url);
  try {
    await page.waitForFunction(() => window.ridgeStatus?.ready || window.ridgeStatus?.error, null, { timeout: timeoutMs, polling: 500 });
  } catch {
    // reported below from the status as it stands
  }
  const status = await page.evaluate(() => window.ridgeStatus);
  const ok = check(`${name}: page ready`, Boolean(status?.ready) && !status.error,
    `${seconds(Date.now() - start)}, ${JSON.stringify({ error: status?.error, tilesLoaded: status?.tilesLoaded, frames: status?.frames })}`);
  if (!ok) {
    for (const line of messages.slice(0, 10)) console.log(`    ${line.slice(0, 300)}`);
    await page.close();
  }
  return { page, status, ok };
}

async function cesiumPhase(ctx) {
  const { context, decoder, base, tileset, ridge, archive, out } = ctx;
  const url = `${base}cesium.html?test=1&tileset=${tileset}&${cameraQuery(CAMERA)}`;
  const { page, status, ok } = await openViewer(context, 'cesium', url, 180_000);
  if (!ok) return;
  const shot = await page.screenshot({ path: join(out, 'cesium.png') });
  const cesium = analyse(await decodeImage(decoder, shot, 'image/png'), isMagenta);
  check('cesium: terrain drawn', cesium.fraction >= MIN_TERRAIN_FRACTION,
    `${(100 * cesium.fraction).toFixed(1)} % of the viewport not magenta (at least ${100 * MIN_TERRAIN_FRACTION} %)`);
  // Holes on the whole globe: clipped to the tileset's bounds (for the skyline below), a screen
  // column near the image's sides may leave the footprint and re-enter it, which is no hole;
  // unclipped, the tiles beyond the archive (its edge fading out to 0 m) are drawn too, so any
  // magenta under the skyline is a crack or a missing tile.
  await page.evaluate(() => window.ridgeUnclip());
  await page.waitForFunction(() => window.ridgeStatus?.ready || window.ridgeStatus?.error, null, { timeout: 120_000, polling: 500 });
  const globeShot = await page.screenshot({ path: join(out, 'cesium-globe.png') });
  await page.close();
  const globe = analyse(await decodeImage(decoder, globeShot, 'image/png'), isMagenta);
  check('cesium (whole globe): no holes', globe.holes <= MAX_HOLE_PIXELS && globe.emptyColumns === 0,
    `${globe.holes} magenta pixels under the skyline (at most ${MAX_HOLE_PIXELS}), ${globe.emptyColumns} columns without terrain`);

  // ridge render from the camera Cesium reports, with Cesium's vertical fov (its frustum's fov is
  // the horizontal one in a landscape canvas), on the ellipsoid as Cesium draws it. The fixture
  // names no vertical datum, so the tiles carry its own heights and Cesium's camera height is the
  // one ridge render takes.
  const cam = status.camera;
  const renderPng = join(out, 'render.png');
  const r = await run(ridge, ['render', archive, '--camera-lonlat', `${cam.lon},${cam.lat},${cam.height}`,
    '--heading', String(cam.heading), '--pitch', String(cam.pitch), '--fov', String(status.fovyDegrees),
    '--size', `${VIEWPORT.width}x${VIEWPORT.height}`, '--no-sky', '--no-fog', '--frame', 'ellipsoid', '-q', '-o', renderPng]);
  if (!check('ridge render', r.code === 0, r.code === 0 ? renderPng : `exit ${r.code}: ${r.stderr.trim()}`)) return;
  const render = analyse(await decodeImage(decoder, readFileSync(renderPng), 'image/png'), isColour(RENDER_SKY));
  console.log(`     ridge render: ${(100 * render.fraction).toFixed(1)} % terrain, ${render.emptyColumns} columns without terrain`);

  const diffs = [];
  let signed = 0;
  for (let x = 0; x < VIEWPORT.width; x++) {
    if (cesium.skyline[x] < 0 || render.skyline[x] < 0) continue;
    diffs.push(Math.abs(cesium.skyline[x] - render.skyline[x]));
    signed += cesium.skyline[x] - render.skyline[x];
  }
  if (!check('cesium vs ridge render: skyline columns', diffs.length >= 0.9 * VIEWPORT.width,
    `${diffs.length} of ${VIEWPORT.width} columns have terrain in both (at least 90 %)`)) return;
  diffs.sort((a, b) => a - b);
  const [median, p95, max] = [percentile(diffs, 0.5), percentile(diffs, 0.95), diffs[diffs.length - 1]];
  check('cesium vs ridge render: skyline', median <= SKYLINE_MEDIAN_PX && p95 <= SKYLINE_P95_PX,
    `|row difference| median ${median} px (at most ${SKYLINE_MEDIAN_PX}), p95 ${p95} px (at most ${SKYLINE_P95_PX}), max ${max} px, ` +
    `mean signed ${(signed / diffs.length).toFixed(2)} px (positive: Cesium's lower), vertical fov ${status.fovyDegrees.toFixed(3)}°`);
}

// ---------------------------------------------------------------------------------------------
// Quantized-mesh tiles, decoded without Cesium.

// TMS geographic tiling: two root tiles, 180/2^z degrees a side, y counted from the south.
function tmsRectangle(z, x, y) {
  const size = 180 / 2 ** z;
  return { west: -180 + x * size, south: -90 + y * size, east: -180 + (x + 1) * size, north: -90 + (y + 1) * size };
}

async function decoderPhase(ctx) {
  const { base, tileset, ridge, archive, decodeMesh } = ctx;
  const layer = await getJson(`${base}${tileset}/layer.json`);
  const maxzoom = layer.available.length - 1;
  // Every available tile at the four deepest levels, the middle one and the two coarsest (the
  // root tiles' headers decide whether Cesium draws anything at all).
  const wanted = new Set([maxzoom, maxzoom - 1, maxzoom - 2, maxzoom - 3, Math.floor(maxzoom / 2), 1, 0]);
  const tiles = [];
  for (const z of [...wanted].filter((z) => z >= 0).sort((a, b) => a - b)) {
    for (const range of layer.available[z]) {
      for (let x = range.startX; x <= range.endX; x++) {
        for (let y = range.startY; y <= range.endY; y++) tiles.push({ z, x, y });
      }
    }
  }
  const template = `${base}${tileset}/${layer.tiles[0].replace('{version}', layer.version)}`;
  let gzipped = 0;
  for (const t of tiles) {
    const url = template.replace('{z}', t.z).replace('{x}', t.x).replace('{y}', t.y);
    const r = await httpGet(url, { Accept: CESIUM_ACCEPT, 'Accept-Encoding': 'gzip' });
    if (r.status !== 200) throw new Error(`${url}: HTTP ${r.status}`);
    const gzip = r.headers['content-encoding'] === 'gzip';
    if (gzip) gzipped++;
    const body = gzip ? gunzipSync(r.body) : r.body;
    t.claimed = Number(r.headers['x-ridge-claimed-error']);
    const mesh = decodeMesh(body.buffer.slice(body.byteOffset, body.byteOffset + body.length));
    const n = mesh.vertexData.length / 3;
    const { minHeight, maxHeight } = mesh.header;
    const rect = tmsRectangle(t.z, t.x, t.y);
    t.step = (maxHeight - minHeight) / 32767;
    t.header = mesh.header;
    t.extensions = Object.keys(mesh.extensions ?? {});
    t.u = mesh.vertexData.subarray(0, n);
    t.v = mesh.vertexData.subarray(n, 2 * n);
    t.h = Array.from(mesh.vertexData.subarray(2 * n), (q) => minHeight + q * t.step);
    t.lonlat = Array.from(t.u, (u, i) => [rect.west + (u / 32767) * (rect.east - rect.west), rect.south + (t.v[i] / 32767) * (rect.north - rect.south)]);
    t.edges = { west: mesh.westIndices, east: mesh.eastIndices, south: mesh.southIndices, north: mesh.northIndices };
  }
  const levels = [...new Set(tiles.map((t) => t.z))].join(', ');
  check('terrain tiles: gzip, claimed error, extensions',
    gzipped === tiles.length && tiles.every((t) => Number.isFinite(t.claimed)) && tiles.every((t) => t.extensions.length === 3),
    `${tiles.length} tiles (zoom ${levels}): ${gzipped} gzip-encoded, ${tiles.filter((t) => Number.isFinite(t.claimed)).length} with X-Ridge-Claimed-Error, ` +
    `extensions ${[...new Set(tiles.map((t) => t.extensions.join('+')))].join(' / ')}`);

  // Every vertex against the archive: |vertex − archive| ≤ claimed error + slack.
  const heights = await archiveHeights(ridge, archive, tiles.flatMap((t) => t.lonlat));
  let k = 0;
  let checked = 0;
  let off = 0;
  let bad = 0;
  let worst = { margin: Infinity };
  let maxError = 0;
  for (const t of tiles) {
    for (let i = 0; i < t.h.length; i++, k++) {
      if (heights[k] === null) {
        off++;
        continue;
      }
      checked++;
      const error = Math.abs(t.h[i] - heights[k]);
      maxError = Math.max(maxError, error);
      const margin = t.claimed + HEIGHT_SLACK - error;
      if (margin < 0) bad++;
      if (margin < worst.margin) worst = { margin, error, claimed: t.claimed, tile: `${t.z}/${t.x}/${t.y}`, at: t.lonlat[i] };
    }
  }
  check('terrain tiles: vertex heights within X-Ridge-Claimed-Error', checked > 0 && bad === 0,
    `${checked} vertices checked (${off} off the archive skipped), ${bad} outside; largest |error| ${maxError.toFixed(3)} m; ` +
    `worst margin ${worst.margin.toFixed(3)} m (|error| ${worst.error?.toFixed(3)} m of ${worst.claimed} m claimed, tile ${worst.tile} at ${worst.at?.map((v) => v.toFixed(5))})`);

  // Shared edges of neighbours at the same zoom: the same vertex positions along the edge, and
  // heights within the two tiles' quantization steps.
  const byKey = new Map(tiles.map((t) => [`${t.z}/${t.x}/${t.y}`, t]));
  // The edge's vertices, keyed by their position along it (v on west/east edges, u on south/north).
  const edgeOf = (t, side) => {
    const [along, coordinate, value] = { west: ['v', 'u', 0], east: ['v', 'u', 32767], south: ['u', 'v', 0], north: ['u', 'v', 32767] }[side];
    const idx = Array.from(t.edges[side]);
    return { offEdge: idx.filter((i) => t[coordinate][i] !== value).length, heights: new Map(idx.map((i) => [t[along][i], t.h[i]])) };
  };
  let pairs = 0;
  let edgeVertices = 0;
  let worstRatio = 0; // |height difference| / (step_a + step_b) over the pairs that agree
  const badPairs = [];
  for (const a of tiles) {
    for (const [dx, dy, sideA, sideB] of [[1, 0, 'east', 'west'], [0, 1, 'north', 'south']]) {
      const b = byKey.get(`${a.z}/${a.x + dx}/${a.y + dy}`);
      if (!b) continue;
      pairs++;
      const ea = edgeOf(a, sideA);
      const eb = edgeOf(b, sideB);
      const unmatched = [...ea.heights.keys()].filter((p) => !eb.heights.has(p)).length + [...eb.heights.keys()].filter((p) => !ea.heights.has(p)).length;
      const positionsAgree = ea.offEdge === 0 && eb.offEdge === 0 && unmatched === 0;
      let difference = 0;
      for (const [p, ha] of ea.heights) {
        if (!eb.heights.has(p)) continue;
        edgeVertices++;
        difference = Math.max(difference, Math.abs(ha - eb.heights.get(p)));
      }
      const ratio = difference === 0 ? 0 : difference / (a.step + b.step);
      if (!positionsAgree || ratio > 1) {
        badPairs.push(`${a.z}/${a.x}/${a.y} ${sideA} edge: ${positionsAgree ? '' : `${ea.offEdge + eb.offEdge} edge indices off the edge, ${unmatched} of ${ea.heights.size} + ${eb.heights.size} vertices without a partner, `}heights up to ${difference.toFixed(3)} m apart (steps ${a.step.toFixed(4)} + ${b.step.toFixed(4)} m)`);
      } else {
        worstRatio = Math.max(worstRatio, ratio);
      }
    }
  }
  check('terrain tiles: shared edges', pairs > 0 && badPairs.length === 0,
    `${pairs} neighbour pairs, ${edgeVertices} shared edge vertices; ${badPairs.length} pairs disagree${badPairs.length ? ` (${badPairs.join('; ')})` : ''}; ` +
    `the others within ${worstRatio.toFixed(3)} of the two tiles' steps (at most 1)`);

  // Headers: every vertex inside the bounding sphere, and the horizon occlusion point visible from
  // 10 km above the tile's data (CesiumJS culls a tile whose point is below its horizon).
  const problems = [];
  for (const t of tiles) {
    const hd = t.header;
    const centre = [hd.boundingSphereCenterX, hd.boundingSphereCenterY, hd.boundingSphereCenterZ];
    const outside = t.lonlat.some(([lon, lat], i) => Math.hypot(...ecef(lon, lat, t.h[i]).map((c, j) => c - centre[j])) > hd.boundingSphereRadius * (1 + 1e-9) + 1);
    if (outside) problems.push(`${t.z}/${t.x}/${t.y}: a vertex outside the bounding sphere`);
    // Above the part of the tile that has data (the whole tile when it has none).
    const rect = tmsRectangle(t.z, t.x, t.y);
    const [west, south, east, north] = ctx.bounds;
    const overlaps = west < rect.east && east > rect.west && south < rect.north && north > rect.south;
    const [w, s, e, n] = overlaps
      ? [Math.max(west, rect.west), Math.max(south, rect.south), Math.min(east, rect.east), Math.min(north, rect.north)]
      : [rect.west, rect.south, rect.east, rect.north];
    const [lon, lat] = [(w + e) / 2, (s + n) / 2];
    const eye = ecef(lon, lat, hd.maxHeight + 10000);
    const hop = [hd.horizonOcclusionPointX, hd.horizonOcclusionPointY, hd.horizonOcclusionPointZ];
    if (!scaledPointVisible(eye, hop)) problems.push(`${t.z}/${t.x}/${t.y}: horizon occlusion point (${hop.join(', ')}) hidden from 10 km above ${lon.toFixed(3)}, ${lat.toFixed(3)}`);
  }
  check('terrain tiles: headers (bounding sphere, horizon occlusion point)', problems.length === 0,
    problems.length ? problems.join('; ') : `${tiles.length} tiles`);
}

// ---------------------------------------------------------------------------------------------
// MapLibre and terrain-RGB tiles.

async function maplibrePhase(ctx) {
  const { context, decoder, base, tileset, out } = ctx;
  for (const [encoding, format, file] of [['mapbox', 'png', 'maplibre.png'], ['terrarium', 'webp', 'maplibre-terrarium-webp.png']]) {
    const url = `${base}maplibre.html?test=1&tileset=${tileset}&encoding=${encoding}&format=${format}&${cameraQuery(CAMERA)}`;
    const { page, status, ok } = await openViewer(context, `maplibre ${encoding} ${format}`, url, 180_000);
    if (!ok) continue;
    // The page takes its tile URLs from ENCODING.json[?format=webp]: they must be the format asked for.
    check(`maplibre ${encoding} ${format}: tile URLs`, status.tiles.every((t) => t.includes(`/${encoding}/{z}/{x}/{y}.${format}`)), status.tiles.join(' '));
    const shot = await page.screenshot({ path: join(out, file) });
    await page.close();
    checkDrawn(`maplibre ${encoding} ${format}`, analyse(await decodeImage(decoder, shot, 'image/png'), isMagenta));
  }
}

// Web Mercator XYZ: the lon/lat of a pixel centre.
function mercatorLonLat(z, x, y, size, i, j) {
  const n = 2 ** z;
  const lon = ((x + (i + 0.5) / size) / n) * 360 - 180;
  const lat = (Math.atan(Math.sinh(Math.PI * (1 - (2 * (y + (j + 0.5) / size)) / n))) * 180) / Math.PI;
  return [lon, lat];
}

function mercatorTile(z, lon, lat) {
  const n = 2 ** z;
  const r = (lat * Math.PI) / 180;
  return [Math.floor(((lon + 180) / 360) * n), Math.floor(((1 - Math.log(Math.tan(r) + 1 / Math.cos(r)) / Math.PI) / 2) * n)];
}

const DECODE = {
  mapbox: (d, i) => -10000 + (d[i] * 65536 + d[i + 1] * 256 + d[i + 2]) * 0.1,
  terrarium: (d, i) => d[i] * 256 + d[i + 1] + d[i + 2] / 256 - 32768,
};

async function rgbPhase(ctx) {
  const { decoder, base, tileset, ridge, archive, bounds } = ctx;
  const [west, south, east, north] = bounds;
  // Every tile over the bounds at the deepest zoom and two zooms up, and the 512 px tiles at their
  // deepest; each in both encodings and both formats.
  const tiles = [];
  const nativeStep = {};
  for (const encoding of ['mapbox', 'terrarium']) nativeStep[encoding] = (await getJson(`${base}${tileset}/${encoding}.json`)).ridge.nativeStep;
  for (const hidpi of ['', '@2x']) {
    const tj = await getJson(`${base}${tileset}/mapbox${hidpi}.json`);
    for (const z of hidpi ? [tj.maxzoom] : [tj.maxzoom, tj.maxzoom - 2]) {
      const [x0, y0] = mercatorTile(z, west, north);
      const [x1, y1] = mercatorTile(z, east, south);
      for (let x = x0; x <= x1; x++) for (let y = y0; y <= y1; y++) tiles.push({ hidpi, size: tj.tileSize, z, x, y });
    }
  }
  // The pixel centres inside the archive, queried once for all encodings and formats.
  const points = [];
  for (const s of tiles) {
    s.pixels = [];
    for (let j = 0; j < s.size; j++) {
      for (let i = 0; i < s.size; i++) {
        const [lon, lat] = mercatorLonLat(s.z, s.x, s.y, s.size, i, j);
        if (lon < west || lon > east || lat < south || lat > north) continue;
        s.pixels.push({ index: j * s.size + i, point: points.length });
        points.push([lon, lat]);
      }
    }
  }
  const heights = await archiveHeights(ridge, archive, points);

  for (const encoding of ['mapbox', 'terrarium']) {
    for (const format of ['png', 'webp']) {
      let fetched = 0;
      let checked = 0;
      let off = 0;
      let bad = 0;
      let transparent = 0;
      let worst = { ratio: -1 };
      let strict = 0; // pixels beyond step/2 + archive error, the bound as stated
      let excess = 0;
      const steps = new Set();
      for (const s of tiles) {
        const url = `${base}${tileset}/${encoding}${s.hidpi}/${s.z}/${s.x}/${s.y}.${format}`;
        const r = await httpGet(url);
        if (r.status !== 200) throw new Error(`${url}: HTTP ${r.status}`);
        const stated = Number(r.headers['x-ridge-step']);
        const archiveError = Number(r.headers['x-ridge-archive-error']);
        if (!Number.isFinite(stated) || !Number.isFinite(archiveError)) throw new Error(`${url}: no X-Ridge-Step / X-Ridge-Archive-Error header`);
        // The header has 3 decimals (terrarium's 1/256 m reads 0.004); the step is the TileJSON's
        // native step times the power of two it rounds.
        const step = nativeStep[encoding] * 2 ** Math.round(Math.log2(stated / nativeStep[encoding]));
        steps.add(step);
        const img = await decodeImage(decoder, r.body, r.headers['content-type']);
        if (img.width !== s.size || img.height !== s.size) throw new Error(`${url}: ${img.width}x${img.height}, not ${s.size} px`);
        fetched++;
        const bound = step / 2 + archiveError;
        const tolerance = bound + HEIGHT_SLACK;
        for (const { index, point } of s.pixels) {
          if (heights[point] === null) {
            off++;
            continue;
          }
          if (img.data[index * 4 + 3] !== 255) transparent++;
          checked++;
          const error = Math.abs(DECODE[encoding](img.data, index * 4) - heights[point]);
          if (error > tolerance) bad++;
          if (error > bound) {
            strict++;
            excess = Math.max(excess, error - bound);
          }
          if (error / tolerance > worst.ratio) worst = { ratio: error / tolerance, error, tolerance, tile: `${s.z}/${s.x}/${s.y}${s.hidpi}` };
        }
      }
      check(`terrain-RGB ${encoding} ${format}: pixel heights within X-Ridge-Step/2 + X-Ridge-Archive-Error`,
        checked > 0 && bad === 0 && transparent === 0,
        `${fetched} tiles, ${checked} pixels inside the archive (${off} off it skipped), ${bad} outside, ${transparent} not opaque; ` +
        `steps ${[...steps].join(', ')} m; worst |error| ${worst.error?.toFixed(5)} m = ${worst.ratio.toFixed(3)} of its tolerance ${worst.tolerance?.toFixed(5)} m (tile ${worst.tile}); ` +
        `${strict} pixels beyond step/2 + archive error without the slack, by at most ${(excess * 1000).toFixed(3)} mm`);
    }
  }
}

// ---------------------------------------------------------------------------------------------

const PHASES = { cesium: cesiumPhase, decoder: decoderPhase, maplibre: maplibrePhase, rgb: rgbPhase };

async function main() {
  const { values } = parseArgs({
    options: {
      ridge: { type: 'string' },
      archive: { type: 'string' },
      out: { type: 'string' },
      timeout: { type: 'string', default: '480' },
      phases: { type: 'string', default: Object.keys(PHASES).join(',') },
    },
  });
  for (const k of ['ridge', 'archive', 'out']) if (!values[k]) usage(`--${k} is required`);
  const [ridge, archive, out] = [resolve(values.ridge), resolve(values.archive), resolve(values.out)];
  if (!existsSync(ridge)) usage(`no ${ridge}`);
  if (!existsSync(archive)) usage(`no ${archive}`);
  const timeoutMs = Number(values.timeout) * 1000;
  if (!(timeoutMs > 0)) usage(`--timeout ${values.timeout}: seconds`);
  const phases = values.phases.split(',');
  for (const p of phases) if (!(p in PHASES)) usage(`--phases: no phase ${p} (${Object.keys(PHASES).join(', ')})`);

  const executablePath = process.env.CHROMIUM ?? CHROMIUM_PATHS.find(existsSync);
  if (!executablePath || !existsSync(executablePath)) skip('no chromium (scripts/install-web-deps.sh)');
  // The test's own packages come from web/node_modules, where the pages' come from.
  const webRequire = createRequire(join(webDir, 'package.json'));
  let chromium;
  let decodeMesh;
  try {
    for (const file of ['cesium/Build/Cesium/Cesium.js', 'maplibre-gl/dist/maplibre-gl.mjs']) {
      if (!existsSync(join(webDir, 'node_modules', file))) throw new Error(`no web/node_modules/${file}`);
    }
    ({ chromium } = await import(pathToFileURL(join(webDir, 'node_modules/playwright-core/index.mjs')).href)); // its ES module entry
    decodeMesh = (await import(pathToFileURL(webRequire.resolve('@here/quantized-mesh-decoder')).href)).default.default;
  } catch (e) {
    skip(`web/node_modules incomplete (scripts/install-web-deps.sh): ${e.message.split('\n')[0]}`);
  }
  mkdirSync(out, { recursive: true });

  const server = startServer(ridge, archive);
  let browser;
  let cleaning; // one cleanup, however many ways out run at once (the time limit and main's end)
  const cleanup = () => (cleaning ??= (async () => {
    await Promise.race([browser?.close(), new Promise((r) => setTimeout(r, 10_000))]);
    await stopServer(server);
  })());
  const finish = async (code) => {
    await cleanup();
    if (code !== 0 && server.log.length) console.log(`ridge serve log (last lines):\n  ${server.log.slice(-8).join('\n  ')}`);
    console.log(`${failures.length ? `FAILED (${failures.length}): ${failures.join('; ')}` : 'all checks passed'} in ${seconds(Date.now() - t0)}`);
    process.exit(code);
  };
  // Bounded time, and the server killed on every way out.
  setTimeout(() => { check('time limit', false, `not done after ${values.timeout} s`); finish(1); }, timeoutMs).unref();
  for (const signal of ['SIGINT', 'SIGTERM']) process.on(signal, () => { check('run', false, `interrupted (${signal})`); finish(1); });

  try {
    const base = await server.url;
    const tileset = basename(archive).replace(/\.ridge$/, '');
    const { tilesets } = await getJson(`${base}tilesets.json`);
    const bounds = tilesets.find((t) => t.name === tileset)?.bounds;
    if (!bounds) throw new Error(`${tileset} not in ${base}tilesets.json`);
    console.log(`ridge serve at ${base}, tileset ${tileset}, camera ${JSON.stringify(CAMERA)}; chromium ${executablePath}`);

    const launched = Date.now();
    // Signals are this script's to handle (it closes the browser, then stops the server).
    browser = await chromium.launch({ executablePath, headless: true, args: CHROMIUM_ARGS, timeout: 60_000, handleSIGINT: false, handleSIGTERM: false, handleSIGHUP: false });
    const context = await browser.newContext({ viewport: VIEWPORT, deviceScaleFactor: 1 });
    const decoder = await context.newPage();
    console.log(`chromium ${browser.version()} started in ${seconds(Date.now() - launched)}`);

    const ctx = { context, decoder, base, tileset, bounds, ridge, archive, out, decodeMesh };
    for (const [name, body] of Object.entries(PHASES)) if (phases.includes(name)) await phase(name, () => body(ctx));
  } catch (e) {
    check('run', false, e.stack ?? String(e));
  }
  await finish(failures.length ? 1 : 0);
}

main();
