# Tests of the installed tree (issue 20), included from tests/CMakeLists.txt:
#  install_tree       cmake --install into build/test-install (a fixture for the others);
#  install_consumer   a separate CMake project (consumer/) configured against that prefix
#                     with find_package(startracker), built, and run on the eight frames;
#  install_pkgconfig  the same program compiled with only `pkg-config --cflags --libs`;
#  install_python     pytest (python/tests) importing the module from that prefix;
#  package_deb        the .deb (cpack), unpacked with dpkg -x: no missing libraries, and
#                     the unpacked startracker and Python module solve a real frame.
set(ST_TEST_PREFIX ${CMAKE_BINARY_DIR}/test-install)
set(_frames ${ST_ROOT}/tests/data/tetra3)
set(_launcher "")
if(CMAKE_CXX_COMPILER_LAUNCHER)
  set(_launcher "-DCMAKE_CXX_COMPILER_LAUNCHER=${CMAKE_CXX_COMPILER_LAUNCHER}")
endif()

add_test(NAME install_tree
         COMMAND sh -c "rm -rf '${ST_TEST_PREFIX}' && '${CMAKE_COMMAND}' --install '${CMAKE_BINARY_DIR}' --prefix '${ST_TEST_PREFIX}' >/dev/null")
set_tests_properties(install_tree PROPERTIES FIXTURES_SETUP st_installed LABELS install)

# The installed headers are the public ones only, and none of them names MRPT or CLI11: a
# flight program compiles against them with OpenCV and Eigen alone.
add_test(NAME install_public_headers
         COMMAND sh -c "cd '${ST_TEST_PREFIX}/include' && ls startracker && ! grep -hE '^ *# *include' startracker/*.hpp | grep -E 'mrpt|CLI|.(common|sensors|catalog|fusion|config|solve|app|api|imageio|navigation)/' && [ $(ls startracker/*.hpp | wc -l) -eq $(ls '${ST_ROOT}/include/startracker' | wc -l) ] && ! grep -iq mrpt '${ST_TEST_PREFIX}/${CMAKE_INSTALL_LIBDIR}/pkgconfig/startracker.pc'")
set_tests_properties(install_public_headers PROPERTIES FIXTURES_REQUIRED st_installed LABELS install)

# The separate MRPT component: a program that reads the project's observations.
add_test(NAME install_mrpt_component
         COMMAND sh -c "rm -rf consumer-mrpt-build && '${CMAKE_COMMAND}' -S '${CMAKE_CURRENT_SOURCE_DIR}/install/consumer_mrpt' -B consumer-mrpt-build -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH='${ST_TEST_PREFIX}' ${_launcher} >/dev/null && '${CMAKE_COMMAND}' --build consumer-mrpt-build >/dev/null && LD_LIBRARY_PATH='${ST_TEST_PREFIX}/${CMAKE_INSTALL_LIBDIR}' consumer-mrpt-build/consumer_mrpt"
         WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
set_tests_properties(install_mrpt_component PROPERTIES FIXTURES_REQUIRED st_installed LABELS install
                     PASS_REGULAR_EXPRESSION "st::CObservationStarTracker round trip: tracking, 1 star")

add_test(NAME install_consumer
         COMMAND sh -c "rm -rf consumer-build && '${CMAKE_COMMAND}' -S '${CMAKE_CURRENT_SOURCE_DIR}/install/consumer' -B consumer-build -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH='${ST_TEST_PREFIX}' ${_launcher} >/dev/null && '${CMAKE_COMMAND}' --build consumer-build >/dev/null && consumer-build/consumer '${_frames}'/*.tiff"
         WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
set_tests_properties(install_consumer PROPERTIES FIXTURES_REQUIRED st_installed LABELS install
                     PASS_REGULAR_EXPRESSION "solved 8 of 8, tracker: lost-in-space then tracking")

add_test(NAME install_pkgconfig
         COMMAND sh -c "PKG_CONFIG_PATH='${ST_TEST_PREFIX}/${CMAKE_INSTALL_LIBDIR}/pkgconfig' && export PKG_CONFIG_PATH && ${CMAKE_CXX_COMPILER} -O1 -o consumer-pc '${CMAKE_CURRENT_SOURCE_DIR}/install/consumer/main.cpp' $(pkg-config --cflags --libs startracker) && ./consumer-pc '${_frames}'/*Alt60_Azi45*.tiff"
         WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
set_tests_properties(install_pkgconfig PROPERTIES FIXTURES_REQUIRED st_installed LABELS install
                     PASS_REGULAR_EXPRESSION "solved 1 of 1, tracker: lost-in-space then tracking")

if(TARGET _startracker)
  add_test(NAME install_python
           COMMAND sh -c "PYTHONPATH='${ST_TEST_PREFIX}/lib/python3/dist-packages' ST_STARTRACKER_EXE='${ST_TEST_PREFIX}/bin/startracker' /usr/bin/python3 -m pytest -q -p no:cacheprovider '${ST_ROOT}/python/tests'")
  set_tests_properties(install_python PROPERTIES FIXTURES_REQUIRED st_installed LABELS "install;python")
  # The package holds the module too (ST_BUILD_PYTHON): the test imports it from the .deb.
  add_test(NAME package_deb
           COMMAND sh ${CMAKE_CURRENT_SOURCE_DIR}/install/test_deb.sh ${CMAKE_BINARY_DIR} ${CMAKE_CURRENT_BINARY_DIR}/deb-test ${_frames})
  set_tests_properties(package_deb PROPERTIES LABELS install TIMEOUT 600)
endif()
