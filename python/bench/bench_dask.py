#!/usr/bin/env python3
"""Scaling of startracker.solve_files over a Dask LocalCluster: 1 and 2 worker processes
against the same solves in this process, on the eight tetra3 frames repeated 20 times.

    PYTHONPATH=PREFIX/lib/python3/dist-packages /usr/bin/python3 python/bench/bench_dask.py \\
        [--repeat 20] [--rounds 5] [--chunk-size N] [--dask-malloc-only]

The 160 solves (fov_deg=11.4, the default database: built or read from the disk cache once
per process and kept) are timed as one solve_files call from the caller's side: in-process
serial (client=None), LocalCluster(n_workers=1) and LocalCluster(n_workers=2), both with
threads_per_worker=1, processes=True. Cluster start-up is not timed, and neither is the
database: this process and every worker solve one frame before the rounds (client.run on each
worker), so each time is the steady state of a warm worker. The first, cold call on fresh
workers (the database read from the disk cache, first imports) is printed apart. The rounds
alternate the setups so that a change of machine load hits all of them; the table gives the
median over the rounds and the best. A task per frame (chunk_size=1) on two workers is timed
too: what the chunking saves.

Worker malloc: Dask's nanny starts each worker with MALLOC_TRIM_THRESHOLD_=65536
(distributed.nanny.pre-spawn-environ). Setting any glibc malloc threshold turns off glibc's
dynamic mmap threshold, so every buffer over 128 kB (a 1024x768 16-bit frame is 1.5 MB, and
detection makes several) is mmap'ed and unmapped, its pages faulted in again, on every frame:
~15 % more CPU per solve. The clusters are timed twice: with Dask's environment as it is, and
with MALLOC_MMAP_THRESHOLD_=33554432 added to it (buffers up to 32 MB from the heap; Dask's
trim threshold kept), the setting the README recommends.

Scaling = 1-worker time / 2-worker time; per-frame engine overhead = (1-worker time -
in-process time) / frames: what the cluster (task messages, pickling the dicts, the scheduler,
the worker's process environment) adds to each frame.
"""
import argparse
import contextlib
import datetime
import logging
import os
import pathlib
import platform
import statistics
import tempfile
import time
import warnings

import startracker
from startracker import scale

REPO = pathlib.Path(__file__).resolve().parents[2]
FOV = 11.4
MMAP_KEY = "MALLOC_MMAP_THRESHOLD_"
MMAP_VALUE = 32 * 1024 * 1024


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


