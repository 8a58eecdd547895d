"""The sharded build: plan here, shard tasks on the Dask cluster, merge here.

  plan        `ridge plan` in this process (it is quick and its errors are the user's).
  summary     one task per shard.
  coordinate  ONE task on the cluster per round, not run here: like the shard tasks it gets
              Dask's retries and uses a worker's memory and paths. While it reports
              pending_stage > 0, an `observe` task per shard follows, and the next round is
              given the previous top file and every shard's observations.
  encode      one task per shard with the final top file.
  merge       `ridge merge` in this process (OUTPUT is written where the driver runs, and
              only after every shard succeeded; ridge writes it atomically).

A task that still fails after --retries retries stops the build (exit 1) with a message
naming the step, the shard and ridge's stderr; the other tasks are stopped through the run
directory's stop file (see tasks.py).
"""

import json
import logging
import os
import shutil
import signal
import sys
import time
import uuid
from contextlib import ExitStack

from . import cli, commands, report as reports, tasks
from .progress import Progress

# A guard against a coordinator that never settles (the progressive codec needs one round).
MAX_COORDINATOR_ROUNDS = 32
# Seconds to let abandoned tasks notice the stop file before their futures are cancelled.
STOP_GRACE_SECONDS = 15
# Seconds to wait for a worker of an existing cluster (--scheduler).
WORKER_WAIT_SECONDS = 120


class DriverError(Exception):
    """The build failed; the message says which step and why."""


def fail_specs_from_environment():
    """The RIDGE_DASK_FAIL_ONCE test hook's "STEP:SHARD" entries (see tasks.fail_once)."""
    value = os.environ.get("RIDGE_DASK_FAIL_ONCE", "")
    return tuple(entry.strip() for entry in value.split(",") if entry.strip())


def _silence_distributed(verbose):
    """distributed logs INFO to stderr by default, in this process and in the worker processes
    (which inherit the environment and read it when they import distributed). Without
    --verbose: WARNING and above, except the workers' "Compute Failed" warnings (with every
    task argument), which a retried task would print per attempt: the driver reports a
    failure itself, with ridge's stderr. A literal dict, since a logger's dotted name cannot be
    spelled in a DASK_LOGGING__... variable."""
    if verbose:
        os.environ["DASK_LOGGING"] = repr({"distributed": "info"})
    else:
        os.environ["DASK_LOGGING"] = repr({"distributed": "warning",
                                           "distributed.worker": "error"})
    return logging.INFO if verbose else logging.WARNING


def import_distributed(verbose):
    """Imports distributed quietly (DriverError if it is missing); returns the log level."""
    level = _silence_distributed(verbose)  # before distributed is imported
    try:
        import distributed  # noqa: F401
    except ImportError as error:
        raise DriverError(f"{sys.executable} cannot import distributed ({error}); on Debian: "
                          "apt-get install python3-distributed, and run /usr/bin/python3") from None
    logging.getLogger("distributed").setLevel(level)
    if not verbose:
        logging.getLogger("distributed.worker").setLevel(logging.ERROR)
    return level


