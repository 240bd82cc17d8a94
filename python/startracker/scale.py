"""Solve many image files: in this process, or mapped over a Dask cluster.

    import startracker
    results = startracker.solve_files(paths, fov_deg=11.4)            # here, in order
    results = startracker.solve_files(paths, fov_deg=11.4, threads=2) # here, two threads

    from distributed import Client
    client = Client("tcp://scheduler:8786")       # or Client(LocalCluster(...))
    results = startracker.solve_files(paths, client=client, fov_deg=11.4,
                                      database="/data/stars_11deg.stdb")

Each result is the dict `solve_file(path, **options)` returns (`startracker solve --json`'s
object), in the order of `paths`. A file that cannot be solved because of an error (missing,
unreadable, not an image) gets the command line's error object in its place, as a batch
`startracker solve --json` prints it: {"solved": False, "status": "error", "error": message,
"exit_code": 2 for bad input (ValueError) else 1, "image": path}; the other files still
solve. (Bad options are bad input too: every file then carries the same error.)

With a client the paths are cut into a few contiguous chunks per worker thread (4, at most
256 frames each; `chunk_size=` overrides) and `client.map` sends each chunk to a worker as one
task. A frame takes ~5 ms and a Dask task ~0.9 ms of scheduling and messaging on 2 cores: a
task per frame made 160 frames on 2 workers 30 % slower (0.58 s against 0.45 s), while 4
chunks per thread (8 tasks of 20 frames) cost no more than one chunk per worker (0.45 s
against 0.44 s) and leave Dask room to even out the workers (work stealing) and to lose
little work when a worker dies. The paths must be readable on the workers (a shared file
system; a relative path is resolved in the worker's working directory). The workers need
`startracker` importable (e.g. the same PYTHONPATH; a LocalCluster's workers inherit this
process's environment).

The database is loaded once per worker process:
 - without `database=`, the C++ module builds (or reads from the disk cache,
   ~/.cache/startracker) the database for the camera on a process's first frame and keeps it
   for every later frame with the same camera and epoch (to the 1e-3 yr);
 - `database="PATH"` (a `startracker catalog build` file): only the path is sent; each
   process opens `startracker.Database(PATH)` once and keeps it in a per-process cache
   (`database_cache_info()` tells how often each path was opened in this process). A
   `startracker.Database` object is accepted only without a client: it is not sent.
The solve releases the GIL, so a worker with several threads solves that many frames at once.

Worker processes: Dask's nanny starts each worker with MALLOC_TRIM_THRESHOLD_=65536, and a
glibc with any malloc threshold set no longer raises its mmap threshold by itself: every
buffer over 128 kB (a frame and detection's images) is mmap'ed and unmapped again, and a solve
takes ~15 % more CPU (0.78 ms more per frame than here, python/bench/bench_dask.py). Start the
workers with a 32 MB mmap threshold to get it back (Dask's trim threshold stays):

    import dask
    with dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_MMAP_THRESHOLD_":
                          33554432}):
        cluster = LocalCluster(n_workers=2, threads_per_worker=1)
    # or: export MALLOC_MMAP_THRESHOLD_=33554432 before `dask worker ...`

The same with dask.bag (one partition is one chunk; solve_chunk takes a partition's paths and
returns their dicts, errors included, with the same per-process database cache):

    import dask.bag as db
    bag = db.from_sequence(paths, npartitions=8)
    results = bag.map_partitions(startracker.scale.solve_chunk, fov_deg=11.4,
                                 database="/data/stars_11deg.stdb").compute()

(with a `distributed.Client` created first, `compute()` runs on its cluster; without one,
dask.bag's default scheduler is a pool of processes on this machine).

Dask is not imported here: a client is used through its `map` and `gather` methods only, so
`import startracker` needs no Dask.
"""
import functools
import math
import os
import threading

from . import _startracker

_MAX_CHUNK = 256           # frames per task at most (~1.3 s of work at ~5 ms per frame)
_CHUNKS_PER_THREAD = 4     # tasks per worker thread when the chunk size is not given

_db_lock = threading.Lock()
_databases = {}            # absolute path -> Database, for the life of this process
_database_opens = {}       # absolute path -> times opened in this process (1 once cached)


def database_cache_info():
    """{absolute path: times opened} of the `database=` files this process opened (once each)."""
    with _db_lock:
        return dict(_database_opens)


