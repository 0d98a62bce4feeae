# The environment every test runs in.
#
# ctest -j2 runs two test processes on two cores. LibTorch's and OpenBLAS's OpenMP threads spin
# while they wait for work (libgomp's default), and the spinning threads of one process take the
# cores the other's need. Measured on the 2-core Intel Xeon: a training test took 6.5 s alone and
# 57 s beside another test, 16.5 s with passive waiting; the whole suite took 24 min, and 13 min
# with passive waiting. The tests time nothing, so their threads sleep while they wait. The tool
# itself keeps libgomp's default: there passive waiting slows one frame's inference 2.8 times.
set(EITBENCH_TEST_ENVIRONMENT "OMP_WAIT_POLICY=passive")

# The tool runs itself again with OpenBLAS's kernels for the CPU where OpenBLAS fell back to its
# SSE3 ones (bench/support/blas_kernels.h): 0.6 s a start, for each of the suite's hundreds of runs
# of the tool. The tests keep the kernels OpenBLAS chose, in their own processes and the tool's
# alike; BlasKernels.* run the tool without the setting. The gtest binary sets it for the runs it
# makes (tests/keep_blas_kernels.cpp): gtest_discover_tests passes one environment entry only.
set(EITBENCH_TEST_TOOL_ENVIRONMENT "EITBENCH_KEEP_BLAS_KERNELS=1")

# Appends both environments to every test the calling directory has added so far.
function(eitbench_test_environment)
  get_property(tests DIRECTORY PROPERTY TESTS)
  if(tests)
    set_property(TEST ${tests} APPEND PROPERTY ENVIRONMENT ${EITBENCH_TEST_ENVIRONMENT}
                                                          ${EITBENCH_TEST_TOOL_ENVIRONMENT})
  endif()
endfunction()
