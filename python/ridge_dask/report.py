"""The build's report: task records from the workers' results, per-phase totals, the JSON
document of --report and the text table printed at the end."""

import json
import os

MIB = 1024.0 * 1024.0
# The phases whose samples count in the throughput (the per-shard pixel work).
THROUGHPUT_STEPS = ("summary", "encode")


def task_record(result, round_=None):
    """A flat record of one task from ridge_task's result (ridge's figures plus attempts)."""
    ridge = result.get("ridge", {})
    record = {
        "step": result["step"],
        "shard": None if result["step"] == "coordinate" else result["shard"],
        "seconds": float(ridge.get("seconds", 0.0) or 0.0),
        "output_bytes": int(ridge.get("output_bytes", 0) or 0),
        "peak_rss_bytes": int(ridge.get("peak_rss_bytes", 0) or 0),
        "samples": int(ridge.get("samples", 0) or 0),
        "skipped": bool(ridge.get("skipped", False)),
        "attempts": int(result.get("attempts", 1)),
        "host": result.get("host"),
        "wall_seconds": round(float(result.get("wall_seconds", 0.0)), 6),
    }
    if round_ is not None:
        record["round"] = round_
    if result["step"] == "coordinate":
        record["pending_stage"] = ridge.get("pending_stage")
    return record


def phase_totals(records, wall_seconds):
    """Totals of one phase's task records."""
    return {
        "wall_seconds": round(wall_seconds, 6),
        "tasks": len(records),
        "skipped": sum(1 for r in records if r["skipped"]),
        "task_seconds": round(sum(r["seconds"] for r in records), 6),
        "samples": sum(r["samples"] for r in records),
        "output_bytes": sum(r["output_bytes"] for r in records),
        "max_peak_rss_bytes": max((r["peak_rss_bytes"] for r in records), default=0),
        "retries": sum(r["attempts"] - 1 for r in records),
    }


def samples_per_second_per_core(records):
    """Total samples / total task seconds over the summary and encode tasks that ran (a skipped
    task did no work, so neither its samples nor its seconds count); None without any."""
    ran = [r for r in records if r["step"] in THROUGHPUT_STEPS and not r["skipped"]]
    seconds = sum(r["seconds"] for r in ran)
    if not ran or seconds <= 0:
        return None
    return sum(r["samples"] for r in ran) / seconds


def build_report(*, phases, records, output, output_bytes, workers, scheduler, plan, wall):
    rebuilt = {}
    for step in ("summary", "observe", "encode"):
        ids = sorted({r["shard"] for r in records if r["step"] == step and not r["skipped"]})
        if step != "observe" or any(r["step"] == step for r in records):
            rebuilt[step] = ids
    rate = samples_per_second_per_core(records)
    return {
        "output": output,
        "output_bytes": output_bytes,
        "workers": workers,
        "scheduler": scheduler,
        "plan": plan,
        "phases": phases,
        "tasks": records,
        "rebuilt": rebuilt,
        "retries": sum(r["attempts"] - 1 for r in records),
        "wall_seconds": round(wall, 6),
        "coordinator_seconds": phases.get("coordinate", {}).get("task_seconds", 0.0),
        "merge_seconds": phases.get("merge", {}).get("seconds", 0.0),
        "samples_per_second_per_core": rate,
    }


def write_json(path, report):
    """Writes the report atomically (a temporary file renamed over PATH)."""
    temporary = f"{path}.tmp.{os.getpid()}"
    with open(temporary, "w", encoding="utf-8") as stream:
        json.dump(report, stream, indent=2)
        stream.write("\n")
    os.replace(temporary, path)


def _shard_cell(record):
    if record["step"] == "coordinate":
        return f"r{record.get('round', 0)}"
    return str(record["shard"])


def format_table(report):
    """The per-task table and the totals, as text."""
    header = ("step", "shard", "seconds", "output bytes", "peak RSS MiB", "skipped", "attempts")
    rows = [(r["step"], _shard_cell(r), f"{r['seconds']:.3f}", str(r["output_bytes"]),
             f"{r['peak_rss_bytes'] / MIB:.1f}", "yes" if r["skipped"] else "no",
             str(r["attempts"])) for r in report["tasks"]]
    widths = [max(len(h), *(len(row[i]) for row in rows)) if rows else len(h)
              for i, h in enumerate(header)]

    def line(cells):
        first = cells[0].ljust(widths[0])
        return "  ".join([first] + [c.rjust(w) for c, w in zip(cells[1:], widths[1:])])

    lines = [line(header)] + [line(row) for row in rows] + [""]
    lines.append("phase        wall s  tasks  skipped  task s  retries")
    for name, phase in report["phases"].items():
        wall = f"{phase.get('wall_seconds', 0.0):6.2f}"
        if "tasks" in phase:
            lines.append(f"{name:<11} {wall}  {phase['tasks']:5d}  {phase['skipped']:7d}"
                         f"  {phase['task_seconds']:6.2f}  {phase['retries']:7d}")
        else:
            lines.append(f"{name:<11} {wall}")
    rate = report["samples_per_second_per_core"]
    rounds = report["phases"].get("coordinate", {}).get("tasks", 0)
    lines.append("")
    lines.append(f"wall {report['wall_seconds']:.2f} s on {report['workers']} worker(s); "
                 f"coordinator {report['coordinator_seconds']:.2f} s ({rounds} round(s)); "
                 f"merge {report['merge_seconds']:.2f} s; retries {report['retries']}")
    lines.append("summary+encode: " + ("no shard rebuilt" if rate is None else
                                       f"{rate:,.0f} samples/s per core"))
    lines.append(f"wrote {report['output']} ({report['output_bytes']} bytes)")
    return "\n".join(lines)
