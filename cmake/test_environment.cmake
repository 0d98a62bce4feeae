# The environment every test runs in.
#
# ctest -j2 runs two test processes on two cores. LibTorch's and OpenBLAS's OpenMP threads spin
# while they wait for work (libgomp's default), and the spinning threads of one process take the
# cores the other's need. Measured on the 2-core Intel Xeon: a training test took 6.5 s alone and
# 57 s beside another test, 16.5 s with passive waiting; the whole suite took 24 min, and 13 min
# with passive waiting. The tests time nothing, so their threads sleep while they wait. The tool
# itself keeps libgomp's default: there passive waiting slows one frame's inference 2.8 times.
set(EITBENCH_TEST_ENVIRONMENT "OMP_WAIT_POLICY=passive")

# Appends EITBENCH_TEST_ENVIRONMENT to every test the calling directory has added so far.
function(eitbench_test_environment)
  get_property(tests DIRECTORY PROPERTY TESTS)
  if(tests)
    set_property(TEST ${tests} APPEND PROPERTY ENVIRONMENT ${EITBENCH_TEST_ENVIRONMENT})
  endif()
endfunction()
