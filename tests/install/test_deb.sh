#!/bin/sh
# The Debian package as a user gets it: cpack makes the .deb from the build tree, dpkg -x
# unpacks it into an empty root (no installation on this machine), then
#  - every ELF file in it (program, MRPT plugins, Python module) has all its libraries (ldd);
#  - the package declares the MRPT component runtime packages, not the metapackage;
#  - the unpacked /usr/bin/startracker solves a real frame with the catalog of the unpacked
#    tree (found beside the program, no environment variable), and so does the unpacked
#    Python module;
#  - MRPT's rawlog-edit loads the unpacked plugin by its bare name.
# usage: test_deb.sh BUILD_DIR WORK_DIR FRAMES_DIR
set -eu
build=$1 work=$2 frames=$3
rm -rf "$work" && mkdir -p "$work/root"
(cd "$work" && cpack --config "$build/CPackConfig.cmake" -B "$work/out" >cpack.log 2>&1) ||
  { cat "$work/cpack.log"; exit 1; }
deb=$(ls "$work"/out/startracker_*.deb)
echo "package: $deb ($(du -k "$deb" | cut -f1) kB)"
dpkg-deb -f "$deb" Depends
dpkg-deb -f "$deb" Depends | grep -q 'libmrpt-obs2' || { echo "Depends lacks the MRPT obs runtime"; exit 1; }
if dpkg-deb -f "$deb" Depends | grep -Eq '(^|[ ,])libmrpt-dev([ ,(]|$)'; then
  echo "Depends names the libmrpt-dev metapackage"; exit 1
fi
dpkg -x "$deb" "$work/root"
missing=0
for f in $(find "$work/root" -type f \( -perm -u+x -o -name '*.so*' \)); do
  file_type=$(head -c 4 "$f" | od -An -c | tr -d ' ')
  [ "$file_type" = "177ELF" ] || continue
  if ldd "$f" | grep -q 'not found'; then
    echo "missing libraries of $f:"; ldd "$f" | grep 'not found'; missing=1
  fi
done
[ $missing -eq 0 ] || exit 1
frame="$frames/2019-07-29T204726_Alt40_Azi-135_Try1.tiff"
unset STARTRACKER_DATA_DIR || true
# --no-cache: the point is the catalog it finds, not a database cached by an earlier run.
out=$("$work/root/usr/bin/startracker" solve --no-cache --fov-deg 11.4 --json "$frame")
echo "$out" | head -c 300; echo
echo "$out" | grep -q '"solved":true' || { echo "the unpacked startracker did not solve"; exit 1; }
echo "$out" | grep -q "\"database\":\"built in memory from $work/root/usr/share/startracker/" ||
  { echo "the unpacked startracker did not use the unpacked catalog"; exit 1; }
PYTHONPATH="$work/root/usr/lib/python3/dist-packages" /usr/bin/python3 - "$frame" "$work/root" <<'PY'
import sys, startracker
assert startracker.__file__.startswith(sys.argv[2]), startracker.__file__
assert startracker.data_dir().startswith(sys.argv[2]), startracker.data_dir()
r = startracker.solve(startracker.read_image(sys.argv[1]), fov_deg=11.4)
assert r["solved"], r
print("python from the .deb: solved, RA %.3f Dec %.3f, %d stars" % (r["ra_deg"], r["dec_deg"], r["stars_matched"]))
PY
# MRPT's tools dlopen() what -p names: a bare name finds the plugin in the loader's path
# (/usr/lib when installed; the unpacked root's here). A failed load only prints an error.
rawlog="$frames/../../../rawlogs/hold.rawlog"
log=$(LD_LIBRARY_PATH="$work/root/usr/lib" rawlog-edit -p libstartracker_mrpt.so --info -i "$rawlog" 2>&1)
if echo "$log" | grep -q "Error loading"; then echo "$log" | head -5; exit 1; fi
echo "package_deb: ok"
