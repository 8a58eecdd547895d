// `ridge tiles` PMTiles output read back by an independent reader, the `pmtiles` npm package:
// for quantized-mesh and terrain-RGB, every tile of the directory output `ridge tiles` writes
// for the same archive must come back from the PMTiles file byte for byte (quantized-mesh
// tiles at PMTiles zoom z + 1, docs/FORMAT.md, inflated by the reader as the header's gzip
// tile compression says), and the header and metadata must say what the tiles are.
//
// Usage: node tests/browser/pmtiles-check.mjs --ridge build/ridge --archive A.ridge --out DIR
// Exit: 0 pass, 1 a check failed, 2 usage, 77 web/node_modules missing (skip).
import { execFileSync } from 'node:child_process';
import { existsSync, mkdirSync, readdirSync, readFileSync, rmSync, openSync, readSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { gunzipSync } from 'node:zlib';
import { fileURLToPath } from 'node:url';

const repo = resolve(dirname(fileURLToPath(import.meta.url)), '../..');
const args = Object.fromEntries(process.argv.slice(2).reduce((pairs, a, i, all) =>
  (a.startsWith('--') ? [...pairs, [a.slice(2), all[i + 1]]] : pairs), []));
if (!args.ridge || !args.archive || !args.out) {
  console.error('usage: pmtiles-check.mjs --ridge RIDGE --archive ARCHIVE --out DIR');
  process.exit(2);
}
const modules = join(repo, 'web/node_modules/pmtiles');
if (!existsSync(modules)) {
  console.log(`SKIP: ${modules} missing (bash scripts/install-web-deps.sh installs it)`);
  process.exit(77);
}
const { PMTiles } = await import(join(modules, 'dist/esm/index.js'));

// The pmtiles Source interface over a local file (range reads).
class FileSource {
  constructor(path) { this.path = path; this.fd = openSync(path, 'r'); }
  getKey() { return this.path; }
  async getBytes(offset, length) {
    const buffer = Buffer.alloc(length);
    const n = readSync(this.fd, buffer, 0, length, offset);
    return { data: buffer.buffer.slice(buffer.byteOffset, buffer.byteOffset + n) };
  }
}

let failures = 0;
function check(name, ok, detail) {
  console.log(`${ok ? 'PASS' : 'FAIL'} ${name}: ${detail}`);
  if (!ok) failures++;
  return ok;
}

// Every Z/X/Y.ext file under `dir`.
function tileFiles(dir, extension) {
  const out = [];
  for (const z of readdirSync(dir).filter((n) => /^\d+$/.test(n)))
    for (const x of readdirSync(join(dir, z)))
      for (const f of readdirSync(join(dir, z, x)))
        if (f.endsWith(`.${extension}`))
          out.push({ z: Number(z), x: Number(x), y: Number(f.slice(0, -extension.length - 1)), path: join(dir, z, x, f) });
  return out;
}

rmSync(args.out, { recursive: true, force: true });
mkdirSync(args.out, { recursive: true });
const cases = [
  { name: 'quantized-mesh', format: 'quantized-mesh', extension: 'terrain', zoomShift: 1, type: 0, compression: 2, tiling: 'geographic-tms+1' },
  { name: 'terrain-rgb png', format: 'terrain-rgb', extension: 'png', zoomShift: 0, type: 2, compression: 1, tiling: 'xyz', extra: [] },
  { name: 'terrarium webp', format: 'terrarium', extension: 'webp', zoomShift: 0, type: 4, compression: 1, tiling: 'xyz', extra: ['--image', 'webp'] },
];
for (const c of cases) {
  const dir = join(args.out, c.format), file = join(args.out, `${c.format}.pmtiles`);
  for (const output of [dir, file])
    execFileSync(args.ridge, ['tiles', args.archive, '-o', output, '--format', c.format, '-q', ...(c.extra ?? [])]);
  const archive = new PMTiles(new FileSource(file));
  const header = await archive.getHeader();
  const metadata = await archive.getMetadata();
  const files = tileFiles(dir, c.extension);
  check(`${c.name}: header`, header.tileType === c.type && header.tileCompression === c.compression &&
    header.numAddressedTiles === files.length && header.clustered === true,
  `type ${header.tileType}, tile compression ${header.tileCompression}, ${header.numAddressedTiles} tiles addressed ` +
    `(${files.length} files), zooms ${header.minZoom}-${header.maxZoom}, clustered ${header.clustered}`);
  check(`${c.name}: metadata`, metadata['ridge:tiling'] === c.tiling, `ridge:tiling ${metadata['ridge:tiling']}`);
  let same = 0;
  const different = [];
  for (const t of files) {
    const got = await archive.getZxy(t.z + c.zoomShift, t.x, t.y);
    // The reader inflates gzip-compressed tiles (the header's tile compression); the
    // directory's quantized-mesh files are stored compressed.
    const want = c.compression === 2 ? gunzipSync(readFileSync(t.path)) : readFileSync(t.path);
    if (got && Buffer.from(got.data).equals(want)) same++;
    else different.push(`${t.z}/${t.x}/${t.y}`);
  }
  check(`${c.name}: tiles`, different.length === 0 && same > 0,
    `${same} of ${files.length} tiles identical to the directory's${different.length ? `; different or missing: ${different.slice(0, 5).join(', ')}` : ''}`);
  const absent = await archive.getZxy(c.zoomShift + 3, 0, 0);
  check(`${c.name}: absent tile`, absent === undefined, 'a tile outside the archive reads as absent');
}
console.log(failures ? `FAILED (${failures})` : 'all passed');
process.exit(failures ? 1 : 0);