def _database(path):
    path = os.fspath(path)
    key = os.path.abspath(path)
    with _db_lock:
        db = _databases.get(key)
        if db is None:
            # Opened under the lock: threads of one worker wait for the first to finish it.
            # Opened as given: the results' "database" names it as solve_file would.
            db = _startracker.Database(path)
            _databases[key] = db
            _database_opens[key] = _database_opens.get(key, 0) + 1
        return db


def _error(path, exc):
    # The object a batch `startracker solve --json` prints for a frame an error ended
    # (solve/solve_output.hpp): exit code 2 for bad input (the module's ValueError), else 1.
    return {"solved": False, "status": "error", "error": str(exc),
            "exit_code": 2 if isinstance(exc, ValueError) else 1, "image": path}


def _solve_one(path, db, options):
    path = os.fspath(path)
    try:
        if db is not None:
            return _startracker.solve_file(path, database=db, **options)
        return _startracker.solve_file(path, **options)
    except TypeError:
        raise  # a wrong keyword or type: the caller's mistake, the same for every file
    except Exception as e:  # noqa: BLE001 - one frame's error must not lose the others
        return _error(path, e)


def _open_database(database):
    if database is None or isinstance(database, _startracker.Database):
        return database
    try:
        return _database(database)
    except TypeError:
        raise
    except Exception as e:  # noqa: BLE001 - reported on every frame, as the CLI would
        return e


def solve_chunk(paths, database=None, **options):
    """Solve `paths` one after another in this process: a list of result dicts in their order.

    `database` is None, a database file's path (opened once per process and kept) or a
    `startracker.Database`. This is the task solve_files sends to a Dask worker, and a
    dask.bag partition function (`bag.map_partitions(solve_chunk, fov_deg=...)`).
    """
    paths = [os.fspath(p) for p in paths]
    db = _open_database(database)
    if isinstance(db, Exception):
        return [_error(p, db) for p in paths]
    return [_solve_one(p, db, options) for p in paths]


def _chunks(paths, size):
    return [paths[i:i + size] for i in range(0, len(paths), size)]


def _cluster_threads(client):
    try:
        return max(1, sum(client.nthreads().values()))
    except Exception:  # noqa: BLE001 - no workers yet: chunk for one thread
        return 1


def solve_files(paths, client=None, database=None, threads=1, chunk_size=None, **options):
    """Solve image files; a list of `solve_file` dicts in the order of `paths`.

    client: None solves in this process (`threads` at once: the GIL is released while a frame
    is solved); a `distributed.Client` maps chunks of the paths over its workers.
    database: None (each process builds or reads the camera's database once and keeps it), a
    database file's path (opened once per process; with a client only the path is sent), or
    a `startracker.Database` (without a client only).
    chunk_size: frames per Dask task (default: 4 tasks per worker thread, at most 256 frames).
    options: solve_file's keywords (fov_deg=, camera=, fov_range=, epoch=, no_cache=, ...).
    An error on one file (missing, unreadable) gives its error dict in its place; the module
    docstring (`help(startracker.scale)`) has the details and a dask.bag recipe.
    """
    paths = [os.fspath(p) for p in paths]
    if database is not None and not isinstance(database, _startracker.Database):
        database = os.fspath(database)
    if client is None:
        db = _open_database(database)
        if isinstance(db, Exception):
            return [_error(p, db) for p in paths]
        threads = max(1, int(threads))
        if threads == 1 or len(paths) < 2:
            return [_solve_one(p, db, options) for p in paths]
        from concurrent.futures import ThreadPoolExecutor
        with ThreadPoolExecutor(max_workers=threads) as pool:
            return list(pool.map(lambda p: _solve_one(p, db, options), paths))
    if isinstance(database, _startracker.Database):
        raise TypeError("solve_files: with a client give database= as a file path (each worker "
                        "opens it once); a Database object is not sent to workers")
    if not paths:
        return []
    if chunk_size is None:
        tasks = _CHUNKS_PER_THREAD * _cluster_threads(client)
        chunk_size = min(_MAX_CHUNK, math.ceil(len(paths) / tasks))
    chunk_size = max(1, int(chunk_size))
    # The options are bound here, not given to client.map as keywords (none can be taken for
    # one of map's own); pure=False: two chunks holding the same paths (frames listed twice)
    # are two tasks, not one result shared by key.
    task = functools.partial(solve_chunk, database=database, **options)
    futures = client.map(task, _chunks(paths, chunk_size), pure=False)
    try:
        return [r for chunk in client.gather(futures) for r in chunk]
    finally:
        for f in futures:
            f.release()
