"""The driver's command line: parsing, validation (exit 2 naming the option) and the search
for the ridge binary. Nothing here imports distributed, so bad arguments fail fast."""

import argparse
import os
import re
import shutil
import sys

PROG = "python3 -m ridge_dask"
# The repository root: this package lives in ROOT/python/ridge_dask/.
REPO_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# Where a CMake build of the repository leaves the binary, tried after PATH in this order
# (the contract names build/apps/ridge/ridge; apps/ridge/CMakeLists.txt currently sets
# RUNTIME_OUTPUT_DIRECTORY to the build root, hence build/ridge).
DEFAULT_RIDGE_CANDIDATES = ("build/apps/ridge/ridge", "build/ridge")

DESCRIPTION = """\
Build a .ridge archive in shards on a Dask cluster: `ridge plan` here, then one
`ridge build --shard I` task per shard for the summaries, the coordinator's rounds (with
observation tasks while it asks for them), one encode task per shard, and `ridge merge` here.
Without --scheduler a LocalCluster of --workers single-threaded worker processes runs the
tasks; with it, an existing cluster is used as it is (its workers must see the ridge binary
and the work directory at the same paths)."""

EPILOG = """\
build options:
  Everything after `--` goes verbatim to `ridge plan` (the shard steps read it from the
  plan), e.g.  -- --patch 129 --codec progressive --max-error 1

test hook:
  RIDGE_DASK_FAIL_ONCE="STEP:SHARD[,STEP:SHARD...]" (STEP: summary, observe, encode, or
  coordinate with the round as SHARD) makes the first attempt of that task fail before ridge
  runs; a marker in the work directory lets the retry succeed on any worker. The retries
  show in the report's attempts.

exit status: 0 success, 1 a step failed (nothing is written at OUTPUT), 2 bad arguments."""


class UsageError(Exception):
    """A bad argument: the message names the option."""


def _non_negative_int(text):
    try:
        value = int(text, 10)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a non-negative integer, not {text!r}")
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be a non-negative integer, not {text!r}")
    return value


def _positive_int(text):
    try:
        value = int(text, 10)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a positive integer, not {text!r}")
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, not {text!r}")
    return value


def build_parser():
    parser = argparse.ArgumentParser(
        prog=PROG, description=DESCRIPTION, epilog=EPILOG,
        usage=f"{PROG} INPUT... -o OUT.ridge --shard-level K [options] [-- BUILD OPTIONS...]",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("inputs", nargs="*", metavar="INPUT",
                        help="input rasters (tiles of a mosaic), passed to `ridge plan`")
    parser.add_argument("-o", "--output", required=True, metavar="OUT.ridge",
                        help="the archive to write (only once every shard succeeded)")
    parser.add_argument("--shard-level", required=True, type=_non_negative_int, metavar="K",
                        help="the pyramid level whose nodes are the shards (non-negative)")
    parser.add_argument("--input-file-list", metavar="FILE",
                        help="a text file listing inputs, forwarded to `ridge plan`")
    parser.add_argument("--work", metavar="DIR",
                        help="work directory for the plan and the shards' files "
                             "(default: OUT.ridge.work); reuse it to skip unchanged shards")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="use the existing Dask cluster at ADDRESS (--workers is ignored)")
    parser.add_argument("--workers", type=_positive_int, default=os.cpu_count() or 1,
                        metavar="N", help="LocalCluster worker processes, one thread each "
                                          "(default: the CPU count, %(default)s here)")
    parser.add_argument("--threads-per-task", type=_positive_int, default=1, metavar="T",
                        help="OpenMP threads of each ridge step (OMP_NUM_THREADS; default "
                             "%(default)s: one core a task, as the workers are single-threaded)")
    parser.add_argument("--retries", type=_non_negative_int, default=2, metavar="R",
                        help="Dask retries of a failed task (default: %(default)s)")
    parser.add_argument("--ridge", metavar="PATH",
                        help="the ridge binary (default: `ridge` on PATH, else the "
                             "repository's build/apps/ridge/ridge or build/ridge)")
    parser.add_argument("--no-skip", action="store_true",
                        help="rebuild every shard (no --skip-unchanged to ridge)")
    parser.add_argument("--report", metavar="FILE.json",
                        help="also write the report (phases, tasks, totals) as JSON")
    parser.add_argument("-q", "--quiet", action="store_true",
                        help="no progress and no table (errors only; see --report)")
    parser.add_argument("-v", "--verbose", action="store_true",
                        help="let distributed log at INFO")
    return parser


