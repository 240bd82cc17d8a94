# Install rules, the CMake package (find_package(startracker)) and the pkg-config file.
# Layout under the prefix:
#   bin/startracker                          the program
#   <libdir>/libstartracker_mrpt.so, _sim.so  MRPT plugins: MRPT's tools dlopen() what -p
#                                             names, so a bare `-p libstartracker_mrpt.so`
#                                             finds them in the loader's path (/usr/lib/...)
#   <libdir>/libst_*.a                       the static libraries of the public API
#   include/startracker/*.hpp                the public API: the facade and its seam types
#                                             (no MRPT, CLI11 or stage header)
#   share/startracker/                       the catalog (StarDatabase::defaultCatalogPath
#                                             finds it from <program>/../share/startracker)
#   <libdir>/cmake/startracker/, <libdir>/pkgconfig/startracker.pc
include(CMakePackageConfigHelpers)

set(ST_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/startracker)
set(ST_DATA_INSTALL_DIR ${CMAKE_INSTALL_DATADIR}/startracker)
# Link order of the static libraries (each before what it uses): pkg-config needs it spelled.
set(ST_EXPORTED_LIBS st_api st_solve st_imageio st_fusion st_sensors_tracking st_sensors_identify
    st_sensors_detect st_sensors_attitude st_sensors_camera st_catalog st_common)

# `startracker` is the launcher; it runs startracker-solve (solve) or startracker-cli (every
# other command) from the same folder.
install(TARGETS startracker startracker-cli startracker-solve RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
install(TARGETS startracker_sim LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT runtime)
# The MRPT plugin is the package's separate `mrpt` component: find_package(startracker
# COMPONENTS mrpt) -> startracker::mrpt (the core package names no MRPT).
install(TARGETS startracker_mrpt EXPORT startrackerMrptTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT runtime)
install(FILES ${ST_ROOT}/sensors/mrpt/observation_star_tracker.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/startracker/mrpt COMPONENT dev)
install(EXPORT startrackerMrptTargets NAMESPACE startracker:: DESTINATION ${ST_CMAKE_INSTALL_DIR}
        COMPONENT dev)
install(FILES ${ST_ROOT}/catalog/data/hip_main_v6.6.dat.gz ${ST_ROOT}/catalog/data/bsc5
              ${ST_ROOT}/catalog/data/README.md
        DESTINATION ${ST_DATA_INSTALL_DIR} COMPONENT runtime)

install(TARGETS ${ST_EXPORTED_LIBS} st_warnings EXPORT startrackerTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
# Only the public headers: the facade and the seam types it names (include/startracker/).
# The stage headers are the library's own and are not installed.
file(GLOB _st_public_headers ${ST_ROOT}/include/startracker/*.hpp)
install(FILES ${_st_public_headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/startracker COMPONENT dev)
install(EXPORT startrackerTargets NAMESPACE startracker:: DESTINATION ${ST_CMAKE_INSTALL_DIR}
        COMPONENT dev)
configure_package_config_file(${ST_ROOT}/cmake/startrackerConfig.cmake.in
  ${CMAKE_BINARY_DIR}/startrackerConfig.cmake
  INSTALL_DESTINATION ${ST_CMAKE_INSTALL_DIR} PATH_VARS ST_DATA_INSTALL_DIR)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/startrackerConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/startrackerConfig.cmake
              ${CMAKE_BINARY_DIR}/startrackerConfigVersion.cmake
        DESTINATION ${ST_CMAKE_INSTALL_DIR} COMPONENT dev)

# pkg-config: the core library links no MRPT (the MRPT adapters are the plugins').
set(ST_PC_CFLAGS "")
set(ST_PC_LIBS "")
foreach(l ${ST_EXPORTED_LIBS})
  string(APPEND ST_PC_LIBS " -l${l}")
endforeach()
# The prefix relative to the .pc file, so that an unpacked tree (dpkg -x) works where it lies.
file(RELATIVE_PATH ST_PC_PREFIX_REL /p/${CMAKE_INSTALL_LIBDIR}/pkgconfig /p)
configure_file(${ST_ROOT}/cmake/startracker.pc.in ${CMAKE_BINARY_DIR}/startracker.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/startracker.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig
        COMPONENT dev)
