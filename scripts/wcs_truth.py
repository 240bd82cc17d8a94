#!/usr/bin/env python3
"""The truth of a frame from its astrometry.net WCS (TAN-SIP): the sky direction of a pixel and
the pixel of a catalog star, with no dependency beyond Python (used by the in-flight frame
study, scripts/inflight.py, and to see which detections are stars).

Usage: scripts/wcs_truth.py FRAME.wcs [--ydouble] [--mag 6.5] [--catalog hip_main.dat.gz]
  prints the Hipparcos stars brighter than --mag inside the image as x y V HIP.
--ydouble: the WCS was solved on the frame with every row doubled (the Swarm frames'), so
  y_here = (y_wcs + 0.5) / 2 - 0.5.
"""
import argparse
import gzip
import math
import os
import re


def read_wcs(path):
    text = open(path, "rb").read().decode("ascii", "replace")
    cards = [text[i:i + 80] for i in range(0, len(text), 80)]
    h = {}
    for c in cards:
        m = re.match(r"^([A-Z0-9_\-]{1,8})\s*=\s*('[^']*'|[^/]*)", c)
        if m:
            v = m.group(2).strip()
            h[m.group(1).strip()] = v.strip("'").strip() if v.startswith("'") else float(v) if re.match(r"^[-+0-9.eE]+$", v) else v
        if c.startswith("END"):
            break
    return h


def sip(h, prefix, u, v):
    order = int(h.get(prefix + "_ORDER", 0))
    s = 0.0
    for p in range(order + 1):
        for q in range(order + 1 - p):
            s += h.get("%s_%d_%d" % (prefix, p, q), 0.0) * u ** p * v ** q
    return s


class TanSip:
    def __init__(self, path, ydouble=False):
        self.h = read_wcs(path)
        self.ydouble = ydouble
        h = self.h
        self.cd = [[h["CD1_1"], h["CD1_2"]], [h["CD2_1"], h["CD2_2"]]]
        det = self.cd[0][0] * self.cd[1][1] - self.cd[0][1] * self.cd[1][0]
        self.cdi = [[self.cd[1][1] / det, -self.cd[0][1] / det], [-self.cd[1][0] / det, self.cd[0][0] / det]]
        self.ra0, self.de0 = math.radians(h["CRVAL1"]), math.radians(h["CRVAL2"])

    def pixel_to_sky(self, x, y):
        """0-based pixel of this image -> (ra, dec) [deg]."""
        if self.ydouble:
            y = 2 * (y + 0.5) - 0.5
        u, v = x + 1 - self.h["CRPIX1"], y + 1 - self.h["CRPIX2"]
        U, V = u + sip(self.h, "A", u, v), v + sip(self.h, "B", u, v)
        xi = math.radians(self.cd[0][0] * U + self.cd[0][1] * V)
        eta = math.radians(self.cd[1][0] * U + self.cd[1][1] * V)
        # TAN deprojection about (ra0, de0)
        d = math.cos(self.de0) - eta * math.sin(self.de0)
        ra = self.ra0 + math.atan2(xi, d)
        de = math.atan2(math.sin(self.de0) + eta * math.cos(self.de0), math.hypot(xi, d))
        return math.degrees(ra) % 360, math.degrees(de)

    def sky_to_pixel(self, ra, de):
        ra, de = math.radians(ra), math.radians(de)
        c = math.sin(de) * math.sin(self.de0) + math.cos(de) * math.cos(self.de0) * math.cos(ra - self.ra0)
        if c <= 0:
            return None
        xi = math.cos(de) * math.sin(ra - self.ra0) / c
        eta = (math.sin(de) * math.cos(self.de0) - math.cos(de) * math.sin(self.de0) * math.cos(ra - self.ra0)) / c
        xi, eta = math.degrees(xi), math.degrees(eta)
        U = self.cdi[0][0] * xi + self.cdi[0][1] * eta
        V = self.cdi[1][0] * xi + self.cdi[1][1] * eta
        u, v = U + sip(self.h, "AP", U, V), V + sip(self.h, "BP", U, V)
        x, y = u + self.h["CRPIX1"] - 1, v + self.h["CRPIX2"] - 1
        if self.ydouble:
            y = (y + 0.5) / 2 - 0.5
        return x, y


def hipparcos(path, mag):
    with gzip.open(path, "rt", errors="replace") as f:
        for line in f:
            p = line.split("|")
            try:
                v, ra, de = float(p[5]), float(p[8]), float(p[9])
            except (ValueError, IndexError):
                continue
            if v <= mag:
                yield int(p[1]), ra, de, v


def separation_arcsec(ra1, de1, ra2, de2):
    ra1, de1, ra2, de2 = map(math.radians, (ra1, de1, ra2, de2))
    h = math.sin((de2 - de1) / 2) ** 2 + math.cos(de1) * math.cos(de2) * math.sin((ra2 - ra1) / 2) ** 2
    return math.degrees(2 * math.asin(math.sqrt(min(1, max(0, h))))) * 3600


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("wcs")
    ap.add_argument("--ydouble", action="store_true")
    ap.add_argument("--mag", type=float, default=6.5)
    ap.add_argument("--width", type=int, default=752)
    ap.add_argument("--height", type=int, default=290)
    ap.add_argument("--catalog", default=os.path.join(here, "..", "catalog", "data", "hip_main_v6.6.dat.gz"))
    a = ap.parse_args()
    w = TanSip(a.wcs, a.ydouble)
    ra, de = w.pixel_to_sky((a.width - 1) / 2, (a.height - 1) / 2)
    print("# centre RA %.5f Dec %+.5f" % (ra, de))
    for hip, ra, de, v in sorted(hipparcos(a.catalog, a.mag), key=lambda s: s[3]):
        p = w.sky_to_pixel(ra, de)
        if p and -0.5 <= p[0] <= a.width - 0.5 and -0.5 <= p[1] <= a.height - 0.5:
            print("%8.2f %8.2f %5.2f HIP %d" % (p[0], p[1], v, hip))


if __name__ == "__main__":
    main()
