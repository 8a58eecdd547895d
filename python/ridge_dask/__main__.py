"""`python3 -m ridge_dask ...`: see `python3 -m ridge_dask --help`."""

import sys

from ridge_dask.driver import main

if __name__ == "__main__":
    sys.exit(main())
