// The web package's JavaScript API under node (tests/adapters/web/api.sh runs it): the WebAssembly
// linker must write the same shaders and reflection as the native one (halo-validate link),
// byte for byte, for every example scene in the example hosts and as composer pieces; its
// errors are HaloErrors at file:line:col; live parameters reach WebGL's uniforms.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';

const srcdir = process.env.srcdir;
const validate = process.env.HALO_VALIDATE;
const { default: libhalo, HaloError } = await import(path.resolve(process.env.HALO_WEB_PACKAGE, 'libhalo.mjs'));
const halo = await libhalo();
const scenes = path.join(srcdir, 'examples/scenes');
const hosts = path.join(srcdir, 'examples/hosts');

function native(args) {
  try {
    return { out: execFileSync(validate, args, { encoding: 'utf8', stdio: ['ignore', 'pipe', 'pipe'] }) };
  } catch (e) {
    return { error: e.stderr };
  }
}

test('every example scene links as the native linker links it (es300, raycast.frag and webgl_caster.frag)', () => {
  let compared = 0, refused = 0;
  for (const host of ['raycast.frag', 'webgl_caster.frag']) {
    const hostPath = path.join(hosts, host);
    const hostText = fs.readFileSync(hostPath, 'utf8');
    for (const file of fs.readdirSync(scenes).filter((f) => f.endsWith('.json')).sort()) {
      const scenePath = path.join(scenes, file);
      const expected = native(['link', '--scene', scenePath, '--host', hostPath, '--target', 'es300']);
      let program;
      try {
        program = halo.link({ scene: fs.readFileSync(scenePath, 'utf8'), sceneFile: scenePath, host: hostText,
          hostFile: hostPath });
      } catch (e) {
        assert.ok(e instanceof HaloError, `${file}: ${e}`);
        assert.ok(expected.error !== undefined, `${file} in ${host}: refused in WebAssembly (${e.message}), linked natively`);
        assert.ok(expected.error.includes(e.diagnostics[0].message), `${file}: another error natively:\n${expected.error}`);
        refused++;
        continue;
      }
      assert.equal(expected.error, undefined, `${file} in ${host}: linked in WebAssembly, refused natively`);
      assert.equal(program.source, expected.out, `${file} in ${host}: the linked source differs`);
      const reflected = native(['link', '--scene', scenePath, '--host', hostPath, '--target', 'es300', '--reflect']);
      assert.deepEqual(program.reflection, JSON.parse(reflected.out), `${file} in ${host}: the reflection differs`);
      program.destroy();
      compared++;
    }
  }
  console.log(`${compared} programs identical to the native linker's, ${refused} refused by both`);
  assert.ok(compared >= 40);
});

test('composer pieces are the native ones', () => {
  const scenePath = path.join(scenes, 'boundary-silhouette.json');
  const pieces = { volume: 'u_volume', color: 'halo_color' };
  const program = halo.link({ scene: fs.readFileSync(scenePath, 'utf8'), sceneFile: scenePath, pieces });
  const expected = native(['link', '--pieces', '--scene', scenePath, '--target', 'es300', '--sample', 'volume=u_volume',
    '--sample', 'color=halo_color']);
  assert.equal(expected.error, undefined, expected.error);
  for (const [name, text] of Object.entries(program.pieces))
    assert.ok(expected.out.includes(text.trimEnd()), `the ${name} piece is not in the native output`);
  assert.deepEqual(Object.keys(program.pieces).sort(), ['declarations', 'finish', 'sample']);
});

test('errors are HaloErrors at file:line:col', () => {
  const host = fs.readFileSync(path.join(hosts, 'raycast.frag'), 'utf8');
  assert.throws(() => halo.link({ scene: '{"halo_scene": 1, "stages": [{"boundary": {"k_gs": "x"}}]}', sceneFile: 'bad.json', host }),
    (e) => e instanceof HaloError && e.file === 'bad.json' && e.line === 1 && e.column > 1 &&
      /^bad\.json:1:\d+: .*k_gs/.test(e.message));
  assert.throws(() => halo.link({ scene: '{"halo_scene": 1, "stages": [{"no_such_stage": {}}]}', host }),
    (e) => e instanceof HaloError && e.id !== undefined && /no_such_stage/.test(e.message));
  assert.throws(() => halo.link({ host, target: 'es310' }), /target 'es310' is not 330, 450, es300 or 150/);
  assert.throws(() => halo.link({ host, colour: 1 }), /unknown option 'colour'/);
  assert.throws(() => halo.link({}), /give host/);
  assert.throws(() => halo.link({ scene: '{"halo_scene": 1, "stages": [{"boundary": {}}]}', host: 'void main() {}', hostFile: 'mine.frag' }),
    (e) => e instanceof HaloError && e.file === 'mine.frag');
});

