# CPack: one Debian package `startracker` (scripts/package.sh makes it). Its Depends come from
# dpkg-shlibdeps over the installed program, plugins and Python module: the MRPT component
# runtime packages they link (libmrpt-obs2.5, ...; never the libmrpt-dev metapackage),
# OpenCV's and cfitsio's runtime libraries; plus the interpreter and NumPy for the module.
# The static libraries, headers and CMake/pkg-config files are in it too: building against
# them needs the -dev packages of the same libraries (Suggests).
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME startracker)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "startracker maintainers <startracker@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Star tracker: plate solving, per-frame tracking and attitude fusion on MRPT")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3 (>= 3.11), python3-numpy")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS
    "mrpt-apps, libmrpt-obs-dev, libmrpt-hwdrivers-dev, libopencv-dev, libeigen3-dev, nlohmann-json3-dev, libcfitsio-dev")
set(CPACK_STRIP_FILES ON)
include(CPack)
