#!/usr/bin/env python3
"""Time per frame of startracker.solve (Python, NumPy image in memory) against the same C++
API called in-process (tests/install/consumer --bench), on the eight tetra3 frames.

    PYTHONPATH=PREFIX/lib/python3/dist-packages /usr/bin/python3 python/bench_solve.py \
        --consumer build/tests/consumer-build/consumer [--repeat 20]

Both sides solve the same pixels at the same epoch with fov_deg=11.4 after one warm-up solve
(the database is built once per camera and kept); the figure is the mean wall time of
`repeat` solves. tetra3 is compared too when it can be imported (it is not a Debian package).
"""
import argparse
import pathlib
import re
import subprocess
import sys
import time

import startracker

REPO = pathlib.Path(__file__).resolve().parents[1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--consumer", required=True, help="tests/install/consumer built program")
    ap.add_argument("--repeat", type=int, default=20)
    ap.add_argument("--frames", default=str(REPO / "tests" / "data" / "tetra3"))
    a = ap.parse_args()
    frames = sorted(pathlib.Path(a.frames).glob("*.tiff"))
    out = subprocess.run([a.consumer, "--bench", str(a.repeat)] + [str(f) for f in frames],
                         capture_output=True, text=True, check=True).stdout
    cpp = {pathlib.Path(m[0]).name: float(m[1])
           for m in re.findall(r"^bench (\S+) ([0-9.]+) ms/frame$", out, re.M)}
    try:
        import tetra3  # noqa: F401
        have_tetra3 = True
    except ImportError:
        have_tetra3 = False
    print(f"{'frame':44s} {'python ms':>10s} {'C++ ms':>8s} {'ratio':>6s}")
    tot_py = tot_cpp = 0.0
    for f in frames:
        img = startracker.read_image(str(f))
        epoch = startracker.solve_file(str(f), fov_deg=11.4)["epoch_jyear"]
        r = startracker.solve(img, fov_deg=11.4, epoch=epoch)  # warm-up: database built
        assert r["solved"], r
        t0 = time.perf_counter()
        for _ in range(a.repeat):
            startracker.solve(img, fov_deg=11.4, epoch=epoch)
        py_ms = (time.perf_counter() - t0) * 1e3 / a.repeat
        c = cpp[f.name]
        tot_py += py_ms
        tot_cpp += c
        print(f"{f.name:44s} {py_ms:10.2f} {c:8.2f} {py_ms / c:6.3f}")
    print(f"{'mean':44s} {tot_py / len(frames):10.2f} {tot_cpp / len(frames):8.2f} "
          f"{tot_py / tot_cpp:6.3f}")
    if not have_tetra3:
        print("tetra3: not importable here (not packaged for Debian 12, no network): "
              "no comparison", file=sys.stderr)


if __name__ == "__main__":
    main()
