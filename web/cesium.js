// CesiumJS viewer of one ridge tileset: cesium.html?tileset=NAME[&lon=&lat=&height=&heading=&pitch=][&test=1]
// The camera is at lon/lat (degrees, both or neither) and height (metres in the tiles' heights:
// above the ellipsoid, or the archive's own where ridge serve does not convert them), looking along
// heading (degrees clockwise from north) and pitch (degrees above the horizon, negative down);
// without lon/lat it frames the tileset's bounds.
import { params, num, testMode, status, fail, chosenTileset } from './common.js';

const Cesium = window.Cesium;

// Consecutive rendered frames with every needed tile loaded before the view counts as complete:
// tilesLoaded can be true for a frame between the camera move and the next tile requests.
const SETTLED_FRAMES = 10;

const viewer = new Cesium.Viewer('viewer', {
  // No Cesium ion: no imagery, geocoder, imagery/terrain pickers or other ion-backed widgets.
  baseLayer: false,
  baseLayerPicker: false,
  geocoder: false,
  homeButton: false,
  sceneModePicker: false,
  navigationHelpButton: false,
  animation: false,
  timeline: false,
  fullscreenButton: false,
  infoBox: false,
  selectionIndicator: false,
  // Render every frame, so that postRender keeps reporting while tiles arrive.
  requestRenderMode: false,
  skyBox: testMode ? false : undefined,
  skyAtmosphere: testMode ? false : undefined,
});
const { scene, camera } = viewer;
const globe = scene.globe;

// Lit by a fixed sun (a November late morning in Nepal), shading from the tiles' vertex normals.
viewer.clock.currentTime = Cesium.JulianDate.fromIso8601('2024-11-15T05:00:00Z');
viewer.clock.shouldAnimate = false;
globe.enableLighting = true;
globe.baseColor = Cesium.Color.fromCssColorString('#b8ab94');

if (testMode) {
  // skyBox: false also leaves out the sun and moon.
  scene.backgroundColor = Cesium.Color.MAGENTA;
  scene.fog.enabled = false;
  globe.showGroundAtmosphere = false;
  // The credit overlay would cover drawn pixels in screenshots.
  viewer.cesiumWidget.creditContainer.style.display = 'none';
}

function setCamera(tileset) {
  const heading = Cesium.Math.toRadians(num('heading', 0));
  if (params.has('lon') || params.has('lat')) {
    camera.setView({
      destination: Cesium.Cartesian3.fromDegrees(num('lon'), num('lat'), num('height', 10000)),
      orientation: { heading, pitch: Cesium.Math.toRadians(num('pitch', -30)), roll: 0 },
    });
  } else {
    const [west, south, east, north] = tileset.bounds;
    const sphere = Cesium.BoundingSphere.fromRectangle3D(Cesium.Rectangle.fromDegrees(west, south, east, north));
    camera.viewBoundingSphere(sphere, new Cesium.HeadingPitchRange(heading, Cesium.Math.toRadians(num('pitch', -35)), 0));
    camera.lookAtTransform(Cesium.Matrix4.IDENTITY); // release the look-at frame so the mouse moves freely
  }
}

async function main() {
  const tileset = await chosenTileset();
  document.title = `ridge · ${tileset.name} · CesiumJS`;
  const provider = await Cesium.CesiumTerrainProvider.fromUrl(`${encodeURIComponent(tileset.name)}/`, {
    requestVertexNormals: true,
    requestWaterMask: true,
    requestMetadata: true,
  });
  // A tile the server fails to deliver (Cesium retries, but the test must hear of it).
  provider.errorEvent.addEventListener((e) => fail(`terrain: ${e.message}`));
  viewer.terrainProvider = provider;
  if (testMode) {
    // Only the tileset's own surface: outside its bounds Cesium would draw the ellipsoid (or
    // upsampled coarse tiles), which hides the skyline of the data and is not what ridge render draws.
    const [west, south, east, north] = tileset.bounds;
    globe.cartographicLimitRectangle = Cesium.Rectangle.fromDegrees(west, south, east, north);
    // The whole globe again (the test's hole check: clipped, a screen column near the image's
    // sides may leave the footprint and come back, which is not a hole).
    window.ridgeUnclip = () => {
      globe.cartographicLimitRectangle = Cesium.Rectangle.MAX_VALUE;
      status.ready = false;
    };
  }
  setCamera(tileset);

  let settled = 0;
  scene.postRender.addEventListener(() => {
    status.frames++;
    status.tilesLoaded = globe.tilesLoaded;
    settled = globe.tilesLoaded ? settled + 1 : 0;
    if (!status.ready && settled >= SETTLED_FRAMES) {
      const c = camera.positionCartographic;
      Object.assign(status, {
        ready: true,
        // Cesium's frustum fov is the horizontal one when the canvas is wider than tall.
        fovyDegrees: Cesium.Math.toDegrees(camera.frustum.fovy),
        canvas: [scene.canvas.width, scene.canvas.height],
        camera: {
          lon: Cesium.Math.toDegrees(c.longitude),
          lat: Cesium.Math.toDegrees(c.latitude),
          height: c.height,
          heading: Cesium.Math.toDegrees(camera.heading),
          pitch: Cesium.Math.toDegrees(camera.pitch),
        },
      });
    }
  });
}

main().catch(fail);
