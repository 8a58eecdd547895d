// MapLibre GL viewer of one ridge tileset's terrain-RGB tiles:
// maplibre.html?tileset=NAME[&encoding=mapbox|terrarium][&format=png|webp][&hidpi=1]
//              [&lon=&lat=&height=&heading=&pitch=][&test=1]
// The camera query is cesium.html's: position lon/lat (degrees) and height (metres), heading
// (degrees clockwise from north), pitch (degrees above the horizon, negative down); without
// lon/lat it frames the tileset's bounds. hidpi=1 uses the 512 px tiles (ENCODING@2x).
import * as maplibregl from './node_modules/maplibre-gl/dist/maplibre-gl.mjs';
import { params, num, testMode, MAGENTA, status, fail, chosenTileset } from './common.js';

const GROUND = '#b8ab94'; // cesium.html's globe colour

async function tileJson(tileset) {
  const encoding = params.get('encoding') ?? 'mapbox';
  const format = params.get('format') ?? 'png';
  if (!['mapbox', 'terrarium'].includes(encoding)) throw new Error(`encoding=${encoding}: mapbox or terrarium`);
  if (!['png', 'webp'].includes(format)) throw new Error(`format=${format}: png or webp`);
  const base = `${location.origin}/${encodeURIComponent(tileset.name)}/`;
  const url = `${base}${encoding}${params.get('hidpi') === '1' ? '@2x' : ''}.json${format === 'webp' ? '?format=webp' : ''}`;
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
  const tj = await response.json();
  // ridge's TileJSON gives tile URLs relative to the tileset's directory; MapLibre wants absolute
  // ones. (Concatenated: new URL() would percent-encode the {z}/{x}/{y} placeholders.)
  const tiles = tj.tiles.map((t) => base + t);
  Object.assign(status, { encoding, format, tileSize: tj.tileSize, tiles });
  return { type: 'raster-dem', tiles, tileSize: tj.tileSize, encoding: tj.encoding, minzoom: tj.minzoom, maxzoom: tj.maxzoom, bounds: tj.bounds };
}

// The tileset's footprint, and (holes: true) the rest of the world with the footprint cut out.
function footprint([west, south, east, north], { holes = false } = {}) {
  const ring = [[west, south], [east, south], [east, north], [west, north], [west, south]];
  const world = [[-180, -85], [-180, 85], [180, 85], [180, -85], [-180, -85]];
  return {
    type: 'Feature',
    properties: {},
    geometry: { type: 'Polygon', coordinates: holes ? [world, ring] : [ring] },
  };
}

async function main() {
  const tileset = await chosenTileset();
  document.title = `ridge · ${tileset.name} · MapLibre GL`;
  const dem = await tileJson(tileset);
  // Above the horizon MapLibre leaves the canvas transparent: in test mode that is background
  // too (a far horizon shows when the ground beyond the tileset fades down to 0 m).
  if (testMode) document.getElementById('map').style.background = MAGENTA;
  const map = new maplibregl.Map({
    container: 'map',
    maxPitch: 85,
    attributionControl: false,
    style: {
      version: 8,
      // MapLibre warns when one raster-dem source feeds both terrain and hillshade.
      sources: {
        terrain: dem,
        hillshade: { ...dem },
        footprint: { type: 'geojson', data: footprint(tileset.bounds) },
        outside: { type: 'geojson', data: footprint(tileset.bounds, { holes: true }) },
      },
      layers: [
        { id: 'background', type: 'background', paint: { 'background-color': testMode ? MAGENTA : '#d8dde3' } },
        // An opaque ground under the hillshade, whose flat parts are transparent: in test mode only
        // the tileset's footprint may cover the magenta.
        { id: 'ground', type: 'fill', source: 'footprint', paint: { 'fill-color': GROUND } },
        {
          id: 'hillshade',
          type: 'hillshade',
          source: 'hillshade',
          paint: {
            'hillshade-illumination-direction': 315,
            'hillshade-exaggeration': 0.6,
            'hillshade-shadow-color': '#3d3528',
            'hillshade-highlight-color': '#fffaf0',
            'hillshade-accent-color': '#5c5140',
          },
        },
        // Test mode shows only the tileset's own surface, as cesium.html's does: outside the
        // footprint the tiles' pixels are not the archive's (and ridge render draws nothing there).
        ...(testMode ? [{ id: 'outside', type: 'fill', source: 'outside', paint: { 'fill-color': MAGENTA, 'fill-antialias': false } }] : []),
      ],
    },
    bounds: tileset.bounds,
    fitBoundsOptions: { padding: 20 },
    // A camera placed by the query stays where it is put, instead of following the ground under
    // the map's centre.
    centerClampedToGround: !(params.has('lon') || params.has('lat')),
  });
  window.ridgeMap = map; // for debugging in the console
  map.on('error', (e) => fail(e.error ?? e));
  await map.once('load');
  map.setTerrain({ source: 'terrain', exaggeration: 1 });

  if (params.has('lon') || params.has('lat')) {
    // MapLibre's pitch is from the nadir; the query's is from the horizon.
    const pitch = 90 + num('pitch', -30);
    map.jumpTo(map.calculateCameraOptionsFromCameraLngLatAltRotation(
      [num('lon'), num('lat')], num('height', 10000), num('heading', 0), pitch));
  } else {
    map.jumpTo({ pitch: 90 + num('pitch', -30), bearing: num('heading', 0) });
  }

  // idle: no camera transition and every tile of every source loaded (terrain included).
  map.on('render', () => { status.frames++; });
  map.on('idle', () => {
    status.tilesLoaded = map.areTilesLoaded();
    if (status.ready || !status.tilesLoaded || !map.getTerrain()) return;
    const center = map.getCenter();
    Object.assign(status, {
      ready: true,
      fovyDegrees: map.getVerticalFieldOfView(),
      canvas: [map.getCanvas().width, map.getCanvas().height],
      camera: { center: [center.lng, center.lat], zoom: map.getZoom(), pitch: map.getPitch(), bearing: map.getBearing() },
    });
  });
}

main().catch(fail);
