// Serves the demo page (docs/web/index.html) on the loopback, from a build tree:
//   node docs/web/serve.mjs [VOLUME.nii.gz] [PORT]
// then open http://127.0.0.1:PORT/ (8080 by default). The page's modules come from the
// web package (adapters/web/package, built by make) and NiiVue from the browser tests'
// node_modules (setup.sh: npm ci in tests/adapters/web). The volume defaults to the MRI head
// of Debian's mricron-data.
import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const top = path.resolve(here, '../..');
const build = path.resolve(process.env.HALO_BUILD || top);
const volume = path.resolve(process.argv[2] || '/usr/share/mricron/templates/ch2better.nii.gz');
const port = Number(process.argv[3] ?? 8080); // 0: any free port (printed)
const roots = [['/pkg/', path.join(build, 'adapters/web/package')],
  ['/modules/', path.join(top, 'tests/adapters/web/node_modules')], ['/', here]];
const types = { '.html': 'text/html', '.mjs': 'text/javascript', '.js': 'text/javascript', '.wasm': 'application/wasm',
  '.json': 'application/json' };
for (const need of [volume, path.join(build, 'adapters/web/package/libhalo.mjs'),
  path.join(top, 'tests/adapters/web/node_modules/@niivue/niivue')])
  if (!fs.existsSync(need)) {
    console.error(`serve.mjs: error: ${need} is missing (the volume; make; setup.sh's npm ci in tests/adapters/web)`);
    process.exit(1);
  }
const realRoots = roots.map(([prefix, root]) => [prefix, fs.existsSync(root) ? fs.realpathSync(root) : root]);
const server = http.createServer((request, response) => {
  const answer = (status) => {
    response.writeHead(status);
    response.end();
  };
  let url;
  try {
    url = decodeURIComponent(new URL(request.url, 'http://localhost').pathname);
  } catch {
    answer(400); // a malformed escape
    return;
  }
  let file = null;
  if (url === '/') { // the page, with the volume served here
    response.writeHead(302, { location: `/index.html?volume=/volumes/${encodeURIComponent(path.basename(volume))}` });
    response.end();
    return;
  }
  if (url === `/volumes/${path.basename(volume)}`) file = volume;
  else
    for (const [prefix, root] of realRoots) {
      if (!url.startsWith(prefix)) continue;
      const candidate = path.resolve(root, url.slice(prefix.length) || 'index.html');
      // inside the root, links followed (a link in node_modules must not lead out of it)
      const real = fs.existsSync(candidate) ? fs.realpathSync(candidate) : null;
      if (real && real.startsWith(root + path.sep) && fs.statSync(real).isFile()) file = real;
      break;
    }
  if (!file) {
    answer(404);
    return;
  }
  const stream = fs.createReadStream(file);
  stream.on('error', () => (response.headersSent ? response.destroy() : answer(500)));
  stream.once('open', () => {
    response.writeHead(200, { 'content-type': types[path.extname(file)] || 'application/octet-stream' });
    stream.pipe(response);
  });
});
server.listen(port, '127.0.0.1', () => console.log(`libhalo's NiiVue demo: http://127.0.0.1:${server.address().port}/`));
export default server;