test('live parameters: set checks the range, upload reaches the uniforms', () => {
  const host = fs.readFileSync(path.join(hosts, 'raycast.frag'), 'utf8');
  const program = halo.link({ scene: '{"halo_scene": 1, "stages": [{"tone_shading": {"live": ["k_ta", "lights"]}}]}', host });
  const calls = [];
  const gl = {
    getUniformLocation: (p, name) => (program.source.includes(`uniform float ${name};`) || program.source.includes(`${name}[`) ||
      program.source.includes(`uniform int ${name};`) ? name : null),
    uniform1fv: (l, v) => calls.push(['1fv', l, Array.from(v)]),
    uniform3fv: (l, v) => calls.push(['3fv', l, Array.from(v)]),
    uniform1i: (l, v) => calls.push(['1i', l, v]),
  };
  program.upload(gl, {});
  assert.deepEqual(calls.find((c) => c[1] === 'halo_tone_shading_k_ta'), ['1fv', 'halo_tone_shading_k_ta', [1]]);
  calls.length = 0;
  program.set('tone_shading.k_ta', 0.4);
  program.set('tone_shading', 'lights', [[0, 0, 1], [1, 0, 0]]);
  program.upload(gl, {});
  assert.deepEqual(calls.find((c) => c[1] === 'halo_tone_shading_k_ta')[2].map((x) => +x.toFixed(6)), [0.4]);
  assert.deepEqual(calls.find((c) => c[1] === 'halo_tone_shading_lights'), ['3fv', 'halo_tone_shading_lights', [0, 0, 1, 1, 0, 0]]);
  assert.deepEqual(calls.find((c) => c[1] === 'halo_tone_shading_lights_count'), ['1i', 'halo_tone_shading_lights_count', 2]);
  calls.length = 0; // nothing set since: nothing uploaded; all (an engine's program built again): every current value
  program.upload(gl, {});
  assert.equal(calls.length, 0);
  program.upload(gl, {}, { all: true });
  assert.deepEqual(calls.find((c) => c[1] === 'halo_tone_shading_k_ta')[2].map((x) => +x.toFixed(6)), [0.4]);
  assert.deepEqual(calls.find((c) => c[1] === 'halo_tone_shading_lights'), ['3fv', 'halo_tone_shading_lights', [0, 0, 1, 1, 0, 0]]);
  assert.throws(() => program.set('tone_shading.k_ta', 99), (e) => e instanceof HaloError && /above the maximum/.test(e.message));
  assert.throws(() => program.set('tone_shading.k_td', 1), HaloError); // not live
  assert.throws(() => program.set('k_ta', 1), /is not stage\.param/);
});

test('halo parameters (type channels) upload as the channel count\'s vector', () => {
  const host = fs.readFileSync(path.join(hosts, 'raycast.frag'), 'utf8');
  const program = halo.link({ scene: fs.readFileSync(path.join(scenes, 'mri-head.json'), 'utf8'), host,
    hostFile: 'raycast.frag', allLive: true, oneDraw: true });
  assert.equal(program.reflection.channels, 2);
  const calls = [];
  const gl = { getUniformLocation: (p, name) => name, uniform2fv: (l, v) => calls.push(['2fv', l, Array.from(v)]),
    uniform1fv: (l, v) => calls.push(['1fv', l, Array.from(v)]), uniform3fv: () => {}, uniform4fv: () => {},
    uniform1iv: () => {}, uniform1i: () => {}, uniformMatrix4fv: () => {} };
  program.upload(gl, {});
  assert.deepEqual(calls.find((c) => c[1] === 'halo_halo_map_opacity'), ['2fv', 'halo_halo_map_opacity', [0.5, 0.3].map(Math.fround)]);
  program.set('halo_map.opacity', [0.25, 0.75]);
  calls.length = 0;
  program.upload(gl, {});
  assert.deepEqual(calls.find((c) => c[1] === 'halo_halo_map_opacity'), ['2fv', 'halo_halo_map_opacity', [0.25, 0.75]]);
  assert.throws(() => program.set('halo_map.opacity', [0.25, 0.75, 0.5]), /whole vec2 elements/);
  program.destroy();
});

test('a WebGL compile log maps to the modules', () => {
  const host = fs.readFileSync(path.join(hosts, 'raycast.frag'), 'utf8');
  const program = halo.link({ scene: fs.readFileSync(path.join(scenes, 'default.json'), 'utf8'), host, hostFile: 'raycast.frag' });
  const lines = program.source.split('\n');
  const at = lines.findIndex((l) => l.includes('void halo_tone_shading_apply')) + 1;
  assert.ok(at > 0);
  assert.equal(program.mapLog(`ERROR: 0:${at}: 'x' : undeclared identifier`),
    `ERROR: ${program.mapLine(at).file}:${program.mapLine(at).line}: 'x' : undeclared identifier`);
  assert.match(program.mapLine(at).file, /tone_shading\.glsl$/);
  assert.deepEqual(program.mapLine(1), { file: 'raycast.frag', line: 1 });
});

