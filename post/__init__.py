"""Post-processing of MBSPH output folders (file formats: doc/output.md).

Library modules:

- :mod:`post.io`: readers of snapshots, CSV files and the effective namelist;
- :mod:`post.interp`: SPH interpolation of particle fields, free surface height.

Tools, each runnable as ``python -m post.<tool> --help``:

- :mod:`post.plot_field`: particles coloured by pressure, velocity or density;
- :mod:`post.plot_series`: time series of ``energy.csv`` columns;
- :mod:`post.dambreak`: surge front against Martin and Moyce (1952);
- :mod:`post.hydrostatic`: pressure profile of a still tank;
- :mod:`post.waves`: wave heights, periods, spectra and reflection from ``gauges.csv``;
- :mod:`post.armour`: displaced armour units, Nod and Ns from ``armour.csv`` and ``bodies.csv``.

Each tool is also ``mbsph-post <tool>`` once the package is installed (``pip install -e .``
in the repository root; ``make deps`` does it in ``.venv/``).

Requirements: numpy, scipy, h5py, matplotlib, f90nml (pyproject.toml). Figures
are drawn with matplotlib's Agg backend and written as PNG files.
"""

from .interp import free_surface_height, interpolate, kernel_sum, wendland_c2
from .io import (
    Snapshot,
    closest_snapshots,
    fluid_box,
    list_snapshots,
    read_case,
    read_csv,
    read_snapshot,
    snapshot_time,
)

__all__ = [
    "Snapshot",
    "list_snapshots",
    "read_snapshot",
    "snapshot_time",
    "closest_snapshots",
    "read_csv",
    "read_case",
    "fluid_box",
    "wendland_c2",
    "kernel_sum",
    "interpolate",
    "free_surface_height",
]
