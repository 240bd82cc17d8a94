"""The Python module on the eight real tetra3 frames (tests/data/tetra3), run by ctest against
the installed tree (tests/install/tests.cmake sets PYTHONPATH to it and ST_STARTRACKER_EXE to
the installed program)."""
import json
import os
import pathlib
import subprocess
import threading

import numpy as np
import pytest

import startracker

REPO = pathlib.Path(__file__).resolve().parents[2]
FRAMES = sorted((REPO / "tests" / "data" / "tetra3").glob("*.tiff"))
EXE = os.environ.get("ST_STARTRACKER_EXE", str(REPO / "build" / "app" / "startracker"))
FOV = 11.4  # horizontal FOV of the tetra3 sample camera [deg]


def cli_solve(path):
    out = subprocess.run([EXE, "solve", "--no-cache", "--fov-deg", str(FOV), "--json", str(path)],
                         capture_output=True, text=True, check=False)
    return json.loads(out.stdout)


def test_eight_frames_are_there():
    assert len(FRAMES) == 8


def without_timings(r):
    return {k: v for k, v in r.items() if k != "timing_ms"}


@pytest.mark.parametrize("path", FRAMES, ids=lambda p: p.stem)
def test_numpy_solve_equals_the_command_line(path):
    """One plate solver (solve/): the same pixels at the same epoch give the same object as
    `solve --json`, number for number, apart from the timings and what names the input."""
    cli = cli_solve(path)
    assert cli["solved"], cli
    img = startracker.read_image(str(path))
    assert img.dtype == np.uint16 and img.shape == (768, 1024)  # 16-bit TIFF
    r = startracker.solve(img, fov_deg=FOV, epoch=cli["epoch_jyear"], name=str(path),
                          no_cache=True)
    assert r["solved"], r
    expected = without_timings(cli)
    expected["epoch_source"] = "--epoch"  # given here, read from the file name there
    expected["database"] = expected["database"].replace("epoch from file name", "epoch from --epoch")
    assert without_timings(r) == expected
    # From the file: nothing differs but the timings.
    assert without_timings(startracker.solve_file(str(path), fov_deg=FOV, no_cache=True)) == \
        without_timings(cli)


def test_known_field_centre():
    # The tetra3 README gives this frame's field centre: RA 230.7, Dec +11.0 deg.
    path = next(p for p in FRAMES if "Alt40_Azi-135" in p.name)
    r = startracker.solve_file(str(path), fov_deg=FOV)
    assert r["solved"]
    assert r["ra_deg"] == pytest.approx(230.7, abs=0.1)
    assert r["dec_deg"] == pytest.approx(11.0, abs=0.1)
    assert r["epoch_source"] == "file name"


def test_eight_bit_and_row_strided_views_solve():
    img = startracker.read_image(str(FRAMES[0]))
    r16 = startracker.solve(img, fov_deg=FOV)
    r8 = startracker.solve((img >> 8).astype(np.uint8), fov_deg=FOV)
    assert r16["solved"] and r8["solved"], (r16, r8)
    # A window whose row stride is wider than its width is used in place (no copy): the same
    # pixels give the same solution.
    big = np.zeros((800, 1100), np.uint16)
    big[10:778, 20:1044] = img
    view = big[10:778, 20:1044]
    assert not view.flags["C_CONTIGUOUS"]
    rv = startracker.solve(view, fov_deg=FOV)
    assert rv["solved"] and rv["ra_deg"] == pytest.approx(r16["ra_deg"], abs=1e-9)


@pytest.mark.parametrize("bad, what", [
    (np.zeros((768, 1024), np.float32), "dtype"),
    (np.zeros((768, 1024, 3), np.uint8), "2-D"),
    (np.zeros((768, 2048), np.uint16)[:, ::2], "adjacent"),
    (np.zeros((8, 8), np.uint8), "at least 16"),
])
def test_bad_images_raise_value_error_naming_the_problem(bad, what):
    with pytest.raises(ValueError, match=what):
        startracker.solve(bad, fov_deg=FOV)


