#!/usr/bin/env python3
"""Solve the same images with startracker and astrometry.net, on this machine, in one run.

Usage:
  scripts/compare_astrometry.py [--startracker PATH] [--fov-deg F] [--no-hint]
                                [--md OUT.md] [--check-arcsec A] [--work DIR] IMAGE|DIR...

For every image it runs `startracker solve` (astrometric frame, --no-aberration, as
astrometry.net's WCS) and astrometry.net's `solve-field` (Debian packages astrometry.net and
astrometry-data-tycho2-10-19, scripts/install-deps.sh) and compares:
  - the sky direction of startracker's principal point in both solutions (the boresight
    agreement, arcsec) and the largest disagreement over the image (corners included);
  - each solution's RMS residual on astrometry.net's own matched Tycho-2 stars (its .corr
    file), so neither is judged only on its own stars;
  - wall time per frame, both run as a user runs them on a folder: one process for all
    images, startracker with its database cache warm (the first call builds it).
With --fov-deg both get the same hint (horizontal FOV within +-10 %); --no-hint also times
both without any (startracker's FOV search, solve-field without a scale).
--check-arcsec A exits 1 unless both solve every image and the boresights agree within A.
Needs Debian's python3 with python3-astropy (a dependency of astrometry.net).
"""
import argparse
import json
import math
import os
import platform
import shutil
import subprocess
import sys
import time
import warnings

from machine_info import cpu_model

try:
    import numpy as np
    from astropy.io import fits
    from astropy.wcs import WCS
except ImportError as e:
    sys.exit(f"compare_astrometry: {e}; run it with Debian's python3 (python3-astropy)")

IMAGE_EXT = (".tif", ".tiff", ".png", ".jpg", ".jpeg", ".fits", ".fit")


def images_of(paths):
    out = []
    for p in paths:
        if os.path.isdir(p):
            out += sorted(os.path.join(p, f) for f in os.listdir(p)
                          if f.lower().endswith(IMAGE_EXT))
        elif os.path.isfile(p):
            out.append(p)
        else:
            sys.exit(f"compare_astrometry: no such image or folder: {p}")
    if not out:
        sys.exit("compare_astrometry: no images given")
    return out


def separation_arcsec(ra1, de1, ra2, de2):
    """Great-circle angle between directions given in degrees (haversine: exact near 0)."""
    ra1, de1, ra2, de2 = map(np.radians, (ra1, de1, ra2, de2))
    h = np.sin((de2 - de1) / 2) ** 2 + np.cos(de1) * np.cos(de2) * np.sin((ra2 - ra1) / 2) ** 2
    return np.degrees(2 * np.arcsin(np.sqrt(np.clip(h, 0, 1)))) * 3600