test('installHalo: volumetric halos through the field (host contract 3), outlines with the THREE module', async () => {
  const { installHalo, MARKERS } = await import(path.resolve(process.env.HALO_WEB_PACKAGE, 'three.mjs'));
  const material = () => ({ glslVersion: '300 es', uniforms: {},
    fragmentShader: `${MARKERS.declarations}\nvoid main() {\n${MARKERS.sample}\n${MARKERS.finish}\n}\n` });
  const scene = (name) => fs.readFileSync(path.join(scenes, name), 'utf8');
  const halos = material();
  const stages = installHalo(halo, halos, { scene: scene('default.json') });
  assert.ok(stages.program.reflection.passes.length > 0, 'the field passes are linked');
  assert.match(halos.fragmentShader, /halo_image_field/); // the sample reads the field
  assert.ok(halos.uniforms.halo_host_screen_right && halos.uniforms.halo_host_screen_up);
  stages.remove();
  assert.equal(halos.uniforms.halo_host_screen_right, undefined);
  // outlines: served with the THREE module (their render targets); without it refused, saying so
  assert.throws(() => installHalo(halo, material(), { scene: scene('outline-depth.json') }),
    /stages \(.*outlines\) draw outlines, which need render targets of their own: pass options\.three/);
  const outlined = material();
  const outlineStages = installHalo(halo, outlined, { scene: scene('outline-depth.json'), three: { WebGLRenderTarget() {} } });
  assert.ok(outlineStages.program.reflection.outputs.length > 0, 'the outputs are linked');
  outlineStages.remove();
  // feature halos: served (the halo buffer is splatted at render), the stage reads it
  const features = material();
  const featureStages = installHalo(halo, features, { scene: scene('feature-halos.json') });
  assert.match(features.fragmentShader, /halo_host_feature_buffer/);
  featureStages.remove();
  assert.throws(() => installHalo(halo, { ...material(), fragmentShader: 'void main() {}' }, { scene: scene('default.json') }),
    /no '\/\/halo:declarations' marker/);
});

test('featureBuffer refuses what it cannot splat before it touches the context', () => {
  const program = halo.link({ scene: fs.readFileSync(path.join(scenes, 'feature-halos.json'), 'utf8'),
    host: fs.readFileSync(path.join(hosts, 'raycast.frag'), 'utf8'), hostFile: 'raycast.frag' });
  assert.ok(program.reflection.host_uniforms.some((u) => u.name === 'halo_host_feature_buffer'));
  const gl = {}; // never reached: every refusal comes first
  assert.throws(() => halo.featureBuffer(gl, {}, { values: [0], dims: [1, 1, 1] }), (e) => e instanceof HaloError && /Program/.test(e.message));
  assert.throws(() => halo.featureBuffer(gl, program, { values: [0], dims: [1, 1] }), /three positive integers/);
  assert.throws(() => halo.featureBuffer(gl, program, { values: [0, 0], dims: [1, 1, 1] }), /must hold 1 x 1 x 1 numbers/);
  program.destroy();
});

test('smallerProgram: a field over its cap links the scene at 1/2, then 1/4, the live values kept', () => {
  const names = { position: 'P', value: 'v', volume: 'u_volume', view: 'w', depth: 'd', fragcoord: 'gl_FragCoord.xy', color: 'c' };
  const scene = fs.readFileSync(path.join(scenes, 'default.json'), 'utf8');
  const over = new HaloError([{ severity: 'error', id: 'FIELD_MEMORY', file: '', line: 0, column: 0,
    message: 'halo_gl_frame_draw: the halo field ... over field_max_bytes' }]);
  const { program } = halo.linkForEngine({ scene, pieces: names, allLive: true }, 'test');
  assert.equal(program.reflection.image_scale, 1);
  program.set('halo_map.opacity', [0.25, 0.75]);
  const half = halo.smallerProgram(program, over);
  assert.equal(half.program.reflection.image_scale, 2);
  assert.match(half.warning, /over field_max_bytes; linked again with halo images at 1\/2/);
  assert.deepEqual(half.program._current.get('halo_map.opacity'), [0.25, 0.75]);
  assert.notEqual(half.program.pieces.declarations, program.pieces.declarations); // the field read at 1/2 (bilinear)
  const quarter = halo.smallerProgram(half.program, over);
  assert.equal(quarter.program.reflection.image_scale, 4);
  assert.deepEqual(quarter.program._current.get('halo_map.opacity'), [0.25, 0.75]);
  assert.equal(halo.smallerProgram(quarter.program, over), null, 'no smaller scale than 1/4');
  assert.equal(halo.smallerProgram(program, new HaloError([], 'another error')), null, 'only FIELD_MEMORY');
  const { program: chosen } = halo.linkForEngine({ scene, pieces: names, imageScale: 2 }, 'test');
  assert.equal(halo.smallerProgram(chosen, over), null, 'an explicit imageScale is kept');
  for (const p of [program, half.program, quarter.program, chosen]) p.destroy();
});
