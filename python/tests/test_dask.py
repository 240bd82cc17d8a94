"""startracker.solve_files over a Dask LocalCluster (two worker processes) on the eight real
tetra3 frames: the same dicts as solving them here, the database file opened once per worker,
a bad file's error in its place. Skipped where `distributed` is not installed (Debian:
python3-distributed). The scaling is measured by python/bench/bench_dask.py, not here."""
import logging
import os
import pathlib
import subprocess
import sys

import pytest

import startracker
from startracker import scale

REPO = pathlib.Path(__file__).resolve().parents[2]
FRAMES = sorted((REPO / "tests" / "data" / "tetra3").glob("*.tiff"))
EXE = os.environ.get("ST_STARTRACKER_EXE", str(REPO / "build" / "app" / "startracker"))
FOV = 11.4  # horizontal FOV of the tetra3 sample camera [deg]


# Debian 12's distributed 2022.12 on tornado 6.2: a deprecation inside the cluster's start.
pytestmark = pytest.mark.filterwarnings("ignore:make_current is deprecated:DeprecationWarning")


def without_timings(r):
    return {k: v for k, v in r.items() if k != "timing_ms"}


def test_import_does_not_need_dask():
    # In a fresh interpreter: this one may have imported Dask for the other tests.
    code = ("import sys, startracker; assert callable(startracker.solve_files); "
            "bad = sorted(m for m in sys.modules if m.split('.')[0] in ('dask', 'distributed')); "
            "assert not bad, bad")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr


@pytest.fixture(scope="module")
def client(tmp_path_factory):
    distributed = pytest.importorskip("distributed")
    # The nanny writes its pre-spawn environment (MALLOC_TRIM_THRESHOLD_, OMP_NUM_THREADS)
    # into this process's os.environ: put it back for the tests that run programs after.
    environ = dict(os.environ)
    # Worker processes are spawned: they get this process's environment and sys.path, so
    # they import the same startracker (asserted below). Their scratch space is pytest's.
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=None, silence_logs=logging.ERROR,
                                       local_directory=str(tmp_path_factory.mktemp("workers")))
    c = distributed.Client(cluster)
    try:
        yield c
    finally:
        c.close()
        cluster.close()
        os.environ.clear()
        os.environ.update(environ)


@pytest.fixture(scope="module")
def paths(tmp_path_factory):
    """The eight frames, a missing file and a file that is not an image, then the eight again."""
    broken = tmp_path_factory.mktemp("dask") / "broken.tiff"
    broken.write_bytes(b"not a tiff")
    frames = [str(p) for p in FRAMES]
    return frames + ["/no/such/frame.tiff", str(broken)] + frames


@pytest.fixture(scope="module")
def serial(paths):
    return startracker.solve_files(paths, fov_deg=FOV, no_cache=True)


def test_workers_import_this_startracker(client):
    where = client.run(lambda: __import__("startracker").__file__)
    assert len(where) == 2 and set(where.values()) == {startracker.__file__}


def test_serial_results_and_errors_in_place(paths, serial):
    assert len(FRAMES) == 8 and len(serial) == len(paths)
    for p, r in zip(paths, serial):
        assert r["image"] == p
    assert all(r["solved"] for r in serial[:8] + serial[10:]), serial
    missing, broken = serial[8], serial[9]
    assert missing == {
        "solved": False, "status": "error", "exit_code": 2, "image": paths[8],
        "error": paths[8] + ": cannot open the image (no such file, or not readable)"}
    assert broken["status"] == "error" and broken["exit_code"] == 2 and paths[9] in broken["error"]
    # One file: what solve_file returns, apart from the timings.
    assert without_timings(serial[3]) == without_timings(
        startracker.solve_file(paths[3], fov_deg=FOV, no_cache=True))
    # Two threads here (the GIL is released): the same.
    threaded = startracker.solve_files(paths, fov_deg=FOV, no_cache=True, threads=2)
    assert [without_timings(r) for r in threaded] == [without_timings(r) for r in serial]


@pytest.mark.parametrize("chunk_size", [None, 3], ids=["default-chunks", "chunks-of-3"])
def test_local_cluster_gives_the_serial_results(client, paths, serial, chunk_size):
    """Every dict equal to the serial one but for timing_ms, in the order of the paths (no_cache:
    each worker builds the database in memory once, and says so as the serial run does)."""
    got = startracker.solve_files(paths, client=client, chunk_size=chunk_size, fov_deg=FOV,
                                  no_cache=True)
    assert len(got) == len(serial)
    for p, g, s in zip(paths, got, serial):
        assert without_timings(g) == without_timings(s), p
    assert got[8]["status"] == "error" and got[8]["image"] == paths[8]


def test_database_file_is_opened_once_per_worker(client, tmp_path):
    if not os.path.exists(EXE):
        pytest.skip(EXE + " not built: no `catalog build` for the database file")
    db = str(tmp_path / "tetra3_11.4deg.stdb")
    subprocess.run([EXE, "catalog", "build", "--fov-deg", str(FOV), "--size", "1024", "768",
                    "--mag-limit", "6.6", "--epoch", "2019.574", "-q", "-o", db],
                   check=True, capture_output=True)
    frames = [str(p) for p in FRAMES] * 2
    here = startracker.solve_files(frames, database=db, fov_deg=FOV)
    assert all(r["solved"] and r["database"] == db for r in here), here
    for _ in range(2):  # 8 tasks of 2 frames per call, two calls: one open per worker
        got = startracker.solve_files(frames, client=client, database=db, chunk_size=2,
                                      fov_deg=FOV)
        assert [without_timings(r) for r in got] == [without_timings(r) for r in here]
        opens = client.run(scale.database_cache_info)
        assert len(opens) == 2
        assert all(o.get(db, 1) == 1 for o in opens.values()), opens
        assert any(db in o for o in opens.values()), opens
    # Opened once here too, for the serial run.
    assert scale.database_cache_info()[db] == 1
    # A Database object is not sent to workers: the path is.
    with pytest.raises(TypeError, match="file path"):
        startracker.solve_files(frames, client=client, database=startracker.Database(db))
    # A database that cannot be opened: every frame says so, nothing is lost to an exception.
    bad = startracker.solve_files(frames[:3], client=client, database=db + ".missing",
                                  fov_deg=FOV)
    assert [r["image"] for r in bad] == frames[:3]
    assert all(r["status"] == "error" and r["exit_code"] == 2 and ".missing" in r["error"]
               for r in bad), bad
