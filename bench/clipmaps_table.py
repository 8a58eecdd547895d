#!/usr/bin/env python3
"""The clipmaps thesis's Table 5.2 (gpu-geometry-clipmaps-thesis.txt, §5.2) over a ridge archive.

For each level size n (1023, 511, 255, 127) it runs `ridge bench --lod clipmaps,n=N` three ways,
as the thesis's tests, and a fourth:
  Test 1   a static camera (the fly-over's first pose, crawling at 1 mm/s), frustum culling on;
  Test 2   the same without culling;
  Test 3   the fly-over at a constant speed, culling on;
  Test 3x  the same at 10 times the speed.
and prints per test the average frame rate, the triangles drawn, the level shifts per frame,
where the render thread's frame time goes, the ratio of Test 3 to Test 1 (goal: >= 0.9) and the
frames slower than twice the median (goal: none while moving).

The thesis splits the frame into disk to memory, memory processing, memory to GPU and
rendering, all on its render thread. In ridge reading and decoding run on the stream workers
(their bytes are reported, their time is not the render thread's); the render thread's frame is
selection (placing the windows), residency (requests and uploads) and the rest (level-texture
writes, the draw, waiting for the GPU).

usage: bench/clipmaps_table.py ARCHIVE [--ridge build/ridge] [--frames 300] [--size 1920x1080]
                               [--speed 250] [--sizes 1023,511,255,127] [--levels 3]
                               [--path flyover|POSES]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile


def run(ridge, archive, n, levels, frames, size, speed, cull, extra, path="flyover"):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "bench.json")
        spec = f"clipmaps,n={n}" + (f",levels={levels}" if levels else "")
        cmd = [ridge, "bench", archive, "--lod", spec, "--path", path,
               "--speed", str(speed), "--frames", str(frames), "--size", size,
               "--json-file", out] + ([] if cull else ["--no-cull"]) + extra
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        with open(out) as f:
            return json.load(f)


def summarise(report):
    # From the first frame that draws every level the view wants: before it the first windows
    # are streaming in (and frame 0 compiles the shaders), which the thesis's tests, started
    # with their data loaded, do not count.
    all_frames = report["frames"]
    start = next((k for k, f in enumerate(all_frames)
                  if k > 0 and f["levels_drawn"] == f["levels_wanted"]), len(all_frames) - 1)
    frames = all_frames[start:]
    total = sum(f["frame_ms"] for f in frames)
    select = sum(f["select_ms"] for f in frames)
    load = sum(f["load_ms"] for f in frames)
    times = sorted(f["frame_ms"] for f in frames)
    median = times[len(times) // 2]
    return {
        "fps": 1000.0 * len(frames) / total,
        "triangles": sum(f["triangles"] for f in frames) / len(frames),
        "shifts": sum(f["level_shifts"] for f in frames) / len(frames),
        "select": select / total,
        "load": load / total,
        "rest": 1.0 - (select + load) / total,
        "read_mib": sum(f["bytes_read"] for f in frames) / 1048576.0,
        "decoded_mib": sum(f["bytes_decoded"] for f in frames) / 1048576.0,
        "over_twice_median": sum(1 for t in times if t > 2.0 * median),
        "waiting": sum(1 for f in frames if f["levels_drawn"] < f["levels_wanted"]),
        "frames": len(frames),
        "warmup": start,
    }


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("archive")
    p.add_argument("--ridge", default=os.path.join(os.path.dirname(__file__), "..", "build", "ridge"))
    p.add_argument("--frames", type=int, default=300)
    p.add_argument("--size", default="1920x1080")
    p.add_argument("--speed", type=float, default=250.0, help="Test 3's speed, m/s")
    p.add_argument("--sizes", default="1023,511,255,127")
    p.add_argument("--levels", type=int, default=3, help="L (the thesis: 3); 0: ridge's default")
    p.add_argument("--extra", default="", help="more ridge bench options, space separated")
    p.add_argument("--path", default="flyover",
                   help="ridge bench --path: flyover, or a file of poses, one a frame (Test 1 and "
                        "2 stand at its first, Test 3 takes each, Test 3 x10 every tenth; --speed "
                        "does not apply)")
    a = p.parse_args()
    extra = a.extra.split()
    # A file of poses is one pose a frame (ridge bench), so --speed does not apply: Test 1 and 2
    # stand at its first pose, Test 3 takes it as it is, Test 3 ×10 every tenth pose.
    paths = {"static": a.path, "moving": a.path, "fast": a.path}
    scratch = tempfile.TemporaryDirectory()
    if a.path != "flyover":
        with open(a.path) as f:
            poses = [line for line in f if line.strip() and not line.lstrip().startswith("#")]
        for name, chosen in (("static", poses[:1]), ("moving", poses), ("fast", poses[::10])):
            paths[name] = os.path.join(scratch.name, name + ".txt")
            with open(paths[name], "w") as f:
                f.writelines(chosen)
    rows = []
    for n in [int(s) for s in a.sizes.split(",")]:
        tests = {
            "Test 1": run(a.ridge, a.archive, n, a.levels, a.frames, a.size, 0.001, True, extra,
                          paths["static"]),
            "Test 2": run(a.ridge, a.archive, n, a.levels, a.frames, a.size, 0.001, False, extra,
                          paths["static"]),
            "Test 3": run(a.ridge, a.archive, n, a.levels, a.frames, a.size, a.speed, True, extra,
                          paths["moving"]),
            "Test 3 ×10": run(a.ridge, a.archive, n, a.levels, a.frames, a.size, 10 * a.speed,
                              True, extra, paths["fast"]),
        }
        gl = tests["Test 1"].get("gl_renderer", "")
        s = {k: summarise(v) for k, v in tests.items()}
        for name, r in s.items():
            ratio = r["fps"] / s["Test 1"]["fps"]
            rows.append((n, name, r, ratio))
        print(f"n = {n} done", file=sys.stderr)
    motion = f"Test 3 at {a.speed} m/s" if a.path == "flyover" else f"poses of {a.path}"
    print(f"archive {a.archive}, L = {a.levels or 'default'}, {a.size}, {a.frames} frames "
          f"(counted from the first drawing every wanted level), {motion}"
          + (f", {gl}" if gl else ""))
    print("| n | test | fps | × Test 1 | triangles | shifts/frame | select | residency | "
          "writes + draw | read / decoded MiB (workers) | frames > 2× median | frames with "
          "levels waiting |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for n, name, r, ratio in rows:
        print(f"| {n} | {name} | {r['fps']:.1f} | {ratio:.2f} | {r['triangles']:,.0f} | "
              f"{r['shifts']:.2f} | {100 * r['select']:.1f} % | {100 * r['load']:.1f} % | "
              f"{100 * r['rest']:.1f} % | {r['read_mib']:.1f} / {r['decoded_mib']:.1f} | "
              f"{r['over_twice_median']} of {r['frames']} | {r['waiting']} |")


if __name__ == "__main__":
    main()
