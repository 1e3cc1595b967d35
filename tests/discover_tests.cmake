# Registers the test executable's tests with CTest, run after each link (cmake -P):
# TEST_EXECUTABLE lists its tests, and CTEST_FILE gets one add_test per suite of quick
# tests (each process starts in about 0.1 s, most of it the loader binding the libraries,
# which a suite's tests then share) and one per test of the suites in APART (those that
# plan or read whole parts, so that they share the cores and none runs long) and of the
# parameterised suites. Every test gets TIMEOUT and waits for the fixture FIXTURE.

cmake_minimum_required(VERSION 3.25)

execute_process(COMMAND "${TEST_EXECUTABLE}" --gtest_list_tests
                OUTPUT_VARIABLE listing RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "${TEST_EXECUTABLE} --gtest_list_tests failed: ${result}")
endif()

string(REPLACE "," ";" APART "${APART}")
set(content "")
macro(add_one name filter)
  string(APPEND content
         "add_test([=[${name}]=] \"${TEST_EXECUTABLE}\" [=[--gtest_filter=${filter}]=])\n"
         "set_tests_properties([=[${name}]=] PROPERTIES TIMEOUT ${TIMEOUT}"
         " FIXTURES_REQUIRED ${FIXTURE})\n")
endmacro()

string(REPLACE "\n" ";" lines "${listing}")
foreach(line IN LISTS lines)
  if(line MATCHES "^([^ #][^ ]*)\\.")  # a suite
    set(suite "${CMAKE_MATCH_1}")
    if(suite IN_LIST APART OR suite MATCHES "/")
      set(apart TRUE)
    else()
      set(apart FALSE)
      add_one("${suite}" "${suite}.*")
    endif()
  elseif(line MATCHES "^  ([^ ]+)" AND apart)  # a test of a suite run test by test
    add_one("${suite}.${CMAKE_MATCH_1}" "${suite}.${CMAKE_MATCH_1}")
  endif()
endforeach()
file(WRITE "${CTEST_FILE}" "${content}")
