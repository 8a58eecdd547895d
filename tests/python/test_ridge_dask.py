"""python/ridge_dask, the sharded build on Dask, against the real ridge binary.

Run by tests/python/run-ctest.sh (which skips with 77 without distributed, gdal_translate or
the binary), or by hand:
  RIDGE_BIN=build/ridge PYTHONPATH=python /usr/bin/python3 tests/python/test_ridge_dask.py -v

The fixture is tests/data/everest_crop.tif (301 x 203 Int16, EPSG:4326) cut into four GeoTIFF
tiles that share their edge column and row like SRTM tiles; `ridge plan` mosaics them into a
VRT next to the plan, and every sharded archive must equal, byte for byte, `ridge build` of
that same VRT path with the same options.
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest
import warnings
import xml.etree.ElementTree as ElementTree

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PYTHON_DIR = os.path.join(ROOT, "python")
EVEREST = os.path.join(ROOT, "tests", "data", "everest_crop.tif")
RIDGE = os.environ.get("RIDGE_BIN", "")
PATCH_OPTIONS = ["--patch", "17"]
SHARD_LEVEL = "2"
# (xoff, yoff, xsize, ysize) in everest_crop: columns 0..150 and 150..300, rows 0..101 and
# 101..202, so neighbours share column 150 and row 101.
TILE_WINDOWS = [(0, 0, 151, 102), (150, 0, 151, 102), (0, 101, 151, 102), (150, 101, 151, 102)]
CODECS = {
    "lossless": (["--codec", "lossless"], [1, 2, 4]),
    "progressive": (["--codec", "progressive", "--max-error", "1"], [1, 4]),
    "jpeg2000": (["--codec", "jpeg2000", "--max-error", "1"], [1, 4]),
}
# Coordinator rounds per codec in the contract: progressive asks for one round of observations.
COORDINATOR_ROUNDS = {"lossless": 1, "progressive": 2, "jpeg2000": 1}


def setUpModule():
    if not RIDGE or not os.path.isfile(RIDGE):
        raise unittest.SkipTest("RIDGE_BIN does not name the ridge binary")
    if shutil.which("gdal_translate") is None:
        raise unittest.SkipTest("no gdal_translate (apt-get install gdal-bin)")
    try:
        import distributed  # noqa: F401
    except ImportError:
        raise unittest.SkipTest("no distributed (apt-get install python3-distributed)")


def run(command, **kwargs):
    return subprocess.run([str(c) for c in command], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, **kwargs)


def make_tiles(directory):
    """The four tiles of everest_crop, tile-0 (north-west) to tile-3 (south-east)."""
    os.makedirs(directory, exist_ok=True)
    tiles = []
    for index, window in enumerate(TILE_WINDOWS):
        path = os.path.join(directory, f"tile-{index}.tif")
        result = run(["gdal_translate", "-q", "-srcwin", *window, EVEREST, path])
        if result.returncode != 0:
            raise RuntimeError(f"gdal_translate failed: {result.stderr}")
        tiles.append(path)
    return tiles


def read_json(path):
    with open(path, encoding="utf-8") as stream:
        return json.load(stream)


def read_bytes(path):
    with open(path, "rb") as stream:
        return stream.read()


def mosaic_path(work):
    """The VRT `ridge plan` wrote next to the plan (the plan's "source" path)."""
    return read_json(os.path.join(work, "plan.json"))["source"]["path"]


def plan_windows(work):
    """{shard id: (x, y, w, h)} from the plan."""
    return {int(shard["id"]): tuple(shard["window"])
            for shard in read_json(os.path.join(work, "plan.json"))["shards"]}


def footprint_in_mosaic(work, tile):
    """The tile's (x, y, w, h) in the mosaic's pixels: the plan's "footprint" of the input, else
    its source's DstRect in the plan's VRT, else the tile's window in everest_crop (the
    mosaic's origin is the north-west tile's)."""
    name = os.path.basename(tile)
    plan = read_json(os.path.join(work, "plan.json"))
    for entry in plan.get("inputs", []):
        if os.path.basename(str(entry.get("path", ""))) == name and "footprint" in entry:
            return tuple(int(v) for v in entry["footprint"])
    vrt = plan["source"]["path"]
    if vrt.lower().endswith(".vrt"):
        for source in ElementTree.parse(vrt).getroot().iter():
            filename = source.find("SourceFilename")
            rect = source.find("DstRect")
            if filename is not None and rect is not None and \
                    os.path.basename(filename.text or "") == name:
                return tuple(int(float(rect.get(k)))
                             for k in ("xOff", "yOff", "xSize", "ySize"))
    return TILE_WINDOWS[int(name[len("tile-"):-len(".tif")])]


def intersects(a, b):
    ax, ay, aw, ah = a
    bx, by, bw, bh = b
    return ax < bx + bw and bx < ax + aw and ay < by + bh and by < ay + ah


class RidgeDaskTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="ridge_dask_test.")
        cls.tiles = make_tiles(os.path.join(cls.tmp, "tiles"))
        cls.cluster = None
        cls.client = None

    @classmethod
    def tearDownClass(cls):
        if cls.client is not None:
            cls.client.close()
            cls.cluster.close()
        if not os.environ.get("RIDGE_DASK_TEST_KEEP"):
            shutil.rmtree(cls.tmp, ignore_errors=True)

    @classmethod
    def scheduler_address(cls):
        """A LocalCluster of this process's, shared by the tests that do not vary the worker
        count: the driver connects to it with --scheduler (and leaves it running)."""
        if cls.client is None:
            # Quiet workers (they read DASK_LOGGING when they import distributed): the tests
            # that fail tasks on purpose would fill the log with "Compute Failed" warnings.
            os.environ["DASK_LOGGING"] = repr({"distributed": "warning",
                                               "distributed.worker": "error"})
            import distributed
            with warnings.catch_warnings():  # tornado's make_current, from distributed 2022.12
                warnings.simplefilter("ignore", DeprecationWarning)
                cls.cluster = distributed.LocalCluster(
                    n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                    scheduler_kwargs={"dashboard": False})
            cls.client = distributed.Client(cls.cluster)
        return cls.cluster.scheduler_address

    def directory(self, name):
        path = os.path.join(self.tmp, name)
        os.makedirs(path, exist_ok=True)
        return path

    def driver(self, inputs, output, work, build_options, *extra, env=None, expect=0):
        """Runs python3 -m ridge_dask and returns the CompletedProcess (asserting its status
        unless expect is None)."""
        environment = dict(os.environ)
        environment["PYTHONPATH"] = os.pathsep.join(
            [PYTHON_DIR] + ([environment["PYTHONPATH"]] if environment.get("PYTHONPATH") else []))
        environment.pop("RIDGE_DASK_FAIL_ONCE", None)
        environment.update(env or {})
        command = [sys.executable, "-m", "ridge_dask", *inputs, "-o", output, "--work", work,
                   "--shard-level", SHARD_LEVEL, "--ridge", RIDGE, *extra, "--", *build_options]
        result = run(command, env=environment)
        if expect is not None:
            self.assertEqual(result.returncode, expect,
                             f"{' '.join(map(str, command))}\nstdout:\n{result.stdout}\n"
                             f"stderr:\n{result.stderr}")
        return result

    def single_build(self, vrt, build_options, output):
        result = run([RIDGE, "build", vrt, "-o", output, *build_options, "-q"])
        self.assertEqual(result.returncode, 0, result.stderr)
        return read_bytes(output)

    def assert_same_archive(self, path, expected, what):
        self.assertTrue(read_bytes(path) == expected,
                        f"{what}: {path} differs from the single-process build "
                        f"({os.path.getsize(path)} vs {len(expected)} bytes)")

    # --- (b) the sharded archive is the single-process archive ---------------------------

    def test_sharded_builds_equal_the_single_build_for_every_codec_and_worker_count(self):
        for codec, (codec_options, worker_counts) in CODECS.items():
            with self.subTest(codec=codec):
                self.check_codec(codec, PATCH_OPTIONS + codec_options, worker_counts)

    def check_codec(self, codec, options, worker_counts):
        base = self.directory(f"codec-{codec}")
        # One work directory for every worker count: the plan's VRT keeps its path, and
        # --no-skip makes every run build every shard again.
        work = os.path.join(base, "work")
        outputs = {}
        for workers in worker_counts:
            output = os.path.join(base, f"workers-{workers}.ridge")
            report_path = output + ".json"
            quiet = ["-q"] if workers != 2 else []
            result = self.driver(self.tiles, output, work, options, "--workers", workers,
                                 "--no-skip", "--report", report_path, *quiet)
            if quiet:
                self.assertEqual(result.stderr, "", "a quiet run prints nothing on stderr "
                                 "(no distributed logs)")
            else:
                self.assertIn("samples/s per core", result.stdout)
            report = read_json(report_path)
            shards = sorted(plan_windows(work))
            self.assertEqual(report["workers"], workers)
            self.assertEqual(report["rebuilt"]["summary"], shards)
            self.assertEqual(report["rebuilt"]["encode"], shards)
            self.assertEqual(report["retries"], 0)
            self.assertEqual(report["phases"]["coordinate"]["tasks"], COORDINATOR_ROUNDS[codec])
            self.assertEqual(report["output_bytes"], os.path.getsize(output))
            self.assertGreater(report["phases"]["summary"]["samples"], 0)
            outputs[workers] = output
        vrt = mosaic_path(work)
        single = os.path.join(base, "single.ridge")
        expected = self.single_build(vrt, options, single)
        for workers, output in outputs.items():
            self.assert_same_archive(output, expected, f"{codec}, {workers} worker(s)")
        verify = run([RIDGE, "verify", single, "--source", vrt])
        self.assertEqual(verify.returncode, 0, verify.stdout + verify.stderr)

    # --- (c) retries ---------------------------------------------------------------------

    def test_a_task_that_fails_once_is_retried_and_counted(self):
        base = self.directory("retry")
        work, output = os.path.join(base, "work"), os.path.join(base, "retry.ridge")
        options = PATCH_OPTIONS + ["--codec", "lossless"]
        report_path = os.path.join(base, "report.json")
        self.driver(self.tiles, output, work, options, "--scheduler", self.scheduler_address(),
                    "--report", report_path, "-q",
                    env={"RIDGE_DASK_FAIL_ONCE": "summary:1,encode:2"})
        report = read_json(report_path)
        self.assertGreater(len(plan_windows(work)), 2, "the test needs shards 1 and 2")
        attempts = {(t["step"], t["shard"]): t["attempts"] for t in report["tasks"]}
        self.assertEqual(attempts[("summary", 1)], 2)
        self.assertEqual(attempts[("encode", 2)], 2)
        others = {key: n for key, n in attempts.items()
                  if key not in (("summary", 1), ("encode", 2))}
        self.assertEqual(set(others.values()), {1}, others)
        self.assertEqual(report["retries"], 2)
        expected = self.single_build(mosaic_path(work), options, os.path.join(base, "single.ridge"))
        self.assert_same_archive(output, expected, "after retries")

    def test_a_task_that_keeps_failing_stops_the_build_without_an_output(self):
        base = self.directory("failure")
        work, output = os.path.join(base, "work"), os.path.join(base, "failed.ridge")
        result = self.driver(self.tiles, output, work, PATCH_OPTIONS + ["--codec", "lossless"],
                             "--scheduler", self.scheduler_address(), "--retries", "0", "-q",
                             env={"RIDGE_DASK_FAIL_ONCE": "encode:0"}, expect=1)
        self.assertIn("encode of shard 0", result.stderr)
        self.assertIn("injected failure", result.stderr)
        self.assertFalse(os.path.exists(output))

    # --- (d) --skip-unchanged ------------------------------------------------------------

    def test_a_changed_tile_rebuilds_exactly_the_shards_over_it(self):
        base = self.directory("skip")
        tiles = make_tiles(os.path.join(base, "tiles"))
        work = os.path.join(base, "work")
        options = PATCH_OPTIONS + ["--codec", "lossless"]
        scheduler = self.scheduler_address()
        first = os.path.join(base, "first.ridge")
        self.driver(tiles, first, work, options, "--scheduler", scheduler,
                    "--report", first + ".json", "-q")
        windows = plan_windows(work)
        self.assertEqual(read_json(first + ".json")["rebuilt"]["summary"], sorted(windows))

        # Every sample of tile 0 one metre higher (same size and georeference): -scale with
        # the ratio 1 and the offset 1.
        changed = tiles[0] + ".changed.tif"
        result = run(["gdal_translate", "-q", "-scale", "0", "10000", "1", "10001",
                      tiles[0], changed])
        self.assertEqual(result.returncode, 0, result.stderr)
        os.replace(changed, tiles[0])

        second = os.path.join(base, "second.ridge")
        self.driver(tiles, second, work, options, "--scheduler", scheduler,
                    "--report", second + ".json", "-q")
        report = read_json(second + ".json")
        vrt = mosaic_path(work)
        footprint = footprint_in_mosaic(work, tiles[0])
        expected = sorted(i for i, window in plan_windows(work).items()
                          if intersects(window, footprint))
        self.assertTrue(0 < len(expected) < len(windows),
                        f"tile 0 at {footprint} should lie under some shards, not all: "
                        f"{windows}")
        for step in ("summary", "encode"):
            self.assertEqual(report["rebuilt"][step], expected,
                             f"{step}: tile 0 at {footprint}, shard windows {windows}")
            skipped = sorted(t["shard"] for t in report["tasks"]
                             if t["step"] == step and t["skipped"])
            self.assertEqual(skipped, sorted(set(windows) - set(expected)))
        single = self.single_build(vrt, options, os.path.join(base, "single.ridge"))
        self.assert_same_archive(second, single, "after the change")
        self.assertNotEqual(read_bytes(first), single)

    # --- (e) bad arguments ---------------------------------------------------------------

    def test_bad_arguments_exit_2_naming_the_option(self):
        base = self.directory("arguments")
        output = os.path.join(base, "never.ridge")
        valid = {"--shard-level": "1", "--workers": "1", "--retries": "0"}
        for option, value in (("--shard-level", "-1"), ("--workers", "0"), ("--retries", "-1")):
            with self.subTest(option=option):
                arguments = {**valid, option: value}
                command = [sys.executable, "-m", "ridge_dask", self.tiles[0], "-o", output,
                           "--ridge", RIDGE] + [a for pair in arguments.items() for a in pair]
                result = run(command, env={**os.environ, "PYTHONPATH": PYTHON_DIR})
                self.assertEqual(result.returncode, 2, result.stderr)
                self.assertIn(option, result.stderr)
        self.assertFalse(os.path.exists(output))

    def test_a_missing_input_is_named_and_writes_nothing(self):
        base = self.directory("missing")
        output = os.path.join(base, "never.ridge")
        missing = os.path.join(base, "no-such-tile.tif")
        result = self.driver([self.tiles[0], missing], output, os.path.join(base, "work"),
                             PATCH_OPTIONS, expect=None)
        self.assertNotEqual(result.returncode, 0)
        self.assertIn("no-such-tile.tif", result.stderr)
        self.assertFalse(os.path.exists(output))


if __name__ == "__main__":
    unittest.main()
