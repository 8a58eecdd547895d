"""The ridge command lines of a sharded build, in one place (the CLI contract).

Every step runs with --json and prints one JSON object on its last line of stdout; a failure
exits non-zero with `ridge: ...` on stderr. Paths are absolute (the driver makes them so)
because the steps run on workers whose working directory may differ.
"""

import os


def plan_path(work):
    return os.path.join(work, "plan.json")


def summary_path(work, shard):
    return os.path.join(work, f"shard-{shard}.summary")


def observation_path(work, shard, round_):
    return os.path.join(work, f"shard-{shard}.obs-{round_}")


def top_path(work, round_):
    return os.path.join(work, f"top-{round_}.top")


def segment_path(work, shard):
    return os.path.join(work, f"shard-{shard}.seg")


def plan_args(inputs, input_file_list, shard_level, plan, build_options):
    """`ridge plan INPUT... [--input-file-list FILE] --shard-level K -o PLAN --json BUILD...`:
    run by the driver itself; the BUILD OPTIONS (after the driver's `--`) go only here, the
    later steps read them from the plan."""
    args = ["plan"] + list(inputs)
    if input_file_list:
        args += ["--input-file-list", input_file_list]
    args += ["--shard-level", str(shard_level), "-o", plan, "--json"]
    return args + list(build_options)


def _skip(skip_unchanged):
    return ["--skip-unchanged"] if skip_unchanged else []


def summary_args(plan, shard, output, skip_unchanged):
    """`ridge build --plan PLAN --shard I --summary -o SHARD.summary [--skip-unchanged]`."""
    return (["build", "--plan", plan, "--shard", str(shard), "--summary", "-o", output]
            + _skip(skip_unchanged) + ["--json"])


def coordinate_args(plan, summaries, output, previous_top=None, observations=()):
    """`ridge build --plan PLAN --coordinate --summaries S... [--top PREV --observations O...]
    -o TOP`: every round is given all the summaries; rounds after the first also the previous
    top file and every shard's observations of it."""
    args = ["build", "--plan", plan, "--coordinate", "--summaries"] + list(summaries)
    if previous_top is not None:
        args += ["--top", previous_top, "--observations"] + list(observations)
    return args + ["-o", output, "--json"]


def observe_args(plan, shard, top, output, skip_unchanged):
    """`ridge build --plan PLAN --shard I --observe TOP -o SHARD.obs-N [--skip-unchanged]`."""
    return (["build", "--plan", plan, "--shard", str(shard), "--observe", top, "-o", output]
            + _skip(skip_unchanged) + ["--json"])


def encode_args(plan, shard, top, output, skip_unchanged):
    """`ridge build --plan PLAN --shard I --top FINAL_TOP -o SHARD.seg [--skip-unchanged]`."""
    return (["build", "--plan", plan, "--shard", str(shard), "--top", top, "-o", output]
            + _skip(skip_unchanged) + ["--json"])


def merge_args(plan, top, segments, output):
    """`ridge merge PLAN FINAL_TOP SEG... -o OUTPUT` with the segments in shard id order;
    ridge writes OUTPUT atomically."""
    return ["merge", plan, top] + list(segments) + ["-o", output, "--json"]
