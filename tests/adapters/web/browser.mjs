// The web package in a real browser (tests/adapters/web/browser.sh): headless Chromium (WebGL 2 on
// SwiftShader), driven by puppeteer-core, draws with a scene's per-sample stages, with the
// inputs that halo-render --export-host wrote for the same scene, camera and volume:
//   - examples/hosts/raycast.frag linked in the page (tests/adapters/web/raycast.html);
//   - the web package's three.js ray caster with the stages put in by installHalo
//     (adapters/web/three.mjs, tests/adapters/web/three.html), drawn by three.js.
// Each image must be within LIMIT (mean abs) of halo-render's; the viewer without libhalo
// must differ from it by more than EFFECT (the stages are visible); a deliberately wrong
// reference must fail; in three.js, the stages installed and removed again must give the
// caster alone (max abs 0). A scene given as one-draw:SCENE is host contract 3: linked
// with oneDraw, its halo field computed by libhalo's C runtime in WebAssembly on the page's
// WebGL 2 context (three's in three.js: installHalo's stages.render), the ray caster drawn
// once; its reference is halo-render --one-draw's. In raycast.html the one-draw frame also
// draws after the context was lost (frame.draw says so) and restored (WEBGL_lose_context):
// the same frame object, the page's objects made again, the same image (max abs 0). A SCENE
// from / is the case folder's (/in/). A scene with outlines (extra outputs, the passes after
// the draw): frame.post in raycast.html, installHalo's stages.render in the three.js caster.
// In the three.js caster, NiiVue and vtk.js a halo field over its cap is linked again at 1/2
// (fieldCap).
//   node browser.mjs CASE_DIR SCENE [CASE_DIR SCENE]...   (environment: srcdir,
//   HALO_WEB_PACKAGE, HALO_CHROMIUM, HALO_WEB_LIMIT)
import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';

const require = createRequire(path.join(path.resolve(process.env.HALO_WEB_MODULES), 'package.json'));
const puppeteer = require('puppeteer-core');
const srcdir = path.resolve(process.env.srcdir);
const packageDir = path.resolve(process.env.HALO_WEB_PACKAGE);
const modulesDir = path.resolve(process.env.HALO_WEB_MODULES);
const LIMIT = Number(process.env.HALO_WEB_LIMIT || 1e-4);
const EFFECT = 0.01;
// a viewer set up as raycast.frag samples against halo-render's image clamped to [0, 1] (a
// canvas holds 8 bits a channel; tone shading lights past 1), its transfer functions sampled
// into its own textures
const MATCH_LIMIT = Number(process.env.HALO_WEB_MATCH_LIMIT || 2e-3);
const cases = [];
for (let i = 2; i + 1 < process.argv.length + 1; i += 2) {
  const oneDraw = process.argv[i + 1].startsWith('one-draw:');
  cases.push({ dir: path.resolve(process.argv[i]), scene: process.argv[i + 1].replace(/^one-draw:/, ''), oneDraw });
}

const types = { '.html': 'text/html', '.mjs': 'text/javascript', '.js': 'text/javascript', '.wasm': 'application/wasm',
  '.json': 'application/json' };
let inputs = null; // the case being drawn: its folder is /in/
const server = http.createServer((request, response) => {
  const url = decodeURIComponent(new URL(request.url, 'http://localhost').pathname);
  const roots = [['/pkg/', packageDir], ['/src/', srcdir], ['/in/', inputs], ['/modules/', modulesDir],
    ['/', path.join(srcdir, 'tests/adapters/web')]];
  for (const [prefix, root] of roots) {
    if (!url.startsWith(prefix) || !root) continue;
    const file = path.resolve(root, url.slice(prefix.length) || 'raycast.html');
    if (!file.startsWith(root + path.sep) || !fs.existsSync(file) || !fs.statSync(file).isFile()) break;
    response.writeHead(200, { 'content-type': types[path.extname(file)] || 'application/octet-stream' });
    fs.createReadStream(file).pipe(response);
    return;
  }
  response.writeHead(404);
  response.end();
});
await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve)); // loopback only
const origin = `http://127.0.0.1:${server.address().port}`;

function difference(a, b) {
  let sum = 0, max = 0;
  for (let i = 0; i < a.length; ++i) {
    const d = Math.abs(a[i] - b[i]);
    if (!(d <= max)) max = Number.isNaN(d) ? Infinity : d;
    sum += Number.isNaN(d) ? Infinity : d;
  }
  return { mean: sum / a.length, max };
}

let failures = 0, drawn = 0;

// An image for a look (HALO_WEB_SAVE): a PAM of its RGBA values times scale (255 for values
// in [0, 1], 1 for bytes), its rows turned top first (WebGL reads the bottom row first).
function savePam(name, values, width, height, scale) {
  const rows = [];
  for (let y = height - 1; y >= 0; --y)
    rows.push(Buffer.from(Array.from(values.slice(y * width * 4, (y + 1) * width * 4), (v) => Math.round(v * scale))));
  fs.writeFileSync(path.join(process.env.HALO_WEB_SAVE, `${name}.pam`), Buffer.concat([Buffer.from(
    `P7\nWIDTH ${width}\nHEIGHT ${height}\nDEPTH 4\nMAXVAL 255\nTUPLTYPE RGB_ALPHA\nENDHDR\n`), ...rows]));
}