def test_bad_options_raise_value_error():
    img = startracker.read_image(str(FRAMES[0]))
    with pytest.raises(ValueError, match="parity"):
        startracker.solve(img, fov_deg=FOV, parity="sideways")
    with pytest.raises(ValueError, match="fov_deg"):
        startracker.solve(img, fov_deg=-3)
    with pytest.raises(ValueError, match="ra_deg, dec_deg and radius_deg"):
        startracker.solve(img, fov_deg=FOV, ra=10)
    with pytest.raises(ValueError, match="no/such.tiff"):
        startracker.read_image("/no/such.tiff")


def test_black_frame_is_a_result_not_an_exception():
    r = startracker.solve(np.zeros((768, 1024), np.uint8), fov_deg=FOV)
    assert r["solved"] is False and r["status"] and r["reason"]


def test_database_object_and_fov_search():
    img = startracker.read_image(str(FRAMES[1]))
    db = startracker.Database.for_camera(1024, 768, FOV, epoch=2019.574)
    assert db.num_stars > 500 and db.epoch == pytest.approx(2019.574)
    r = startracker.solve(img, fov_deg=FOV, database=db)
    assert r["solved"] and r["database"] == db.source


def test_tracker_lost_in_space_then_tracking_with_a_gyro_rate():
    img = startracker.read_image(str(FRAMES[2]))
    s = startracker.solve_file(str(FRAMES[2]), fov_deg=FOV)
    # The camera as solve fitted it, no calibration file: solve's 0.5 px sigma floor.
    t = startracker.Tracker(1024, 768, fov_deg=s["hfov_deg"], epoch=s["epoch_jyear"],
                            min_sigma_px=0.5, tracking_min_sigma_px=0.5)
    a = t.process(img, 0.0)
    # The next frame of a camera standing still: the same sky, the bias 1 ADU higher (the
    # same image again is refused as a frozen readout).
    nxt = np.minimum(img, np.iinfo(img.dtype).max - 1) + 1
    b = t.process(nxt, 0.1, rate=(0.0, 0.0, 0.0))
    frozen = t.process(nxt, 0.2, rate=(0.0, 0.0, 0.0))
    assert frozen["failure"] == "frozen-image" and not frozen["has_attitude"], frozen
    assert a["mode"] == "lost-in-space" and a["has_attitude"]
    assert b["mode"] == "tracking" and b["has_attitude"] and b["prediction"] == "gyro", b
    assert len(b["stars"]) >= 4
    assert b["ra_deg"] == pytest.approx(a["ra_deg"], abs=0.01)
    with pytest.raises(ValueError, match="1024x768"):
        t.process(np.zeros((100, 100), np.uint8), 0.2)


def test_threads_solve_concurrently_with_the_gil_released():
    imgs = [startracker.read_image(str(p)) for p in FRAMES[:4]]
    startracker.solve(imgs[0], fov_deg=FOV)  # database built once
    results = [None] * len(imgs)

    def work(i):
        results[i] = startracker.solve(imgs[i], fov_deg=FOV)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(len(imgs))]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    assert all(r["solved"] for r in results)


def test_binned_in_flight_frame_with_pixel_aspect_equals_the_command_line():
    """Issue 34: the same option in the library as on the command line (`--pixel-aspect 2`),
    on a real Swarm frame (rows binned 2x): the same answer, and a picture twice as tall as
    wide per pixel is what made it solvable (square pixels do not solve it)."""
    path = REPO / "tests" / "data" / "swarm" / "SWA_StrA_2014-10-21T10h30m10.000Z_151.png"
    out = subprocess.run([EXE, "solve", "--no-cache", "--pixel-aspect", "2", "--fov-range", "14",
                          "22", "--json", str(path)], capture_output=True, text=True, check=False)
    cli = json.loads(out.stdout)
    assert cli["solved"], cli
    r = startracker.solve_file(str(path), pixel_aspect=2, fov_range=(14, 22), no_cache=True)
    assert without_timings(r) == without_timings(cli)
    assert r["camera"]["fx"] / r["camera"]["fy"] == pytest.approx(1.93, abs=0.01)
    square = startracker.solve_file(str(path), fov_range=(14, 22), no_cache=True)
    assert not square["solved"]
