# Install.DownstreamProjectBuildsAgainstThePackage: `cmake --install` the build into a folder of
# its own, then configure, build and run examples/downstream against it, as a user's project
# would (find_package(eitbench), eitbench::solvers). Run by ctest with -DBUILD= and -DSOURCE=.
set(root ${BUILD}/install_test)
file(REMOVE_RECURSE ${root})
function(step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "failed (${status}): ${ARGN}\n${out}\n${err}")
  endif()
  message("${out}")
endfunction()
step(${CMAKE_COMMAND} --install ${BUILD} --prefix ${root}/prefix)
step(${CMAKE_COMMAND} -S ${SOURCE}/examples/downstream -B ${root}/downstream
     -DCMAKE_PREFIX_PATH=${root}/prefix -DCMAKE_BUILD_TYPE=Release)
step(${CMAKE_COMMAND} --build ${root}/downstream)
step(${root}/downstream/downstream)