def read_wcs(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # astropy's notes on SIP/RADESYS keywords
        return WCS(fits.Header.fromfile(path))


def timed(cmd, **kw):
    t0 = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    return r, time.perf_counter() - t0


def run_startracker(st, images, fov, extra):
    cmd = [st, "solve", *images, "--json", "-q"] + extra
    if fov:
        cmd += ["--fov-deg", str(fov)]
    r, wall = timed(cmd)
    if r.returncode == 2:
        sys.exit(f"compare_astrometry: {' '.join(cmd)} failed:\n{r.stderr}")
    sols = [json.loads(line) for line in r.stdout.splitlines() if line.strip()]
    if len(sols) != len(images):
        sys.exit(f"compare_astrometry: startracker printed {len(sols)} results for "
                 f"{len(images)} images")
    return sols, wall


def run_solve_field(images, fov, outdir):
    os.makedirs(outdir, exist_ok=True)
    cmd = ["solve-field", "--overwrite", "--no-plots", "--no-remove-lines", "-N", "none",
           "--temp-axy", "--dir", outdir, "--cpulimit", "120"]
    if fov:
        cmd += ["--scale-units", "degwidth", "--scale-low", f"{0.9 * fov:g}",
                "--scale-high", f"{1.1 * fov:g}"]
    r, wall = timed(cmd + images)
    if r.returncode != 0:
        sys.exit(f"compare_astrometry: solve-field exited {r.returncode}:\n{r.stderr[-2000:]}")
    stems = [os.path.splitext(os.path.basename(i))[0] for i in images]
    solved = [os.path.exists(os.path.join(outdir, s + ".solved")) for s in stems]
    return stems, solved, wall


def rms_on_matches(wcs, corr):
    """RMS and max angle [arcsec] between the WCS's sky at astrometry.net's matched field
    stars (FITS pixels, 1-based) and the matched index stars."""
    ra, de = wcs.all_pix2world(corr["field_x"], corr["field_y"], 1)
    e = separation_arcsec(ra, de, corr["index_ra"], corr["index_dec"])
    return math.sqrt(float(np.mean(e ** 2))), float(e.max())


def package_version(pkg):
    r = subprocess.run(["dpkg-query", "-W", "-f=${Version}", pkg], capture_output=True, text=True)
    return r.stdout.strip() or "?"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("inputs", nargs="+")
    ap.add_argument("--startracker", default="build/app/startracker")
    ap.add_argument("--fov-deg", type=float, default=None)
    ap.add_argument("--no-hint", action="store_true", help="also time both without a FOV hint")
    ap.add_argument("--md", help="write the comparison as a Markdown page")
    ap.add_argument("--check-arcsec", type=float, default=None)
    ap.add_argument("--work", default="out/compare_astrometry")
    a = ap.parse_args()
    if shutil.which("solve-field") is None:
        sys.exit("compare_astrometry: solve-field not found (Debian package astrometry.net; "
                 "scripts/install-deps.sh installs it with its Tycho-2 index files)")
    st = os.path.abspath(a.startracker)
    if not os.access(st, os.X_OK):
        sys.exit(f"compare_astrometry: startracker not found at {a.startracker} (--startracker)")
    images = [os.path.abspath(i) for i in images_of(a.inputs)]
    os.makedirs(a.work, exist_ok=True)
    n = len(images)

    # The database cache is warmed first so that neither timing includes a one-off build.
    run_startracker(st, images[:1], a.fov_deg, ["--no-aberration"])
    ours, our_wall = run_startracker(st, images, a.fov_deg, ["--no-aberration"])
    apparent, _ = run_startracker(st, images, a.fov_deg, [])
    print(f"startracker: {sum(s['solved'] for s in ours)}/{n} solved, "
          f"{1000 * our_wall / n:.1f} ms per frame", file=sys.stderr)
    stems, anet_solved, anet_wall = run_solve_field(images, a.fov_deg, os.path.join(a.work, "anet"))
    print(f"astrometry.net: {sum(anet_solved)}/{n} solved, {anet_wall / n:.2f} s per frame",
          file=sys.stderr)
    nohint = None
    if a.no_hint:
        o2, w2 = run_startracker(st, images, None, ["--no-aberration"])
        _, s2, aw2 = run_solve_field(images, None, os.path.join(a.work, "anet_nohint"))
        nohint = (sum(s["solved"] for s in o2), w2, sum(s2), aw2)

    rows, worst, failures = [], 0.0, []
    for img, stem, sol, app, ok in zip(images, stems, ours, apparent, anet_solved):
        if not sol["solved"] or not ok:
            failures.append(f"{stem}: startracker {'solved' if sol['solved'] else 'failed'}, "
                            f"astrometry.net {'solved' if ok else 'failed'}")
            rows.append((stem, None))
            continue
        anet = read_wcs(os.path.join(a.work, "anet", stem + ".wcs"))
        cam = sol["camera"]
        # startracker's (ra, dec) is its principal point's direction (0-based pixel cx, cy)
        ra, de = anet.all_pix2world([cam["cx"]], [cam["cy"]], 0)
        centre = float(separation_arcsec(ra[0], de[0], sol["ra_deg"], sol["dec_deg"]))
        worst = max(worst, centre)
        ours_wcs = os.path.join(a.work, stem + ".startracker.wcs")
        cmd = [st, "solve", img, "--no-aberration", "--wcs", ours_wcs, "-q", "-f"]  # -f: the last run's WCS is replaced
        if a.fov_deg:
            cmd += ["--fov-deg", str(a.fov_deg)]
        subprocess.run(cmd, check=True, capture_output=True)
        mine = read_wcs(ours_wcs)
        header = fits.Header.fromfile(ours_wcs)
        w, h = header["IMAGEW"], header["IMAGEH"]
        gx, gy = np.meshgrid(np.linspace(0, w - 1, 9), np.linspace(0, h - 1, 7))
        r1, d1 = anet.all_pix2world(gx.ravel(), gy.ravel(), 0)
        r2, d2 = mine.all_pix2world(gx.ravel(), gy.ravel(), 0)
        field = float(separation_arcsec(r1, d1, r2, d2).max())
        corr = fits.open(os.path.join(a.work, "anet", stem + ".corr"))[1].data
        rms_anet, _ = rms_on_matches(anet, corr)
        rms_ours, _ = rms_on_matches(mine, corr)
        frame_shift = float(separation_arcsec(app["ra_deg"], app["dec_deg"],
                                              sol["ra_deg"], sol["dec_deg"]))
        rows.append((stem, dict(ra=sol["ra_deg"], dec=sol["dec_deg"], centre=centre, field=field,
                                ours_n=sol["stars_matched"], anet_n=len(corr),
                                rms_anet=rms_anet, rms_ours=rms_ours, shift=frame_shift,
                                sigma=sol["sigma_cross_boresight_arcsec"])))
        if a.check_arcsec is not None and centre > a.check_arcsec:
            failures.append(f"{stem}: boresights differ by {centre:.1f}\" "
                            f"(limit {a.check_arcsec:g}\")")

    lines = []
    hint = f"--fov-deg {a.fov_deg:g} / --scale-units degwidth {0.9 * a.fov_deg:g}..{1.1 * a.fov_deg:g}" \
        if a.fov_deg else "none"
    lines.append(f"Machine: {cpu_model()}, {os.cpu_count()} cores, {platform.system()} "
                 f"{platform.release()}; astrometry.net {package_version('astrometry.net')} with "
                 f"astrometry-data-tycho2-10-19 {package_version('astrometry-data-tycho2-10-19')}; "
                 f"{time.strftime('%Y-%m-%d')}. FOV hint: {hint}.")
    lines.append("")
    lines.append("| frame | startracker RA, Dec [deg] | boresight difference | largest difference "
                 "over the image | stars matched (startracker HIP / astrometry.net Tycho-2) | "
                 "RMS on astrometry.net's matches: its WCS / startracker's | startracker 1-sigma "
                 "| apparent - astrometric |")
    lines.append("|---|---|---|---|---|---|---|---|")
    for stem, r in rows:
        if r is None:
            lines.append(f"| {stem} | not solved by both | | | | | | |")
            continue
        lines.append(f"| {stem} | {r['ra']:.4f}, {r['dec']:+.4f} | {r['centre']:.1f}\" | "
                     f"{r['field']:.1f}\" | {r['ours_n']} / {r['anet_n']} | "
                     f"{r['rms_anet']:.1f}\" / {r['rms_ours']:.1f}\" | {r['sigma']:.1f}\" | "
                     f"{r['shift']:.1f}\" |")
    lines.append("")
    lines.append("| | startracker | astrometry.net |")
    lines.append("|---|---|---|")
    lines.append(f"| solved (hint) | {sum(s['solved'] for s in ours)}/{n} | {sum(anet_solved)}/{n} |")
    lines.append(f"| wall time per frame (hint), one process for all frames | "
                 f"{1000 * our_wall / n:.0f} ms | {1000 * anet_wall / n:.0f} ms |")
    if nohint:
        lines.append(f"| solved (no hint) | {nohint[0]}/{n} | {nohint[2]}/{n} |")
        lines.append(f"| wall time per frame (no hint) | {1000 * nohint[1] / n:.0f} ms | "
                     f"{1000 * nohint[3] / n:.0f} ms |")
    text = "\n".join(lines) + "\n"
    print(text)
    if a.md:
        with open(a.md, "w") as f:
            f.write("# startracker and astrometry.net on the same frames\n\n"
                    "Generated by `scripts/compare_astrometry.py "
                    + " ".join(sys.argv[1:]) + "`.\n\n" + text)
    if failures:
        print("compare_astrometry: FAILED\n  " + "\n  ".join(failures), file=sys.stderr)
        return 1
    if a.check_arcsec is not None:
        print(f"compare_astrometry: all {n} solved by both, boresights within {worst:.1f}\" "
              f"(limit {a.check_arcsec:g}\")", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