// A halo field over its cap (fieldMaxBytes) in an adapter: linked again at 1/2 with a
// warning, drawn as the same scene installed with imageScale 2 (max abs 0); an explicit
// imageScale over the cap is refused, not linked again. render(options) draws in the page
// (the adapter's options: fieldMaxBytes, imageScale; repeat) and resolves to { pixels,
// warnings, imageScale } or rejects with the adapter's error; full: the scene's image at
// full size (it must differ: the scale is seen).
async function fieldCap(name, render, full) {
  // the field's bytes at 1/2 from the refusal of an explicit scale over a cap of one byte
  const probe = await render({ imageScale: 2, fieldMaxBytes: 1 }).then((r) => r.warnings.join(' / '), (e) => String(e.message || e));
  const m = /halo field of (\d+) layers .*?\((\d+) bytes a layer/.exec(probe);
  if (!m || /linked again/.test(probe)) {
    fail(`${name}: imageScale 2 over a cap of one byte: not refused with the field's size (${probe.slice(0, 300)})`);
    return;
  }
  const cap = Math.floor(Number(m[1]) * Number(m[2]) * 1.25); // 1/2 fits, full size (4x) does not
  let capped, explicit;
  try {
    capped = await render({ fieldMaxBytes: cap, repeat: 3 });
    explicit = await render({ imageScale: 2, repeat: 3 });
  } catch (e) {
    fail(`${name}: a field over a cap of ${cap} bytes: ${e.message || e}`);
    return;
  }
  const same = difference(capped.pixels, explicit.pixels), scale = difference(capped.pixels, full.pixels);
  const warning = capped.warnings.find((w) => /FIELD_MEMORY|over field_max_bytes/.test(w) && /linked again/.test(w)) || '';
  console.log(`${name}: the field over a cap of ${cap} bytes: linked again at 1/${capped.imageScale} ("${warning.slice(0, 160)}..."); ` +
    `against imageScale 2 max abs ${same.max}, against full size mean abs ${scale.mean.toExponential(3)} (must differ)`);
  if (capped.imageScale !== 2 || !warning) fail(`${name}: a field over its cap was not linked again at 1/2 with a warning`);
  if (!(same.max === 0)) fail(`${name}: the field over its cap draws ${same.max} from imageScale 2's image`);
  if (!(scale.mean > 0)) fail(`${name}: 1/2 and full size give the same image: the test sees no scale`);
  if (explicit.warnings.length) fail(`${name}, imageScale 2: ${explicit.warnings.join(' / ')}`);
}

// NiiVue and vtk.js (their pinned versions in package.json) with the MRI head that
// halo-render exported (HALO_WEB_MRI: host.json and volume.f32, written here as NIfTI-1 for
// the viewers to read), each through the package's adapter (HALO_WEB_ENGINES: niivue,
// vtkjs). A viewer's own renderer is not raycast.frag (its jitter, its empty-space pass, its
// transfer functions and opacity correction), so its image is compared with the viewer's
// own: the stages must be visible, the halos alone must be visible (the scene against itself
// without its halo_* stages), the halo field must matter (M = 1 against the scene's M), and
// removed again they must give the viewer alone exactly.
const mriCase = process.env.HALO_WEB_MRI ? path.resolve(process.env.HALO_WEB_MRI) : null;
const engines = (process.env.HALO_WEB_ENGINES || '').split(/\s+/).filter(Boolean);
function writeNifti(dir) {
  const host = JSON.parse(fs.readFileSync(path.join(dir, 'host.json')));
  const data = fs.readFileSync(path.join(dir, 'volume.f32'));
  const header = Buffer.alloc(352);
  header.writeInt32LE(348, 0);
  [3, ...host.dims, 1, 1, 1, 1].forEach((v, i) => header.writeInt16LE(v, 40 + 2 * i));
  header.writeInt16LE(16, 70); // float32
  header.writeInt16LE(32, 72);
  [1, 1, 1, 1, 1, 1, 1, 1].forEach((v, i) => header.writeFloatLE(v, 76 + 4 * i));
  header.writeFloatLE(352, 108); // vox_offset
  header.writeFloatLE(1, 112); // scl_slope
  header.writeFloatLE(1, 124); // cal_max (cal_min 0): the values are halo-render's, in [0, 1]
  header.writeInt16LE(1, 254); // sform_code: the identity below
  [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]].forEach((row, r) => row.forEach((v, c) => header.writeFloatLE(v, 280 + 16 * r + 4 * c)));
  header.write('n+1\0', 344, 'latin1');
  fs.writeFileSync(path.join(dir, 'head.nii'), Buffer.concat([header, data]));
}
// The demo page (docs/web/index.html, served by docs/web/serve.mjs as a user runs it): it
// loads, makes its sliders from the reflection, a slider changes the image, and the stages
// switched off give NiiVue alone.
async function demo(page, volume) {
  const { spawn } = await import('node:child_process');
  const serve = spawn(process.execPath, [path.join(srcdir, 'docs/web/serve.mjs'), volume, '0'],
    { env: { ...process.env, HALO_BUILD: path.resolve(packageDir, '../../..') }, stdio: ['ignore', 'pipe', 'inherit'] });
  try {
    const url = await new Promise((resolve, reject) => {
      serve.stdout.on('data', (d) => { const m = /http:\/\/[\d.:]+\//.exec(String(d)); if (m) resolve(m[0]); });
      serve.on('exit', (code) => reject(new Error(`serve.mjs exited with ${code}`)));
      setTimeout(() => reject(new Error('serve.mjs printed no address in 30 s')), 30000);
    });
    // the server refuses what is outside its roots, and survives a malformed request
    for (const [bad, status] of [['/..%2f..%2fconfigure.ac', 404], ['/pkg/..%2f..%2f..%2fconfigure.ac', 404], ['/%E0%A4%A', 400]]) {
      const got = (await fetch(url + bad.slice(1))).status;
      if (got !== status) fail(`docs/web/serve.mjs: ${bad} answered ${got}, not ${status}`);
    }
    await page.goto(url);
    await page.waitForFunction('window.demo && window.demo.ready', { timeout: 120000 });
    const state = await page.evaluate(() => ({ error: window.demo.error, sliders: window.demo.sliders }));
    const name = 'the demo page (docs/web/index.html)';
    if (state.error) { fail(`${name}: ${state.error}`); return; }
    const before = await page.evaluate(() => window.demo.pixels());
    await page.evaluate(() => { // halo_map.opacity[1], the dark halo, to 1
      const input = [...document.querySelectorAll('label')].find((l) => l.textContent.startsWith('halo_map.opacity[1]'))
        .querySelector('input');
      input.value = '1';
      input.dispatchEvent(new Event('input'));
    });
    const after = await page.evaluate(() => window.demo.pixels());
    await page.evaluate(() => { const box = document.getElementById('enabled'); box.checked = false; box.dispatchEvent(new Event('change')); });
    const off = await page.evaluate(() => window.demo.pixels());
    const slider = difference(after.map((v) => v / 255), before.map((v) => v / 255));
    const stages = difference(before.map((v) => v / 255), off.map((v) => v / 255));
    console.log(`${name}: ${state.sliders.length} sliders; halo_map.opacity[1] 0.3 -> 1 changes the image by ${slider.mean.toExponential(3)} ` +
      `mean abs; the stages against NiiVue alone ${stages.mean.toExponential(3)}`);
    if (!state.sliders.includes('halo_map.opacity[1]') || state.sliders.length < 8) fail(`${name}: sliders ${state.sliders}`);
    if (!(slider.mean > 1e-3)) fail(`${name}: the halo opacity slider changes the image by only ${slider.mean}`);
    if (!(stages.mean > EFFECT)) fail(`${name}: the stages change NiiVue's image by only ${stages.mean}`);
    drawn++;
  } finally {
    serve.kill();
  }
}

// A viewer that cannot be set up as raycast.frag samples (NiiVue: it classifies before it
// interpolates, jitters, skips empty space) against libhalo's C runtime drawing a host in its
// style (examples/hosts/niivue_caster.frag) with the viewer's own inputs: the camera the
// adapter gave libhalo, the viewer's classified volume, each pixel's jitter as the page's GPU
// computes it and the background (exported by the page with the frame), the values
// halo-render exported (dir); the step is NiiVue's, which the reference derives. The scene's
// stages without halo_* (images.noHalos), and with its halos drawn once (images.staged).
// Compared over the pixels the volume covers, the reference rounded to 8 bits as the canvas:
// what is left is a level or two either way over the head (SwiftShader's filtering and 8-bit
// blending against llvmpipe's floats), hence the limit. Controls that must fail: the image
// shifted by a row, the reference without NiiVue's jitter and without its empty-space pass,
// the viewer alone against the stages' reference, the field at M = 1 against the scene's M.
const REDRAW_LIMIT = Number(process.env.HALO_WEB_REDRAW_LIMIT || 4.5e-3);
async function redrawn(name, program, dir, images, featuresScene) {
  const { execFileSync } = await import('node:child_process');
  // what: the folder's name; control: { zeroJitter, emptySpacePass } for the controls
  const draw = (what, image, sceneFile, control = {}) => {
    const out = path.join(dir, `redrawn-${what}`);
    fs.mkdirSync(out, { recursive: true });
    const r = image.reference;
    if (!r) { fail(`${name}, ${what}: the page exported nothing to draw again`); return null; }
    if (image.imageScale !== 1) fail(`${name}, ${what}: the page drew its halo images at 1/${image.imageScale}`);
    fs.writeFileSync(path.join(out, 'view.txt'), `size ${r.view.width} ${r.view.height}\ndims ${r.dims.join(' ')}\n` +
      `background ${r.background.join(' ')}\ninverse ${r.view.inverseViewProjection.join(' ')}\n` +
      (control.emptySpacePass !== undefined ? `empty_space_pass ${control.emptySpacePass}\n` : ''));
    fs.writeFileSync(path.join(out, 'color.u8'), Buffer.from(r.color, 'base64'));
    const jitter = Buffer.from(r.jitter, 'base64');
    if (control.zeroJitter) jitter.fill(0);
    if (process.env.HALO_WEB_REDRAW_HASH) fs.rmSync(path.join(out, 'jitter.f32'), { force: true }); // the jitter computed there
    else fs.writeFileSync(path.join(out, 'jitter.f32'), jitter);
    fs.copyFileSync(path.join(dir, 'volume.f32'), path.join(out, 'volume.f32'));
    try {
      execFileSync(program, [sceneFile, out, path.join(out, 'image.f32')], { stdio: ['ignore', 'inherit', 'inherit'] });
    } catch (e) {
      fail(`${name}, ${what}: ${program} failed (${e.message})`);
      return null;
    }
    // as the canvas holds it: 8 bits a channel
    return new Float32Array(fs.readFileSync(path.join(out, 'image.f32')).buffer.slice(0))
      .map((v) => Math.round((v > 0 ? (v < 1 ? v : 1) : 0) * 255) / 255);
  };
  // mean and max abs over the pixels the volume covers in either image (not the background's)
  const background = images.noHalos.reference ? images.noHalos.reference.background : [1, 1, 1];
  const covered = (a, b) => {
    let sum = 0, max = 0, n = 0;
    for (let k = 0; k < a.length; k += 4) {
      if ([0, 1, 2].every((c) => Math.abs(a[k + c] - background[c]) < 0.5 / 255 && Math.abs(b[k + c] - background[c]) < 0.5 / 255))
        continue;
      ++n;
      for (let c = 0; c < 4; ++c) {
        const d = Math.abs(a[k + c] - b[k + c]);
        sum += d;
        max = d > max ? d : max;
      }
    }
    return { mean: n ? sum / (4 * n) : Infinity, max, pixels: n };
  };
  const stagesScene = path.join(dir, 'stages.json');
  const full = JSON.parse(fs.readFileSync(path.join(srcdir, 'examples/scenes/mri-head.json')));
  fs.writeFileSync(stagesScene, JSON.stringify({ ...full,
    stages: full.stages.filter((st) => !Object.keys(st).some((k) => k.startsWith('halo_'))) }));
  const haloScene = path.join(srcdir, 'examples/scenes/mri-head.json');
  const withStages = draw('stages', images.noHalos, stagesScene);
  const withHalos = draw('halos', images.staged, haloScene);
  const withFeatures = images.features && featuresScene ? draw('features', images.features, featuresScene) : null;
  if (!withStages || !withHalos) return;
  if (process.env.HALO_WEB_SAVE) {
    savePam('niivue-redrawn-stages', withStages, images.noHalos.width, images.noHalos.height, 255);
    savePam('niivue-redrawn-halos', withHalos, images.staged.width, images.staged.height, 255);
    if (withFeatures) savePam('niivue-redrawn-features', withFeatures, images.features.width, images.features.height, 255);
  }
  const width = images.staged.width;
  for (const [what, image, ref, limit = REDRAW_LIMIT] of [['its stages without halo_*', images.noHalos, withStages],
    ['its stages and halos, drawn once', images.staged, withHalos],
    // feature halos raise opacity beside features: on the rim a ray of one renderer meets a
    // sample and the other's does not (17 pixels over 20 levels apart), hence twice the limit
    ...(withFeatures ? [['its stages without halo_* and with feature halos', images.features, withFeatures, 2 * REDRAW_LIMIT]] : [])]) {
    if (image.pixels.length !== ref.length) { fail(`${name}: ${image.pixels.length} values in the page, ${ref.length} redrawn`); continue; }
    const against = covered(image.pixels, ref);
    const shifted = covered(image.pixels.slice(0, ref.length - 4 * width), ref.slice(4 * width));
    console.log(`${name}, ${what}: against libhalo's C runtime drawing niivue_caster.frag with NiiVue's inputs, over the ` +
      `${against.pixels} pixels the volume covers: mean abs ${against.mean.toExponential(3)}, max abs ${against.max.toExponential(3)} ` +
      `(limit ${limit} mean); shifted by a row ${shifted.mean.toExponential(3)} (must fail)`);
    if (!(against.mean <= limit)) fail(`${name}, ${what}: ${against.mean} from the image drawn again (mean abs)`);
    if (!(shifted.mean > limit)) fail(`${name}, ${what}: the image shifted by a row passes too (${shifted.mean})`);
  }
  // controls that must fail: the reference without NiiVue's jitter, and without its
  // empty-space pass (the stages alone: NiiVue's pass is on), NiiVue alone against the
  // stages, the field at M = 1 against the scene's M
  const controls = [
    ['the stages drawn again without the jitter', images.noHalos, draw('control-jitter', images.noHalos, stagesScene, { zeroJitter: true })],
    ['the stages drawn again without the empty-space pass', images.noHalos,
      draw('control-empty', images.noHalos, stagesScene, { emptySpacePass: 0 })],
    ['NiiVue alone against the stages drawn again', images.alone, withStages],
    ['its field at M = 1 against the scene\'s M drawn again', images.m1, withHalos],
    ...(withFeatures ? [['its stages without feature halos against them drawn again', images.noHalos, withFeatures,
      2 * REDRAW_LIMIT]] : []),
  ];
  for (const [what, image, ref, limit = REDRAW_LIMIT] of controls) {
    if (!ref) continue;
    const d = covered(image.pixels, ref);
    console.log(`${name}: control, ${what}: mean abs ${d.mean.toExponential(3)} (must fail: limit ${limit})`);
    if (!(d.mean > limit)) fail(`${name}: control, ${what}, passes (${d.mean})`);
  }
}

const ENGINES = {
  niivue: { page: 'niivue.html', module: '@niivue/niivue', name: 'NiiVue', outlines: true, reference: 'HALO_WEB_NIIVUE_REFERENCE' },
  vtkjs: { page: 'vtkjs.html', module: 'vtk.js', name: 'vtk.js', match: true, outlines: true },
};
async function engine(page, dir, which) {
  const viewer = ENGINES[which];
  if (!viewer) { fail(`HALO_WEB_ENGINES: no viewer '${which}' (known: ${Object.keys(ENGINES).join(', ')})`); return; }
  inputs = dir;
  // a viewer that can be set up as raycast.frag samples (vtk.js) is, and is compared with
  // halo-render too
  const stagesDir = viewer.match && process.env.HALO_WEB_MRI_STAGES ? path.resolve(process.env.HALO_WEB_MRI_STAGES) : null;
  const featuresDir = process.env.HALO_WEB_MRI_FEATURES ? path.resolve(process.env.HALO_WEB_MRI_FEATURES) : null;
  const query = stagesDir ? '?match' : process.env.HALO_WEB_SIZE ? `?size=${process.env.HALO_WEB_SIZE}` : '';
  await page.goto(`${origin}/${viewer.page}${query}`);
  await page.waitForFunction('window.ready === true', { timeout: 60000 });
  const scene = 'mri-head.json';
  const draw = (options) => page.evaluate((o) => window.render(o), options);
  const alone = await draw({ scene: null, repeat: 3 });
  // a viewer drawn again by libhalo's C runtime (NiiVue: tests/adapters/web/niivue_reference)
  // exports what that needs with these two
  const reference = viewer.reference && process.env[viewer.reference] ? process.env[viewer.reference] : null;
  const staged = await draw({ scene, repeat: 3, reference: !!reference });
  const noHalos = await draw({ scene, withoutHalos: true, repeat: 3, reference: !!reference });
  const m1 = await draw({ scene, interval: 1 });
  const removed = await draw({ scene, removed: true });
  await fieldCap(`${scene} in ${viewer.name}`, (o) => draw({ scene, ...o }), staged);
  // the stages without halo_* and with feature halos (the halo buffer splatted in the page)
  const features = featuresDir ? await draw({ scene: 'mri-features.json', repeat: 3,
    sceneJson: JSON.parse(fs.readFileSync(path.join(featuresDir, 'scene.json'))), reference: !!reference }) : null;
  // its stages and halos with outlines (the passes after the draw), where the adapter serves them
  const outlinesDir = viewer.outlines && process.env.HALO_WEB_MRI_OUTLINES ? path.resolve(process.env.HALO_WEB_MRI_OUTLINES) : null;
  const outlined = outlinesDir ? await draw({ scene: 'mri-outlines.json', repeat: 3,
    sceneJson: JSON.parse(fs.readFileSync(path.join(outlinesDir, 'scene.json'))) }) : null;
  const version = JSON.parse(fs.readFileSync(path.join(modulesDir, viewer.module, 'package.json'))).version;
  if (process.env.HALO_WEB_SAVE) // the images, for a look
    for (const [what, image] of Object.entries({ alone, staged, noHalos, m1, ...(features ? { features } : {}),
      ...(outlined ? { outlined } : {}) }))
      savePam(`${which}-${what}`, image.pixels, image.width, image.height, 255);
  const name = `${scene} in ${viewer.name} ${version} (${staged.renderer})`;
  const stages = difference(staged.pixels, alone.pixels), halos = difference(staged.pixels, noHalos.pixels);
  const field = difference(staged.pixels, m1.pixels), back = difference(removed.pixels, alone.pixels);
  console.log(`${name}: against ${viewer.name} alone mean abs ${stages.mean.toExponential(3)}; the halos (against its stages ` +
    `without halo_*) ${halos.mean.toExponential(3)}; the field at M = 1 against the scene's M ${field.mean.toExponential(3)}; ` +
    `removed against ${viewer.name} alone max abs ${back.max}; draw and read back ${staged.drawMs.toFixed(1)} ms with the stages ` +
    `and halos (${staged.stillMs.toFixed(1)} ms drawn again unchanged: the field reused), ${noHalos.drawMs.toFixed(1)} ms ` +
    `with the stages alone, ${alone.drawMs.toFixed(1)} ms ${viewer.name} alone (${alone.width}x${alone.height}; the camera ` +
    'turning between frames)');
  if (!(stages.mean > EFFECT)) fail(`${name}: the stages change ${viewer.name}'s image by only ${stages.mean}`);
  if (!(halos.mean > EFFECT / 4)) fail(`${name}: the halos change the image by only ${halos.mean}`);
  if (!(field.mean > 1e-4)) fail(`${name}: the field of other segments gives the same image (${field.mean})`);
  if (!(back.max === 0)) fail(`${name}: the stages removed again leave the image ${back.max} from ${viewer.name} alone`);
  if (features) { // the feature halos are visible, and of the size they have in halo-render's image
    const effect = difference(features.pixels, noHalos.pixels);
    const image = (d) => new Float32Array(fs.readFileSync(path.join(d, 'image.f32')).buffer.slice(0)).map((v) => (v > 0 ? (v < 1 ? v : 1) : 0));
    const theirs = difference(image(featuresDir), image(path.resolve(process.env.HALO_WEB_MRI_STAGES))).mean;
    console.log(`${name}: feature halos (against its stages without them) mean abs ${effect.mean.toExponential(3)} (in ` +
      `halo-render's images ${theirs.toExponential(3)}; the page's must be within half and twice it); draw and read back ` +
      `${features.drawMs.toFixed(1)} ms with them, ${noHalos.drawMs.toFixed(1)} ms without (the camera turning between ` +
      'frames: the buffer splatted each frame)');
    // a viewer that cannot be set up as raycast.frag (NiiVue) is checked by the size of the
    // effect: its sampler left on another texture gives 0.14 against halo-render's 0.020
    if (!(effect.mean > EFFECT / 4)) fail(`${name}: the feature halos change the image by only ${effect.mean}`);
    if (!(effect.mean >= theirs / 2 && effect.mean <= 2 * theirs))
      fail(`${name}: the feature halos change the image by ${effect.mean}, not within half and twice halo-render's ${theirs}`);
  }
  if (outlined && !stagesDir) {
    // a viewer that cannot be set up as raycast.frag (NiiVue): its outlines' lines against
    // halo-render's, by count, on the scene's background as halo-render draws it: the pixels
    // the outlines make dark (every channel under 0.15) that were not (one at 0.3 or more);
    // NiiVue's view is another, so the count must be within half and twice halo-render's
    const image = (d) => new Float32Array(fs.readFileSync(path.join(d, 'image.f32')).buffer.slice(0)).map((v) => (v > 0 ? (v < 1 ? v : 1) : 0));
    const lines = (before, after) => {
      let n = 0;
      for (let k = 0; k < after.length; k += 4)
        n += Math.max(after[k], after[k + 1], after[k + 2]) < 0.15 && Math.max(before[k], before[k + 1], before[k + 2]) >= 0.3;
      return n;
    };
    const sceneJson = JSON.parse(fs.readFileSync(path.join(outlinesDir, 'scene.json')));
    const { background } = sceneJson.render;
    const onBackground = await draw({ scene, background }), outlinedOn = await draw({ scene: 'mri-outlines.json', sceneJson, background });
    if (process.env.HALO_WEB_SAVE) {
      savePam(`${which}-outlined-on-background`, outlinedOn.pixels, outlinedOn.width, outlinedOn.height, 255);
      savePam(`${which}-staged-on-background`, onBackground.pixels, onBackground.width, onBackground.height, 255);
    }
    const ours = lines(onBackground.pixels, outlinedOn.pixels), theirs = lines(image(dir), image(outlinesDir));
    const effect = difference(outlinedOn.pixels, onBackground.pixels);
    console.log(`${name}: outlines: ${ours} pixels of lines (halo-render's image: ${theirs}; within half and twice it), ` +
      `mean abs ${effect.mean.toExponential(3)} against its stages and halos without them; draw and read back ` +
      `${outlined.drawMs.toFixed(1)} ms with them, ${staged.drawMs.toFixed(1)} ms without (the camera turning between frames)`);
    if (!(theirs > 0 && ours >= theirs / 2 && ours <= 2 * theirs))
      fail(`${name}: the outlines draw ${ours} pixels of lines, not within half and twice halo-render's ${theirs}`);
    // where the view is the background alone (its rays saw nothing), the outlines change nothing:
    // no feature where there is none (a ray NiiVue ends early writes the outputs too)
    let empty = 0, changed = 0;
    for (let k = 0; k < onBackground.pixels.length; k += 4) {
      if (![0, 1, 2].every((c) => Math.abs(onBackground.pixels[k + c] - background[c]) <= 1 / 255)) continue;
      ++empty;
      changed = Math.max(changed, ...[0, 1, 2].map((c) => Math.abs(outlinedOn.pixels[k + c] - onBackground.pixels[k + c])));
    }
    console.log(`${name}: outlines: over the ${empty} pixels of background alone they change the image by max abs ${changed}`);
    if (!(empty > 0 && changed === 0)) fail(`${name}: the outlines change the background alone by ${changed} (${empty} pixels)`);
    // in NiiVue's multiplanar layout, the render in a tile off the canvas's origin: outlined too
    const tiled = await draw({ scene, background, multiplanar: true });
    const outlinedTile = await draw({ scene: 'mri-outlines.json', sceneJson, background, multiplanar: true });
    const tileLines = lines(tiled.pixels, outlinedTile.pixels), said = (outlinedTile.warnings || []).join(' / ');
    console.log(`${name}: outlines in the multiplanar layout: ${tileLines} pixels of lines; warnings: ${said || 'none'}`);
    if (!(tileLines > theirs / 8) || /left out/.test(said)) fail(`${name}: the outlines in a tile off the origin: ${tileLines} lines (${said})`);
  }
  if (reference) await redrawn(name, reference, dir, { alone, staged, noHalos, m1, features },
    featuresDir && path.join(featuresDir, 'scene.json'));
  if (stagesDir) { // against halo-render --host raycast: the scene without its halos, and with them drawn once
    const reference = (d) => new Float32Array(fs.readFileSync(path.join(d, 'image.f32')).buffer.slice(0))
      .map((v) => (v > 0 ? (v < 1 ? v : 1) : 0));
    const withStages = reference(stagesDir), withHalos = reference(dir);
    const width = JSON.parse(fs.readFileSync(path.join(dir, 'host.json'))).width;
    const rows = [
      ['its stages without halo_*', noHalos, withStages, 'halo-render --host raycast'],
      ['its stages and halos', staged, withHalos, 'halo-render --host raycast --one-draw'],
    ];
    if (features) {
      // feature halos change within a voxel beside a feature: where vtk.js's samples lie
      // (its stages alone: about 1e-3 from raycast.frag's) they differ more, on the rims;
      // raycast.frag's page and the three.js caster give halo-render's image on this scene
      // to 1e-7 (the cases above), so libhalo's buffer is not the difference
      rows.push(['its stages without halo_* and with feature halos', features, reference(featuresDir), 'halo-render --host raycast',
        2 * MATCH_LIMIT]);
    }
    if (outlined) {
      // vtk.js's rays run to their end for the outlines' feature outputs (hidden features
      // too): with its early termination kept, 9.6e-3 (fails); without the passes after the
      // draw, 9.5e-3 (fails)
      rows.push(['its stages and halos with outlines', outlined, reference(outlinesDir), 'halo-render --host raycast --one-draw']);
      const effect = difference(outlined.pixels, staged.pixels);
      console.log(`${name}: outlines (against its stages and halos without them) mean abs ${effect.mean.toExponential(3)}; ` +
        `draw and read back ${outlined.drawMs.toFixed(1)} ms with them, ${staged.drawMs.toFixed(1)} ms without (the camera ` +
        'turning between frames)');
      if (!(effect.mean > EFFECT / 4)) fail(`${name}: the outlines change the image by only ${effect.mean}`);
    }
    for (const [what, image, ref, by, limit = MATCH_LIMIT] of rows) {
      if (image.pixels.length !== ref.length) { fail(`${name}: ${image.pixels.length} values in the page, ${ref.length} in ${by}'s`); continue; }
      const against = difference(image.pixels, ref);
      const shifted = difference(image.pixels.slice(0, ref.length - 4 * width), ref.slice(4 * width)); // the control
      console.log(`${name}, ${what}, set up as raycast.frag: against ${by}: mean abs ${against.mean.toExponential(3)}, ` +
        `max abs ${against.max.toExponential(3)} (limit ${limit} mean); against its image shifted by a row ` +
        `${shifted.mean.toExponential(3)} (must fail)`);
      if (!(against.mean <= limit)) fail(`${name}, ${what}: ${against.mean} from ${by}'s image (mean abs)`);
      if (!(shifted.mean > limit)) fail(`${name}, ${what}: the image shifted by a row passes too (${shifted.mean})`);
    }
    const plain = difference(alone.pixels, withStages), other = difference(m1.pixels, withHalos);
    console.log(`${name}: vtk.js alone against halo-render's stages ${plain.mean.toExponential(3)}, its field at M = 1 ` +
      `against halo-render's at the scene's M ${other.mean.toExponential(3)} (both must fail)`);
    if (!(plain.mean > MATCH_LIMIT)) fail(`${name}: vtk.js alone passes against the stages' image too (${plain.mean})`);
    if (!(other.mean > MATCH_LIMIT)) fail(`${name}: the field at M = 1 passes against the scene's M too (${other.mean})`);
  }
  for (const [what, image] of Object.entries({ alone, staged, noHalos, m1, removed, ...(features ? { features } : {}),
    ...(outlined ? { outlined } : {}) })) {
    if (image.warnings && image.warnings.length) fail(`${name}, ${what}: ${image.warnings.join(' / ')}`);
    if (image.hooked) fail(`${name}, ${what}: the context's drawArrays is left libhalo's after the render`);
  }
  if (which === 'vtkjs') { // a live parameter set while vtk.js drew with another of its programs
    const r = await page.evaluate(() => window.liveSwitch());
    console.log(`${viewer.name}: halo_map.opacity set while vtk.js drew with shading on, then off: against the stages ` +
      `installed with it ${r.againstFresh} max abs in 1/255 (the opacity changes the image by ${r.changed})`);
    if (r.againstFresh !== 0) fail(`${viewer.name}: a live parameter set under another program is lost (${r.againstFresh})`);
    if (!(r.changed > 0)) fail(`${viewer.name}: halo_map.opacity changes nothing`);
    console.log(`${viewer.name}: the volume removed and added again: ${r.readded} max abs in 1/255 from before`);
    if (r.readded !== 0) fail(`${viewer.name}: the volume added again is drawn otherwise (${r.readded})`);
  }
  if (which === 'vtkjs') { // its reduced viewport while the user interacts
    const r = await page.evaluate((keep) => window.smallViewport(keep), !!process.env.HALO_WEB_SAVE);
    for (const [what, image] of Object.entries(r.images || {})) // for a look (bytes)
      savePam(`vtkjs-interacting-${what}`, image, r.width, image.length / 4 / r.width, 1);
    console.log(`${viewer.name}: drawn at 1/2 while interacting: its stages and halos against them drawn whole mean abs ` +
      `${r.stagedSmallVsWhole.toExponential(3)} (vtk.js alone ${r.aloneSmallVsWhole.toExponential(3)}); the stages ` +
      `against vtk.js alone at 1/2 ${r.effectSmall.toExponential(3)} (whole ${r.effectWhole.toExponential(3)}); GL error ` +
      `${r.error}${r.warnings.length ? `; ${r.warnings.join(' / ')}` : ''}`);
    if (r.error || r.warnings.length) fail(`${viewer.name}: drawn at 1/2 while interacting: GL error ${r.error}, ${r.warnings.join(' / ')}`);
    if (!(r.aloneSmallVsWhole > 0)) fail(`${viewer.name}: vtk.js did not draw at 1/2 while interacting (the test sees nothing)`);
    if (!(r.effectSmall > EFFECT / 4)) fail(`${viewer.name}: the stages change the image at 1/2 by only ${r.effectSmall}`);
    if (!(r.stagedSmallVsWhole <= 2 * r.aloneSmallVsWhole + 2e-3))
      fail(`${viewer.name}: the stages at 1/2 are ${r.stagedSmallVsWhole} from them drawn whole (vtk.js alone: ${r.aloneSmallVsWhole})`);
  }
  if (which === 'vtkjs') { // what it cannot serve: refused with a message, never drawn meaningless
    const r = await page.evaluate(() => window.refusals());
    console.log(`${viewer.name}: outlines of segmentation labels: ${r.outlines}; maximum intensity at install: ${r.maximumAtInstall}; ` +
      `maximum intensity after install: ${r.warnings.join(' / ')} (the image ${r.maxDifference} from vtk.js's own, max ` +
      'abs in 1/255)');
    if (!/outline/.test(r.outlines) || !/host uniforms.*does not serve/.test(r.outlines)) fail(`${viewer.name}: a scene with label outlines: ${r.outlines}`);
    if (!/blend mode is not composite/.test(r.maximumAtInstall)) fail(`${viewer.name}: maximum intensity at install: ${r.maximumAtInstall}`);
    if (!r.warnings.some((w) => /blend mode is not composite/.test(w))) fail(`${viewer.name}: no warning for maximum intensity`);
    if (r.maxDifference !== 0) fail(`${viewer.name}: maximum intensity with the stages off is not vtk.js's own image`);
    console.log(`${viewer.name}: a clipping plane added after install: ${r.warnings.filter((w) => /clipping/.test(w)).join(' / ')} ` +
      `(that frame ${r.clipDifference} from vtk.js's own, max abs in 1/255; GL error ${r.clipError})`);
    if (!r.warnings.some((w) => /clipping planes/.test(w))) fail(`${viewer.name}: no warning for a clipping plane`);
    if (r.clipDifference !== 0 || r.clipError) fail(`${viewer.name}: the frame with a clipping plane is ${r.clipDifference} from ` +
      `vtk.js's own (GL error ${r.clipError})`);
    if (r.hooked) fail(`${viewer.name}: the context's drawArrays is still libhalo's after remove()`);
    console.log(`${viewer.name}: outlines with the renderer over half the canvas: ` +
      `${r.warnings.filter((w) => /outlines are left out/.test(w)).join(' / ')} (GL error ${r.partError})`);
    if (!r.warnings.some((w) => /outlines are left out/.test(w)) || r.partError)
      fail(`${viewer.name}: outlines in a renderer smaller than the canvas: no warning, or GL error ${r.partError}`);
  }
  drawn++;
}
const fail = (text) => { console.log(`FAIL: ${text}`); failures++; };
const browser = await puppeteer.launch({
  executablePath: process.env.HALO_CHROMIUM,
  headless: true,
  args: ['--headless=new', '--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader',
    '--ignore-gpu-blocklist', '--disable-gpu-sandbox'],
});
try {
  const page = await browser.newPage();
  page.on('console', (m) => console.log(`page: ${m.text()}`));
  page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  let casterAlone = null; // raycast.frag without libhalo, for the three.js caster's own difference

  for (const c of cases) writeNifti(c.dir); // the three.js caster's page reads the volume as NIfTI
  for (const c of cases) for (const viewer of ['raycast', 'three']) {
    inputs = c.dir;
    drawn++;
    await page.goto(`${origin}/${viewer}.html`);
    await page.waitForFunction('window.ready === true', { timeout: 30000 });
    // a one-draw frame is drawn three times: its time is the third's (the first builds libhalo's programs)
    const repeat = c.oneDraw ? 3 : 1;
    const staged = await page.evaluate((scene, oneDraw, repeat) => window.render({ scene, oneDraw, repeat }), c.scene,
      c.oneDraw, repeat);
    const plain = await page.evaluate((repeat) => window.render({ scene: null, repeat }), repeat);
    const label = c.scene.startsWith('/in/') ? `${path.basename(c.dir)}/${c.scene.slice(4)}` : c.scene; // a case's own scene
    const name = `${label}${c.oneDraw ? ' drawn once (host contract 3)' : ''} in ` +
      `${viewer === 'three' ? "the three.js caster" : 'raycast.frag'}`;
    if (c.oneDraw && viewer === 'raycast' && staged.draws !== 1) fail(`${name}: the host was drawn ${staged.draws} times, not once`);
    // the frame's memory holds at least the halo field's stack: a float a pixel, a layer a segment
    if (c.oneDraw && viewer === 'raycast' && !(staged.gpuBytes >= staged.pixels.length)) {
      fail(`${name}: the frame reports ${staged.gpuBytes} bytes of GPU memory, under one float a pixel`);
    }
    const reference = new Float32Array(fs.readFileSync(path.join(c.dir, 'image.f32')).buffer.slice(0));
    if (reference.length !== staged.pixels.length) {
      fail(`${name}: ${staged.pixels.length} values in the page, ${reference.length} in halo-render's image`);
      continue;
    }
    const against = difference(staged.pixels, reference), effect = difference(plain.pixels, reference);
    // the three.js caster is another ray caster: its samples are raycast.frag's up to float
    // rounding (the ray from the camera, not from the near plane), and the box's rasterized
    // back faces miss pixels whose ray only grazes it; the limit is its own difference from
    // raycast.frag without libhalo, twice, plus LIMIT
    let limit = LIMIT;
    if (viewer === 'raycast') casterAlone = plain.pixels;
    else {
      const own = difference(plain.pixels, casterAlone);
      limit = 2 * own.mean + LIMIT;
      console.log(`${label}: the three.js caster alone against raycast.frag alone: mean abs ${own.mean.toExponential(3)}, ` +
        `max abs ${own.max.toExponential(3)}`);
    }
    console.log(`${name}: ${staged.renderer}; against halo-render: mean abs ${against.mean.toExponential(3)}, ` +
      `max abs ${against.max.toExponential(3)} (limit ${limit.toExponential(3)} mean); the viewer without libhalo against it: mean abs ` +
      `${effect.mean.toExponential(3)}; link ${staged.linkMs.toFixed(1)} ms, draw and read back ${staged.drawMs.toFixed(1)} ms ` +
      `(${plain.drawMs.toFixed(1)} ms without the stages${c.oneDraw && viewer === 'raycast' ? `; ${staged.stillMs.toFixed(1)} ms drawn ` +
        'again unchanged, the field reused' : ''})`);
    if (!(against.mean <= limit)) fail(`${name}: the page's image is ${against.mean} from halo-render's (mean abs)`);
    if (!(effect.mean > EFFECT)) fail(`${name}: the stages change the image by only ${effect.mean}: not visible`);
    // the control: the same comparison against a wrong reference (the image shifted by a row) fails
    const shifted = reference.slice(4 * JSON.parse(fs.readFileSync(path.join(c.dir, 'host.json'))).width);
    const control = difference(staged.pixels.slice(0, shifted.length), shifted);
    if (control.mean <= limit) fail(`${name}: an image shifted by one row passes too (${control.mean}): the limit sees nothing`);
    if (c.oneDraw) { // the field matters: drawn with one plane a segment (M = 1), not the scene's M, it fails
      const other = await page.evaluate((scene) => window.render({ scene, oneDraw: true, interval: 1 }), c.scene);
      const m1 = difference(other.pixels, reference);
      console.log(`${name}: its field at M = 1 against halo-render's at the scene's M: mean abs ${m1.mean.toExponential(3)}`);
      if (m1.mean <= limit) fail(`${name}: a field of other segments passes too (${m1.mean}): the limit sees nothing`);
    }
    // the context lost and restored: the same frame (the same feature buffer, with the same
    // view: nothing but the loss makes it build again) draws the same image
    if ((c.oneDraw || c.scene === 'feature-halos.json') && viewer === 'raycast') {
      const r = await page.evaluate((scene, oneDraw) => window.render({ scene, oneDraw, restore: true }), c.scene, c.oneDraw);
      const again = r.restored ? difference(r.restored, r.pixels) : { max: NaN };
      console.log(`${name}: the WebGL context lost (${c.oneDraw ? 'frame.draw' : 'featureBuffer.build'}: ${r.whileLost}) ` +
        `and restored: the same frame drawn again, max abs ${again.max} against before the loss`);
      if (!/context is lost/.test(r.whileLost || '')) fail(`${name}: a draw on a lost context did not say so`);
      if (!(again.max === 0)) fail(`${name}: after the context was restored the frame draws ${again.max} from before`);
    }
    if (viewer === 'three' && staged.alone) { // the same renderer after the stages: the caster alone
      const after = difference(staged.alone, plain.pixels);
      if (!(after.max === 0)) fail(`${name}: renderer.render after the stages is ${after.max} from the caster alone (three's state)`);
    }
    if (viewer === 'three' && /outline/.test(c.scene)) {
      // outlines draw the scene's layers around the caster: another object (a red quad in a
      // corner, partly in the caster's box) drawn before the caster and after it, as three.js
      // draws it alone (three draws by renderOrder; the caster's is 0)
      const red = (p) => { let n = 0; for (let k = 0; k < p.length; k += 4) n += p[k] === 1 && p[k + 1] === 0 && p[k + 2] === 0; return n; };
      for (const renderOrder of [-1, 1]) {
        const quad = await page.evaluate((scene, o) => window.render({ scene, quad: { renderOrder: o } }), c.scene, renderOrder);
        const quadAlone = await page.evaluate((o) => window.render({ scene: null, quad: { renderOrder: o } }), renderOrder);
        console.log(`${name}: a red quad in the scene, renderOrder ${renderOrder}: ${red(quad.pixels)} red pixels with the ` +
          `outlines, ${red(quadAlone.pixels)} with three.js alone`);
        if (!(red(quadAlone.pixels) > 0) || red(quad.pixels) !== red(quadAlone.pixels))
          fail(`${name}: the scene's other object (renderOrder ${renderOrder}) is not drawn as three.js draws it`);
        // and the rest of the image is the one without the quad (the caster, its halos and outlines)
        let rest = 0;
        for (let k = 0; k < quad.pixels.length; k += 4) {
          const isRed = quadAlone.pixels[k] === 1 && quadAlone.pixels[k + 1] === 0 && quadAlone.pixels[k + 2] === 0;
          if (!isRed) for (let c = 0; c < 4; ++c) rest = Math.max(rest, Math.abs(quad.pixels[k + c] - staged.pixels[k + c]));
        }
        console.log(`${name}: renderOrder ${renderOrder}: beside the quad, max abs ${rest} from the image without it`);
        if (renderOrder > 0 && !(rest === 0)) fail(`${name}: an overlay changes the image beside it by ${rest}`);
      }
    }
    if (viewer === 'three' && c.oneDraw)
      await fieldCap(name, (o) => page.evaluate((scene, options) => window.render({ scene, ...options }), c.scene, o), staged);
    if (viewer === 'three') { // installed and removed: the caster alone again
      const removed = await page.evaluate((scene) => window.render({ scene, removed: true }), c.scene);
      const back = difference(removed.pixels, plain.pixels);
      if (!(back.max === 0)) fail(`${name}: the stages removed again leave the image ${back.max} from the caster alone`);
    }
  }
  if (mriCase) {
    writeNifti(mriCase);
    for (const which of engines) await engine(page, mriCase, which);
    if (engines.includes('niivue')) await demo(page, path.join(mriCase, 'head.nii'));
  }
} finally {
  await browser.close();
  server.close();
}
console.log(failures ? `${failures} failed` : `${drawn} passed, 0 failed`);
process.exit(failures ? 1 : 0);
