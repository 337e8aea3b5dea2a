# Checks VISFIELD_REQUIRE_CUDA=1 (ctest -L cuda runs this with TEST_BINARY = test_cuda): where the
# device query, left alone, skips (no usable device), under VISFIELD_REQUIRE_CUDA=1 it must fail and
# say why; where it passes (a device), it must pass under VISFIELD_REQUIRE_CUDA=1 too.
set(filter --gtest_filter=Cuda.DeviceQuery)
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=VISFIELD_REQUIRE_CUDA ${TEST_BINARY} ${filter}
  RESULT_VARIABLE plain OUTPUT_VARIABLE plain_out ERROR_VARIABLE plain_out)
execute_process(COMMAND ${CMAKE_COMMAND} -E env VISFIELD_REQUIRE_CUDA=1 ${TEST_BINARY} ${filter}
  RESULT_VARIABLE required OUTPUT_VARIABLE required_out ERROR_VARIABLE required_out)
string(FIND "${plain_out}" "[  SKIPPED ]" skipped)
if(NOT plain EQUAL 0)
  message(FATAL_ERROR "the device query failed without VISFIELD_REQUIRE_CUDA:\n${plain_out}")
elseif(skipped GREATER -1)
  string(FIND "${required_out}" "VISFIELD_REQUIRE_CUDA=1 but no CUDA device is usable" said)
  if(required EQUAL 0 OR said EQUAL -1)
    message(FATAL_ERROR "no device, yet VISFIELD_REQUIRE_CUDA=1 did not fail the device query with its message:\n${required_out}")
  endif()
  message(STATUS "no device: skipped alone, failed under VISFIELD_REQUIRE_CUDA=1, as it must")
elseif(NOT required EQUAL 0)
  message(FATAL_ERROR "a device, yet the device query failed under VISFIELD_REQUIRE_CUDA=1:\n${required_out}")
else()
  message(STATUS "a device: the device query passed alone and under VISFIELD_REQUIRE_CUDA=1")
endif()