@contextlib.contextmanager
def clusters(mmap_threshold):
    """A 1-worker and a 2-worker LocalCluster (1 thread each, processes)."""
    import dask
    from distributed import Client, LocalCluster
    # The nanny copies its pre-spawn environment into this process's os.environ: a setting
    # left from the other configuration must not reach these workers.
    os.environ.pop(MMAP_KEY, None)
    extra = {f"distributed.nanny.pre-spawn-environ.{MMAP_KEY}": mmap_threshold} \
        if mmap_threshold else {}
    with tempfile.TemporaryDirectory(prefix="bench_dask") as tmp, contextlib.ExitStack() as stack:
        with dask.config.set(extra):
            clients = {}
            for w in (1, 2):
                cluster = stack.enter_context(LocalCluster(
                    n_workers=w, threads_per_worker=1, processes=True, dashboard_address=None,
                    silence_logs=logging.ERROR, local_directory=tmp))
                clients[w] = stack.enter_context(Client(cluster))
                clients[w].wait_for_workers(w)
        try:
            yield clients
        finally:
            os.environ.pop(MMAP_KEY, None)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=20, help="times the eight frames are listed")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--chunk-size", type=int, default=None,
                    help="frames per task (default: solve_files' own, 4 tasks per worker)")
    ap.add_argument("--dask-malloc-only", action="store_true",
                    help="time the clusters with Dask's worker environment only")
    ap.add_argument("--frames", default=str(REPO / "tests" / "data" / "tetra3"))
    a = ap.parse_args()
    # Two schedulers at once: the second one's HTTP server (not a dashboard) takes another port.
    warnings.filterwarnings("ignore", message="Port .* is already in use")

    load0 = os.getloadavg()[0]
    frames = [str(f) for f in sorted(pathlib.Path(a.frames).glob("*.tiff"))]
    paths = frames * a.repeat
    n = len(paths)

    def check(results, count=n):
        assert len(results) == count and all(r["solved"] for r in results), \
            [r for r in results if not r["solved"]][:1]
        return results

    check(startracker.solve_files(frames, fov_deg=FOV), len(frames))  # database built/read here
    configs = [("Dask's worker env", None)]
    if not a.dask_malloc_only:
        configs.insert(0, (f"{MMAP_KEY}=32 MB", MMAP_VALUE))
    serial = "in-process, serial"
    times = {serial: []}
    cold = {}
    rows = {}
    for label, mmap in configs:
        with clusters(mmap) as clients:
            for w in (1, 2):
                cold[label, w], res = timed(lambda: startracker.solve_files(
                    paths, client=clients[w], chunk_size=a.chunk_size, fov_deg=FOV))
                check(res)
                clients[w].run(scale.solve_chunk, frames[:1], fov_deg=FOV)  # each worker warm
            setups = {
                serial: lambda: startracker.solve_files(paths, fov_deg=FOV),
                (label, 1): lambda: startracker.solve_files(
                    paths, client=clients[1], chunk_size=a.chunk_size, fov_deg=FOV),
                (label, 2): lambda: startracker.solve_files(
                    paths, client=clients[2], chunk_size=a.chunk_size, fov_deg=FOV),
                (label, "task per frame"): lambda: startracker.solve_files(
                    paths, client=clients[2], chunk_size=1, fov_deg=FOV),
            }
            rows[label] = list(setups)[1:]
            for k in rows[label]:
                times[k] = []
            for _ in range(a.rounds):
                for k, fn in setups.items():
                    t, res = timed(fn)
                    check(res)
                    times[k].append(t)

    med = {k: statistics.median(v) for k, v in times.items()}
    best = {k: min(v) for k, v in times.items()}

    def name(k):
        if k == serial:
            return k
        label, w = k
        what = {1: "1 worker", 2: "2 workers", "task per frame": "2 workers, a task per frame"}[w]
        return f"LocalCluster, {what} ({label})"

    print(f"{n} solves ({len(frames)} frames x {a.repeat}), {a.rounds} rounds, "
          f"{os.cpu_count()} cores, {platform.python_implementation()} "
          f"{platform.python_version()}, {datetime.date.today()}, chunk size "
          f"{a.chunk_size or 'default (4 tasks per worker)'}; load average before "
          f"{load0:.2f}, after {os.getloadavg()[0]:.2f} (another process's load skews the ratio)")
    print()
    print("| setup | wall [s], median | best | frames/s | ms/frame |")
    print("|---|---:|---:|---:|---:|")
    for k in [serial] + [k for label, _ in configs for k in rows[label]]:
        print(f"| {name(k)} | {med[k]:.3f} | {best[k]:.3f} | {n / med[k]:.0f} | "
              f"{1e3 * med[k] / n:.2f} |")
    print()
    for label, _ in configs:
        one, two, each = (label, 1), (label, 2), (label, "task per frame")
        print(f"{label}:")
        print(f"- scaling 1 -> 2 workers: {med[one] / med[two]:.2f}x (median), "
              f"{best[one] / best[two]:.2f}x (best)")
        print(f"- per-frame engine overhead, (1 worker - in-process) / {n}: "
              f"{1e3 * (med[one] - med[serial]) / n:.3f} ms (median), "
              f"{1e3 * (best[one] - best[serial]) / n:.3f} ms (best)")
        print(f"- a task per frame on 2 workers: "
              f"{1e3 * (med[each] - med[two]) / n:+.3f} ms per frame against the chunks")
        print(f"- first (cold) call on fresh workers, not in the table: 1 worker "
              f"{cold[label, 1]:.3f} s, 2 workers {cold[label, 2]:.3f} s")


if __name__ == "__main__":
    main()
