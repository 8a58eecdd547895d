"""ridge_dask: a sharded build of a .ridge archive on a Dask cluster.

`python3 -m ridge_dask INPUT... -o OUT.ridge --shard-level K [-- BUILD OPTIONS...]` runs
`ridge plan`, the per-shard `ridge build --shard` steps as Dask tasks (LocalCluster by
default, an existing cluster with --scheduler), the coordinator's rounds, and `ridge merge`.
See driver.py for the phases, commands.py for the ridge command lines, tasks.py for what runs
on a worker. Dependencies: the standard library and distributed (Debian: python3-distributed).
"""

__all__ = ["main"]


def main(argv=None):
    """The command line; returns the exit status (distributed is imported only when needed)."""
    from .driver import main as driver_main
    return driver_main(argv)
