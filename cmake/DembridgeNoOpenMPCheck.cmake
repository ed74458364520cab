# The no-OpenMP build (-DDEMBRIDGE_WITH_OPENMP=OFF, or no OpenMP found) compiles the threaded code
# with every `omp` pragma and call left out. The test build.no_openmp checks it without a second
# build tree: the translation units that use OpenMP, compiled here without it (-Wunknown-pragmas
# catches an unguarded pragma; warnings are errors when the build has them on).
if(DEMBRIDGE_BUILD_TESTS AND DEMBRIDGE_OPENMP)
  set(_sources pair_styles/pair_gran_omp.cpp fixes/fix_contact_history.cpp fixes/integrate/fix_nve_bpm_sphere_omp.cpp)
  set(_libs LAMMPS::lammps dembridge_materials dembridge_contact dembridge_threads)
  if(TARGET dembridge_springs)
    list(APPEND _sources fixes/springs/fix_parmec_spring.cpp)
    list(APPEND _libs dembridge_springs)
  endif()
  add_library(dembridge_no_openmp_check OBJECT EXCLUDE_FROM_ALL ${_sources})
  target_include_directories(dembridge_no_openmp_check PRIVATE $<TARGET_PROPERTY:dembridgeplugin,INCLUDE_DIRECTORIES>)
  target_compile_definitions(dembridge_no_openmp_check PRIVATE $<TARGET_PROPERTY:dembridgeplugin,COMPILE_DEFINITIONS>)
  target_link_libraries(dembridge_no_openmp_check PRIVATE ${_libs})
  target_compile_options(dembridge_no_openmp_check PRIVATE -O0 -Wunknown-pragmas)  # -O0: a quick compile
  add_test(NAME build.no_openmp COMMAND ${CMAKE_COMMAND} --build ${CMAKE_BINARY_DIR} --target dembridge_no_openmp_check)
endif()
