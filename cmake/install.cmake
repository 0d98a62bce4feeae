# `cmake --install build --prefix DIR`, then find_package(eitbench) in another project: the module
# libraries as eitbench::jacobian, ::augment, ::solvers, ::learned and ::bench_* (static), their
# headers, the eitbench tool, and a versioned package config that finds their dependencies.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(eitbench_libraries eitbench_jacobian eitbench_augment eitbench_solvers eitbench_learned)
foreach(part support io data report methods run ktc)
  list(APPEND eitbench_libraries eitbench_bench_${part})
endforeach()
# The wrappers of the dependencies without a CMake package of their own travel with them.
set(eitbench_wrappers eitbench_cholmod eitbench_opencv eitbench_bench)
if(EITBENCH_WITH_GMSH)
  list(APPEND eitbench_wrappers eitbench_gmsh)
endif()
foreach(target ${eitbench_libraries} ${eitbench_wrappers})
  string(REPLACE "eitbench_" "" short ${target})  # eitbench::jacobian, eitbench::bench_io, ...
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${short})
endforeach()

install(TARGETS ${eitbench_libraries} ${eitbench_wrappers} EXPORT eitbenchTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS eitbench RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# learned/'s LibTorch module: the tool finds it in ../lib from itself, a program in this prefix.
install(TARGETS eitbench_learned_torch LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
foreach(dir jacobian augment solvers learned)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${dir}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endforeach()
foreach(part support io data report methods run ktc)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/bench/${part}/include/
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endforeach()

set(eitbench_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/eitbench)
install(EXPORT eitbenchTargets NAMESPACE eitbench:: DESTINATION ${eitbench_cmake_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/eitbenchConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/eitbenchConfig.cmake
                              INSTALL_DESTINATION ${eitbench_cmake_dir})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/eitbenchConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/eitbenchConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/eitbenchConfigVersion.cmake
        DESTINATION ${eitbench_cmake_dir})
