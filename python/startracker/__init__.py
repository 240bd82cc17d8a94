"""Star tracker: plate-solve a NumPy image and track frame by frame (C++ core).

    import startracker, numpy
    r = startracker.solve(image, fov_deg=11.4)   # dict: the keys of `startracker solve --json`
    if r["solved"]: print(r["ra_deg"], r["dec_deg"], r["roll_deg"], r["covariance"])

    t = startracker.Tracker(1024, 768, fov_deg=11.4)
    fix = t.process(frame, t=0.1, rate=(0.0, 0.0, 0.01))   # rate [rad/s], optional

Without `database=`, solve builds the database for the camera (or the FOV search) from the
default catalog and keeps it for the next call with the same camera; pass
`startracker.Database(path)` (a `startracker catalog build` file) or
`startracker.Database.for_camera(w, h, fov_deg)` to choose it.

    rs = startracker.solve_files(paths, fov_deg=11.4)                 # many files, in order
    rs = startracker.solve_files(paths, client=dask_client, fov_deg=11.4)  # over Dask workers

(startracker/scale.py: chunks per worker, the database loaded once per worker, a dask.bag
recipe; Dask is needed only when a client is passed.)
"""
import os as _os
import pathlib as _pathlib

# An installed tree keeps the catalog in <prefix>/share/startracker; the module lives in
# <prefix>/lib/python3/dist-packages/startracker. The C++ core looks beside the program
# (python3 here), so point it at the module's own tree when the user did not.
_parents = _pathlib.Path(__file__).resolve().parents
if "STARTRACKER_DATA_DIR" not in _os.environ and len(_parents) > 4:
    _share = _parents[4] / "share" / "startracker"
    if (_share / "hip_main_v6.6.dat.gz").exists():
        _os.environ["STARTRACKER_DATA_DIR"] = str(_share)

from ._startracker import (  # noqa: E402
    Database, Tracker, data_dir, read_image, solve, solve_file, version)
from .scale import solve_files  # noqa: E402  (many files: here, or over a Dask client)

__version__ = version()
__all__ = ["Database", "Tracker", "data_dir", "read_image", "solve", "solve_file", "solve_files",
           "version", "__version__"]
