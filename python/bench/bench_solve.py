#!/usr/bin/env python3
"""Time per frame of startracker.solve (Python, NumPy image in memory) against the same C++
API called in-process (tests/install/consumer --bench), on the eight tetra3 frames.

    PYTHONPATH=PREFIX/lib/python3/dist-packages /usr/bin/python3 python/bench/bench_solve.py \\
        --consumer build/tests/consumer-build/consumer [--repeat 20] [--rounds 3]

Both sides solve the same pixels at the same epoch with fov_deg=11.4 after one warm-up solve
(the database is built once per camera and kept). The rounds alternate C++ and Python so that
a change of machine load hits both; per frame the table gives the minimum over all solves
(the least disturbed by other processes) and the mean. tetra3 is compared too when it can be
imported (it is not a Debian package).
"""
import argparse
import pathlib
import re
import subprocess
import sys
import time

import startracker

REPO = pathlib.Path(__file__).resolve().parents[2]


def cpp_round(consumer, frames, repeat):
    out = subprocess.run([consumer, "--bench", str(repeat)] + [str(f) for f in frames],
                         capture_output=True, text=True, check=True).stdout
    return {pathlib.Path(m[0]).name: (float(m[1]), float(m[2])) for m in
            re.findall(r"^bench (\S+) mean ([0-9.]+) min ([0-9.]+) ms/frame$", out, re.M)}


def python_round(images, repeat):
    res = {}
    for name, (img, epoch) in images.items():
        startracker.solve(img, fov_deg=11.4, epoch=epoch)  # warm: database built once
        times = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            startracker.solve(img, fov_deg=11.4, epoch=epoch)
            times.append((time.perf_counter() - t0) * 1e3)
        res[name] = (sum(times) / len(times), min(times))
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--consumer", required=True, help="tests/install/consumer built program")
    ap.add_argument("--repeat", type=int, default=20)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--frames", default=str(REPO / "tests" / "data" / "tetra3"))
    a = ap.parse_args()
    frames = sorted(pathlib.Path(a.frames).glob("*.tiff"))
    images = {}
    for f in frames:
        r = startracker.solve_file(str(f), fov_deg=11.4)
        assert r["solved"], r
        images[f.name] = (startracker.read_image(str(f)), r["epoch_jyear"])
    cpp, py = {}, {}
    for _ in range(a.rounds):
        for store, res in ((cpp, cpp_round(a.consumer, frames, a.repeat)),
                           (py, python_round(images, a.repeat))):
            for k, (mean, best) in res.items():
                m0, b0, n = store.get(k, (0.0, float("inf"), 0))
                store[k] = (m0 + mean, min(b0, best), n + 1)
    print(f"{'frame':44s} {'py min':>8s} {'C++ min':>8s} {'ratio':>6s} {'py mean':>8s} {'C++ mean':>8s}")
    sp = sc = 0.0
    for f in frames:
        pm, pb, pn = py[f.name]
        cm, cb, cn = cpp[f.name]
        sp += pb
        sc += cb
        print(f"{f.name:44s} {pb:8.2f} {cb:8.2f} {pb / cb:6.3f} {pm / pn:8.2f} {cm / cn:8.2f}")
    print(f"{'sum of minima':44s} {sp:8.2f} {sc:8.2f} {sp / sc:6.3f}")
    try:
        import tetra3  # noqa: F401
    except ImportError:
        print("tetra3: not importable here (not packaged for Debian 12, no network): "
              "no comparison", file=sys.stderr)


if __name__ == "__main__":
    main()
