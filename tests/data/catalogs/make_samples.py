#!/usr/bin/env python3
"""Makes the two catalog fixtures of tests/catalog from the committed Hipparcos subset.

hip_main_sample.dat: lines of catalog/data/hip_main_v6.6.dat.gz copied unchanged, plus two
real lines that the subset lacks (HIP 1, V 9.10; HIP 55203 without a position).
tyc2_sample.dat: the same bright stars written in the Tycho-2 main-catalogue format
(I/259 tyc2.dat, '|'-separated), plus three real tyc2.dat lines of faint stars (TYC 1-8-1,
1-13-1, 1-33-1 with no mean position). Run from the repository root:
    python3 tests/data/catalogs/make_samples.py
"""
import gzip
import math

# HIP -> real TYC identifier (these bright stars sit in Tycho-2's suppl_1.dat in the real
# distribution; here they are written in the main-catalogue layout).
TYC = {
    30438: "8534 02277 1", 69673: "1472 01436 2", 24436: "5331 01752 1",
    27989: "0129 01873 1", 97649: "1058 03399 1", 21421: "1266 01416 1",
    65474: "5547 01518 1", 80763: "6803 02158 1", 37826: "1920 02194 1",
    113368: "6977 01267 1", 102098: "3574 03347 1", 49669: "0833 01381 1",
    7588: "8478 01395 1", 60718: "8979 03464 1", 68702: "9005 03919 1",
    25336: "0113 01856 1", 26311: "4766 02450 1", 26727: "4771 01188 1",
    25428: "1859 01470 1", 62956: "3845 01190 1", 67301: "3467 01257 1",
    46390: "5460 01592 1", 61084: "8654 03422 1", 85927: "7388 01093 1",
    45238: "9200 02603 1", 41037: "8579 02692 1", 33579: "6535 03619 1",
    109268: "8438 01959 1",
}
HIP_EXTRA = [32349, 71683, 104214, 11767]  # no BT/VT in hip_main or no TYC id here

REAL_HIP = [
    "H|           1| |00 00 00.22|+01 05 20.4| 9.10| |H|000.00091185|+01.08901332| |   3.54|   -5.20|   -1.88|  1.32|  0.74|  1.39|  1.36|  0.81| 0.32|-0.07|-0.11|-0.24| 0.09|-0.01| 0.10|-0.01| 0.01| 0.34|  0| 0.74|     1| 9.643|0.020| 9.130|0.019| | 0.482|0.025|T|0.55|0.03|L| | 9.2043|0.0020|0.017| 87| | 9.17| 9.24|       | | | |          | |  | 1| | | |  |   |       |     |     |    |S| | |224700|B+00 5077 |          |          |0.66|F5          |S ",
    "H|       55203| |11 18 11.24|+31 31 50.8| 3.79| |G|            |            | |       |        |        |      |      |      |      |      |     |     |     |     |     |     |     |     |     |     |   |     | 55203|      |     |      |     | | 0.606|0.015|G|0.68|0.01|H| | 3.8731|0.0007|0.006| 88| | 3.87| 3.89|       |D| | |11182+3132|I| 1|  | | |S|  |   |       |     |     |    |S| |Y| 98230|B+32 2132 |          |          |0.68|G0V         |S ",
]
REAL_TYC = [
    "0001 00008 1| |  2.31750494|  2.23184345|  -16.3|   -9.0| 68| 73| 1.7| 1.8|1958.89|1951.94| 4|1.0|1.0|0.9|1.0|12.146|0.158|12.146|0.223|999| |         |  2.31754222|  2.23186444|1.67|1.54| 88.0|100.8| |-0.2",
    "0001 00013 1| |  1.12558209|  2.26739400|   27.7|   -0.5|  9| 12| 1.2| 1.2|1990.76|1989.25| 8|1.0|0.8|1.0|0.7|10.488|0.038| 8.670|0.015|999|T|         |  1.12551889|  2.26739556|1.81|1.52|  9.3| 12.7| |-0.2",
    "0001 00033 1|X|            |            |       |       |   |   |    |    |       |       |  |   |   |   |   |12.512|0.228|      |     |  5|T|         |  1.58432611|  0.94286667|1.69|1.58|115.5|125.1| | 0.0",
]
MAS = math.pi / 180 / 3600e3


def propagate(ra_deg, de_deg, pmra, pmde, dt):
    """Rectilinear motion on the sphere (as catalog/epoch_correction.hpp, no radial velocity)."""
    a, d = math.radians(ra_deg), math.radians(de_deg)
    u = [math.cos(d) * math.cos(a), math.cos(d) * math.sin(a), math.sin(d)]
    e_ra = [-math.sin(a), math.cos(a), 0.0]
    e_de = [-math.sin(d) * math.cos(a), -math.sin(d) * math.sin(a), math.cos(d)]
    v = [u[k] + dt * MAS * (pmra * e_ra[k] + pmde * e_de[k]) for k in range(3)]
    n = math.sqrt(sum(x * x for x in v))
    v = [x / n for x in v]
    return math.degrees(math.atan2(v[1], v[0])) % 360.0, math.degrees(math.asin(v[2]))


def main():
    lines = {}
    with gzip.open("catalog/data/hip_main_v6.6.dat.gz", "rt") as f:
        for line in f:
            lines[int(line.split("|")[1])] = line.rstrip("\r\n")
    hip_out, tyc_out = [], []
    for hip in list(TYC) + HIP_EXTRA:
        hip_out.append(lines[hip])
    hip_out += REAL_HIP
    for hip, tyc in TYC.items():
        f = [x.strip() for x in lines[hip].split("|")]
        ra, de = float(f[8]), float(f[9])
        pmra, pmde = float(f[12]), float(f[13])
        bt, e_bt, vt, e_vt = float(f[32]), float(f[33]), float(f[34]), float(f[35])
        mra, mde = propagate(ra, de, pmra, pmde, 2000.0 - 1991.25)
        e_ra, e_de, e_pmra, e_pmde = (float(f[k]) for k in (14, 15, 17, 18))
        tyc_out.append(
            f"{tyc}| |{mra:12.8f}|{mde:12.8f}|{pmra:7.1f}|{pmde:7.1f}|{round(e_ra):3d}|"
            f"{round(e_de):3d}|{e_pmra:4.1f}|{e_pmde:4.1f}|1991.25|1991.25| 2|0.0|0.0|0.0|0.0|"
            f"{bt:6.3f}|{e_bt:5.3f}|{vt:6.3f}|{e_vt:5.3f}|999|T|{hip:6d}   |{ra:12.8f}|"
            f"{de:12.8f}|1.25|1.25|{e_ra:5.1f}|{e_de:5.1f}| | 0.0")
    tyc_out += REAL_TYC
    with open("tests/data/catalogs/hip_main_sample.dat", "w") as f:
        f.write("\n".join(hip_out) + "\n")
    with open("tests/data/catalogs/tyc2_sample.dat", "w") as f:
        f.write("\r\n".join(tyc_out) + "\r\n")  # tyc2.dat records end in CR LF


if __name__ == "__main__":
    main()