def split_build_options(argv):
    """(driver arguments, build options): the build options are what follows the first `--`."""
    argv = list(argv)
    if "--" in argv:
        index = argv.index("--")
        return argv[:index], argv[index + 1:]
    return argv, []


def _gdal_special(name):
    """Names GDAL resolves itself (/vsi..., URLs, DRIVER:... connection strings) are not
    checked for existence here; ridge plan reports them."""
    return name.startswith("/vsi") or "://" in name or re.match(r"^[A-Z][A-Z0-9_]*:", name)


def find_ridge(explicit):
    """The ridge binary as an absolute path, or UsageError naming --ridge."""
    if explicit:
        path = explicit if os.sep in explicit else (shutil.which(explicit) or explicit)
        path = os.path.abspath(path)
        if not (os.path.isfile(path) and os.access(path, os.X_OK)):
            raise UsageError(f"--ridge: {explicit!r} is not an executable file")
        return path
    found = shutil.which("ridge")
    if found:
        return os.path.abspath(found)
    for relative in DEFAULT_RIDGE_CANDIDATES:
        path = os.path.join(REPO_ROOT, relative)
        if os.path.isfile(path) and os.access(path, os.X_OK):
            return path
    raise UsageError("--ridge: no ridge binary on PATH nor at "
                     + " or ".join(os.path.join(REPO_ROOT, r) for r in DEFAULT_RIDGE_CANDIDATES)
                     + "; pass --ridge PATH")


def _check_parent_dir(option, path):
    parent = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(parent):
        raise UsageError(f"{option}: the directory {parent!r} of {path!r} does not exist")
    if os.path.isdir(path):
        raise UsageError(f"{option}: {path!r} is a directory")


def validate(args):
    """Checks what argparse cannot and makes every path absolute (the steps run on workers
    whose working directory may differ). Raises UsageError."""
    if not args.inputs and not args.input_file_list:
        raise UsageError("INPUT: give at least one input or --input-file-list FILE")
    inputs = []
    for name in args.inputs:
        if _gdal_special(name):
            inputs.append(name)
        elif not os.path.exists(name):
            raise UsageError(f"INPUT: {name!r} does not exist")
        else:
            inputs.append(os.path.abspath(name))
    args.inputs = inputs
    if args.input_file_list:
        if not os.path.isfile(args.input_file_list):
            raise UsageError(f"--input-file-list: {args.input_file_list!r} is not a file")
        args.input_file_list = os.path.abspath(args.input_file_list)
    _check_parent_dir("-o/--output", args.output)
    args.output = os.path.abspath(args.output)
    args.work = os.path.abspath(args.work or args.output + ".work")
    if os.path.exists(args.work) and not os.path.isdir(args.work):
        raise UsageError(f"--work: {args.work!r} exists and is not a directory")
    if args.report:
        _check_parent_dir("--report", args.report)
        args.report = os.path.abspath(args.report)
    args.ridge = find_ridge(args.ridge)
    return args


def parse(argv=None):
    """The validated options, with .build_options; exits 2 with a message naming the option
    on bad arguments."""
    argv = sys.argv[1:] if argv is None else argv
    driver_argv, build_options = split_build_options(argv)
    parser = build_parser()
    # Inputs may come before, between or after the options.
    args = parser.parse_intermixed_args(driver_argv)
    args.build_options = build_options
    try:
        return validate(args)
    except UsageError as error:
        parser.error(str(error))
