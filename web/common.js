// Shared by ridge serve's viewer pages: the query string, the tileset list and window.ridgeStatus,
// the state a headless test (tests/browser/run.mjs) polls.

export const params = new URLSearchParams(location.search);

// A number from the query string, or `fallback` when absent (without a fallback it is required); a
// non-number is an error, so that a typo in a test's camera does not silently give another view.
export function num(name, fallback) {
  const text = params.get(name);
  if (text === null || text === '') {
    if (fallback === undefined) throw new Error(`query parameter ${name}= is required`);
    return fallback;
  }
  const value = Number(text);
  if (!Number.isFinite(value)) throw new Error(`query parameter ${name}=${text} is not a number`);
  return value;
}

// test=1: a pure magenta background and nothing else that could be mistaken for terrain, so that a
// test can find the skyline and count holes.
export const testMode = params.get('test') === '1';
export const MAGENTA = '#ff00ff';

// The contract with tests: `ready` once the view is complete (every tile the camera needs is drawn),
// `error` the first failure (a page that will never become ready says why here).
export const status = {
  ready: false,
  tilesLoaded: false,
  error: null,
  tileset: null,
  frames: 0,
};
window.ridgeStatus = status;

export function fail(error) {
  const message = error instanceof Error ? `${error.message}` : String(error);
  console.error('ridge:', message);
  if (status.error === null) status.error = message;
  const box = document.getElementById('error');
  if (box) {
    box.textContent = message;
    box.hidden = false;
  }
}
window.addEventListener('error', (e) => fail(e.error ?? e.message));
window.addEventListener('unhandledrejection', (e) => fail(e.reason));

// The tileset named by ?tileset=, or the only one served when there is exactly one.
export async function chosenTileset() {
  const response = await fetch('tilesets.json');
  if (!response.ok) throw new Error(`tilesets.json: HTTP ${response.status}`);
  const { tilesets } = await response.json();
  const name = params.get('tileset');
  const tileset = name === null && tilesets.length === 1 ? tilesets[0] : tilesets.find((t) => t.name === name);
  if (!tileset) {
    const names = tilesets.map((t) => t.name).join(', ');
    throw new Error(name === null ? `no ?tileset= given (served: ${names})` : `no tileset "${name}" (served: ${names})`);
  }
  status.tileset = tileset.name;
  return tileset;
}