class Build:
    def __init__(self, options, progress):
        self.options = options
        self.progress = progress
        self.run_dir = os.path.join(options.work, ".ridge_dask", uuid.uuid4().hex)
        self.cwd = os.getcwd()
        self.fail_specs = fail_specs_from_environment()
        self.plan_file = commands.plan_path(options.work)
        self.shards = []
        self.plan_info = {}
        self.records = []
        self.phase_records = {}
        self.phase_wall = {}
        self.local_phases = {}
        self.client = None
        self.in_flight = []
        self.final_top = None
        self.workers = 0
        self.scheduler = "local"

    # --- local steps ---------------------------------------------------------------------

    def run_local(self, step, args):
        try:
            result, _ = tasks.run_ridge(self.options.ridge, args, step, cwd=self.cwd)
        except tasks.RidgeStepError as error:
            raise DriverError(str(error)) from None
        return result

    def plan(self):
        start = time.monotonic()
        self.progress.start("plan", 1)
        args = commands.plan_args(self.options.inputs, self.options.input_file_list,
                                  self.options.shard_level, self.plan_file,
                                  self.options.build_options)
        result = self.run_local("plan", args)
        self.plan_file = os.path.abspath(result.get("plan") or self.plan_file)
        plan_document = {}
        try:
            with open(self.plan_file, encoding="utf-8") as stream:
                plan_document = json.load(stream)
        except (OSError, ValueError):
            pass
        shards = result.get("shards") or plan_document.get("shards") or []
        try:
            ids = [int(shard["id"]) for shard in shards]
        except (KeyError, TypeError, ValueError):
            raise DriverError(f"plan: shards without integer ids in {self.plan_file}") from None
        if not ids or len(set(ids)) != len(ids):
            raise DriverError(f"plan: no shards, or repeated shard ids, in {self.plan_file}")
        self.shards = sorted(ids)
        self.plan_info = {
            "path": self.plan_file,
            "hash": result.get("hash"),
            "layout_hash": result.get("layout_hash"),
            "shard_level": result.get("shard_level", self.options.shard_level),
            "shards": len(self.shards),
            "source": plan_document.get("source") or result.get("source"),
        }
        self.progress.advance()
        self.progress.finish(f"{len(self.shards)} shards")
        self.local_phases["plan"] = {"wall_seconds": round(time.monotonic() - start, 6),
                                     "shards": len(self.shards)}

    def merge(self):
        start = time.monotonic()
        self.progress.start("merge", 1)
        segments = [commands.segment_path(self.options.work, shard) for shard in self.shards]
        args = commands.merge_args(self.plan_file, self.final_top, segments,
                                   self.options.output)
        result = self.run_local("merge", args)
        if not os.path.isfile(self.options.output):
            raise DriverError(f"merge: ridge reported success but wrote no {self.options.output}")
        self.progress.advance()
        self.progress.finish(f"{result.get('patches', '?')} patches")
        self.local_phases["merge"] = {
            "wall_seconds": round(time.monotonic() - start, 6),
            "seconds": float(result.get("seconds", 0.0) or 0.0),
            "bytes": result.get("bytes"),
            "patches": result.get("patches"),
            "peak_rss_bytes": result.get("peak_rss_bytes"),
        }

    # --- the cluster ---------------------------------------------------------------------

    def open_cluster(self, stack):
        start = time.monotonic()
        self.progress.start("cluster", 1)
        level = import_distributed(self.options.verbose)
        import distributed
        try:
            # The worker side is sent by value: an existing cluster's workers need not
            # have this package importable (cloudpickle >= 2.0).
            import cloudpickle
            cloudpickle.register_pickle_by_value(tasks)
        except (ImportError, AttributeError, ValueError):
            pass
        if self.options.scheduler:
            self.scheduler = self.options.scheduler
            try:
                self.client = stack.enter_context(distributed.Client(self.options.scheduler))
                self.client.wait_for_workers(1, timeout=WORKER_WAIT_SECONDS)
            except (OSError, TimeoutError) as error:
                raise DriverError(f"--scheduler {self.options.scheduler}: {error}") from None
            self.workers = len(self.client.scheduler_info().get("workers", {}))
        else:
            # No dashboard, and the scheduler's HTTP server (health, metrics) on a free port:
            # with dashboard_address=None it would try 8787 and warn when that is taken.
            try:
                cluster = stack.enter_context(distributed.LocalCluster(
                    n_workers=self.options.workers, threads_per_worker=1, processes=True,
                    dashboard_address=":0", scheduler_kwargs={"dashboard": False},
                    silence_logs=level))
                self.client = stack.enter_context(distributed.Client(cluster))
            except Exception as error:  # whatever distributed raises: say what failed
                raise DriverError(f"cannot start a LocalCluster of {self.options.workers} "
                                  f"worker(s): {error}") from None
            self.workers = self.options.workers
        self.progress.advance()
        self.progress.finish(f"{self.workers} worker(s)"
                             + (f" at {self.scheduler}" if self.options.scheduler else ""))
        self.local_phases["cluster"] = {"wall_seconds": round(time.monotonic() - start, 6),
                                        "workers": self.workers}

    def stop_tasks(self, futures):
        """Stops the build's tasks: running ones kill their ridge when they see the stop
        file, queued ones fail at once; whatever is left after the grace time is cancelled."""
        import distributed
        os.makedirs(self.run_dir, exist_ok=True)
        with open(os.path.join(self.run_dir, "stop"), "w", encoding="utf-8"):
            pass
        pending = [future for future in futures if not future.done()]
        if not pending:
            return
        try:
            distributed.wait(pending, timeout=STOP_GRACE_SECONDS)
        except Exception:  # a timeout, or a cluster going away: cancel what is left
            pass
        try:
            self.client.cancel([future for future in pending if not future.done()])
        except Exception:
            pass

    def run_phase(self, phase, jobs, round_=None):
        """Runs one task per (id, args) job and returns their records in id order."""
        import distributed
        start = time.monotonic()
        label = phase if round_ is None else f"{phase} r{round_}"
        self.progress.start(label, len(jobs))
        futures = {}
        for ident, args in jobs:
            future = self.client.submit(
                tasks.ridge_task, self.options.ridge, args, phase, ident, self.run_dir,
                self.cwd, self.fail_specs, self.options.threads_per_task,
                key=f"{phase}-{ident}-{uuid.uuid4().hex}",
                pure=False, retries=self.options.retries)
            futures[future] = ident
        self.in_flight = list(futures)
        results = {}
        retries = 0
        for future in distributed.as_completed(list(futures)):
            ident = futures[future]
            if future.status != "finished":
                error = future.exception() if future.status == "error" else future.status
                attempts = tasks.count_attempts(self.run_dir, phase, ident)
                what = tasks.step_label(phase, ident)
                text = str(error)
                if text.startswith(what + ": "):
                    text = text[len(what) + 2:]
                self.progress.abandon()
                self.stop_tasks(list(futures))
                raise DriverError(f"{what} failed after {attempts} attempt(s): {text}")
            results[ident] = future.result()
            retries += results[ident]["attempts"] - 1
            self.progress.advance(f"{retries} retried" if retries else "")
        self.in_flight = []
        records = [reports.task_record(results[ident], round_) for ident, _ in
                   sorted(jobs, key=lambda job: job[0])]
        skipped = sum(1 for record in records if record["skipped"])
        self.progress.finish(", ".join(filter(None, [
            f"{skipped} skipped" if skipped else "", f"{retries} retried" if retries else ""])))
        self.records += records
        self.phase_records.setdefault(phase, []).extend(records)
        self.phase_wall[phase] = self.phase_wall.get(phase, 0.0) + time.monotonic() - start
        return records

    # --- the phases ----------------------------------------------------------------------

    def shard_phases(self):
        work, plan, skip = self.options.work, self.plan_file, not self.options.no_skip
        summaries = [commands.summary_path(work, shard) for shard in self.shards]
        self.run_phase("summary", [
            (shard, commands.summary_args(plan, shard, commands.summary_path(work, shard), skip))
            for shard in self.shards])
        previous_top, observations = None, []
        for round_ in range(MAX_COORDINATOR_ROUNDS + 1):
            top = commands.top_path(work, round_)
            args = commands.coordinate_args(plan, summaries, top, previous_top, observations)
            record = self.run_phase("coordinate", [(round_, args)], round_=round_)[0]
            pending = record.get("pending_stage")
            if not isinstance(pending, int) or isinstance(pending, bool) or pending < 0:
                raise DriverError(f"coordinate (round {round_}): ridge printed pending_stage "
                                  f"{pending!r}, not a non-negative integer")
            if pending == 0:
                self.final_top = top
                break
            observations = [commands.observation_path(work, shard, round_)
                            for shard in self.shards]
            self.run_phase("observe", [
                (shard, commands.observe_args(plan, shard, top,
                                              commands.observation_path(work, shard, round_),
                                              skip))
                for shard in self.shards], round_=round_)
            previous_top = top
        else:
            raise DriverError(f"coordinate: still pending after {MAX_COORDINATOR_ROUNDS} rounds")
        self.run_phase("encode", [
            (shard, commands.encode_args(plan, shard, self.final_top,
                                         commands.segment_path(work, shard), skip))
            for shard in self.shards])

    def phases(self):
        phases = {}
        for name in ("plan", "cluster", "summary", "coordinate", "observe", "encode", "merge"):
            if name in self.phase_records:
                phases[name] = reports.phase_totals(self.phase_records[name],
                                                    self.phase_wall[name])
                if name == "coordinate":
                    phases[name]["pending_stages"] = [r.get("pending_stage")
                                                      for r in self.phase_records[name]]
            elif name in self.local_phases:
                phases[name] = self.local_phases[name]
        return phases

    def run(self):
        start = time.monotonic()
        created_work = not os.path.isdir(self.options.work)
        os.makedirs(self.options.work, exist_ok=True)
        try:
            import_distributed(self.options.verbose)  # fail before the plan if it is missing
            self.plan()
            with ExitStack() as stack:
                self.open_cluster(stack)
                try:
                    self.shard_phases()
                except KeyboardInterrupt:
                    self.progress.abandon()
                    self.stop_tasks(self.in_flight)
                    raise
            self.merge()
        finally:
            shutil.rmtree(self.run_dir, ignore_errors=True)
            # The run's bookkeeping goes, and a work directory this run made and left empty.
            for directory in [os.path.dirname(self.run_dir)] + (
                    [self.options.work] if created_work else []):
                try:
                    os.rmdir(directory)
                except OSError:
                    pass
        return reports.build_report(
            phases=self.phases(), records=self.records, output=self.options.output,
            output_bytes=os.path.getsize(self.options.output), workers=self.workers,
            scheduler=self.scheduler, plan=self.plan_info, wall=time.monotonic() - start)


def _interrupt(signum, frame):
    raise KeyboardInterrupt


def main(argv=None):
    """The command line (python3 -m ridge_dask); returns the exit status."""
    options = cli.parse(argv)
    progress = Progress(options.quiet)
    # SIGTERM (a batch system's cancel) takes the way of Ctrl-C: the tasks are stopped, which
    # kills their ridge processes, instead of leaving them orphaned on the workers.
    signal.signal(signal.SIGTERM, _interrupt)
    try:
        report = Build(options, progress).run()
    except DriverError as error:
        progress.abandon()
        print(f"ridge_dask: {error}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        progress.abandon()
        print("ridge_dask: interrupted", file=sys.stderr)
        return 130
    if options.report:
        reports.write_json(options.report, report)
    if not options.quiet:
        print(reports.format_table(report))
    return 0
