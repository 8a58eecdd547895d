"""What runs on a Dask worker: one `ridge` subprocess per call.

Standard library only, and nothing imported from the rest of ridge_dask: the driver registers
this module with cloudpickle as pickled *by value*, so the workers of an existing cluster
(`--scheduler`) need neither this package installed nor it on their sys.path — only the
ridge binary and the work directory at the same paths (a shared file system).

Per-run bookkeeping lives in a run directory (WORK/.ridge_dask/RUN_ID/) that the driver
creates and removes:
  attempts/STEP-SHARD.K  one file per attempt of a task, claimed with O_EXCL, so the driver
                         learns how often Dask ran it (retries, lost workers) on any worker;
  fail-once-STEP-SHARD   the marker of the RIDGE_DASK_FAIL_ONCE test hook (see fail_once);
  stop                   written by the driver when the build is abandoned: a running task
                         kills its ridge and raises, a starting one raises at once.
"""

import json
import os
import socket
import subprocess
import time

# Characters of ridge's stderr kept in results and error messages.
STDERR_TAIL_CHARS = 4000
# Seconds between checks of the stop file while ridge runs.
POLL_SECONDS = 0.5


class RidgeStepError(RuntimeError):
    """A ridge step that failed: the message names the step, the shard and ridge's stderr."""


def step_label(step, shard):
    """'summary of shard 3'; for the coordinator, whose `shard` is its round: 'coordinate
    (round 1)'; for a local step without one (plan, merge): the step's name."""
    if shard is None:
        return step
    if step == "coordinate":
        return f"coordinate (round {shard})"
    return f"{step} of shard {shard}"


def tail(text, limit=STDERR_TAIL_CHARS):
    text = (text or "").rstrip()
    return text if len(text) <= limit else "..." + text[-limit:]


def _object(text):
    try:
        value = json.loads(text)
    except ValueError:
        return None
    return value if isinstance(value, dict) else None


def last_json_object(stdout):
    """The JSON object on the last non-empty line of stdout (the contract), or else an
    indented object that ends stdout (from the last line opening with "{" to the end: what
    nlohmann's dump(2) prints); None without either."""
    lines = (stdout or "").rstrip().splitlines()
    if not lines:
        return None
    value = _object(lines[-1].strip())
    if value is not None:
        return value
    for index in range(len(lines) - 1, -1, -1):
        if lines[index].startswith("{"):
            return _object("\n".join(lines[index:]))
    return None


def attempt_path(run_dir, step, shard, attempt):
    return os.path.join(run_dir, "attempts", f"{step}-{shard}.{attempt}")


def claim_attempt(run_dir, step, shard):
    """Claims and returns this attempt's number (1 for the first run of the task)."""
    os.makedirs(os.path.join(run_dir, "attempts"), exist_ok=True)
    attempt = 1
    while True:
        try:
            fd = os.open(attempt_path(run_dir, step, shard, attempt),
                         os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
        except FileExistsError:
            attempt += 1
            continue
        os.write(fd, f"{socket.gethostname()} {os.getpid()}\n".encode())
        os.close(fd)
        return attempt


def count_attempts(run_dir, step, shard):
    """How many attempts of a task were started (the driver's count after a failure)."""
    attempt = 0
    while os.path.exists(attempt_path(run_dir, step, shard, attempt + 1)):
        attempt += 1
    return attempt


def fail_once(run_dir, step, shard, fail_specs):
    """TEST HOOK (RIDGE_DASK_FAIL_ONCE="STEP:SHARD[,STEP:SHARD...]", read by the driver and
    passed here as fail_specs): the first attempt of a matching task raises before ridge runs.
    The marker file is created atomically in the run directory, so whichever worker runs the
    next attempt finds it and goes on. For the coordinator, SHARD is the round (0, 1, ...)."""
    if f"{step}:{shard}" not in (fail_specs or ()):
        return
    marker = os.path.join(run_dir, f"fail-once-{step}-{shard}")
    try:
        os.close(os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644))
    except FileExistsError:
        return
    raise RidgeStepError(f"{step_label(step, shard)}: injected failure "
                         f"(RIDGE_DASK_FAIL_ONCE={step}:{shard}, first attempt)")


def run_ridge(ridge, args, step, shard=None, cwd=None, stop_path=None, threads=None):
    """Runs `ridge ARGS...` and returns its last-line JSON object and its stderr's tail.

    Raises RidgeStepError naming the step, the shard and ridge's stderr when ridge exits
    non-zero, prints no JSON object, or is stopped through stop_path."""
    command = [ridge] + [str(a) for a in args]
    env = dict(os.environ)
    if threads is not None:  # ridge's OpenMP threads: one core a task by default
        env["OMP_NUM_THREADS"] = str(threads)
    if cwd is not None and not os.path.isdir(cwd):
        cwd = None
    try:
        process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                   stdin=subprocess.DEVNULL, cwd=cwd, env=env, text=True,
                                   errors="replace")
    except OSError as error:
        raise RidgeStepError(f"{step_label(step, shard)}: cannot run {ridge}: {error}") from None
    while True:
        try:
            stdout, stderr = process.communicate(timeout=POLL_SECONDS)
            break
        except subprocess.TimeoutExpired:
            if stop_path and os.path.exists(stop_path):
                process.kill()
                process.communicate()
                raise RidgeStepError(f"{step_label(step, shard)}: stopped (the build was "
                                     "abandoned)") from None
    label = step_label(step, shard)
    if process.returncode != 0:
        raise RidgeStepError(f"{label}: ridge exited with status {process.returncode}\n"
                             f"  command: {' '.join(command)}\n{tail(stderr)}")
    result = last_json_object(stdout)
    if result is None:
        raise RidgeStepError(f"{label}: ridge printed no JSON object on its last line of "
                             f"stdout\n  command: {' '.join(command)}\n"
                             f"  stdout: {tail(stdout, 500)}\n{tail(stderr)}")
    return result, tail(stderr)


def ridge_task(ridge, args, step, shard, run_dir, cwd=None, fail_specs=None, threads=None):
    """One task on a worker: claims an attempt, honours the stop file and the test hook, runs
    ridge, and returns {"step", "shard", "attempts", "host", "wall_seconds", "stderr_tail",
    "ridge": ridge's JSON object}. Any failure raises, so Dask retries the task."""
    attempt = claim_attempt(run_dir, step, shard)
    stop_path = os.path.join(run_dir, "stop")
    if os.path.exists(stop_path):
        raise RidgeStepError(f"{step_label(step, shard)}: stopped (the build was abandoned)")
    fail_once(run_dir, step, shard, fail_specs)
    start = time.monotonic()
    result, stderr_tail = run_ridge(ridge, args, step, shard, cwd=cwd, stop_path=stop_path,
                                    threads=threads)
    return {
        "step": step,
        "shard": shard,
        "attempts": attempt,
        "host": socket.gethostname(),
        "wall_seconds": time.monotonic() - start,
        "stderr_tail": stderr_tail,
        "ridge": result,
    }
