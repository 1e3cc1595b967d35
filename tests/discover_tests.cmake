# Registers the test executable's tests with CTest, run after each link (cmake -P):
# TEST_EXECUTABLE lists its tests, and CTEST_FILE gets one add_test per suite of quick
# tests (each process starts in about 0.14 s, most of it the loader binding the libraries,
# which a suite's tests then share), and one per test named in APART or of a suite named
# there (those that plan or read whole parts, so that they share the cores and none runs
# long). The tests of parameterised suites run as one test per parameter (`Nist/nist_ctc_02`
# runs every `Nist/*` test of NIST CTC 02), so that they share what they read of it. Every
# test gets TIMEOUT and waits for the fixture FIXTURE.

cmake_minimum_required(VERSION 3.25)

execute_process(COMMAND "${TEST_EXECUTABLE}" --gtest_list_tests
                OUTPUT_VARIABLE listing RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "${TEST_EXECUTABLE} --gtest_list_tests failed: ${result}")
endif()

string(REPLACE "," ";" APART "${APART}")
set(content "")
set(listed "")
set(groups "")  # of parameterised tests, one per instance and parameter
macro(add_one name filter)
  string(APPEND content
         "add_test([=[${name}]=] \"${TEST_EXECUTABLE}\" [=[--gtest_filter=${filter}]=])\n"
         "set_tests_properties([=[${name}]=] PROPERTIES TIMEOUT ${TIMEOUT}"
         " FIXTURES_REQUIRED ${FIXTURE})\n")
endmacro()

# A suite runs as one test but for those of its tests in APART, each alone.
macro(add_suite)
  if(DEFINED suite AND NOT suite_apart)
    set(filter "${suite}.*")
    if(alone)
      string(REPLACE ";" ":" alone "${alone}")
      set(filter "${filter}:-${alone}")
    endif()
    add_one("${suite}" "${filter}")
  endif()
endmacro()

string(REPLACE "\n" ";" lines "${listing}")
foreach(line IN LISTS lines)
  if(line MATCHES "^([^ #][^ ]*)\\.")  # a suite
    add_suite()
    set(suite "${CMAKE_MATCH_1}")
    list(APPEND listed "${suite}")
    set(alone "")
    set(parameterised FALSE)
    if(suite MATCHES "^([^/]+)/")
      set(parameterised TRUE)
      set(instance "${CMAKE_MATCH_1}")
    endif()
    if(suite IN_LIST APART OR parameterised)
      set(suite_apart TRUE)
    else()
      set(suite_apart FALSE)
    endif()
  elseif(line MATCHES "^  ([^ ]+)")  # a test
    set(test "${suite}.${CMAKE_MATCH_1}")
    list(APPEND listed "${test}")
    if(parameterised)
      string(REGEX REPLACE ".*/" "" parameter "${test}")
      if(NOT "${instance}/${parameter}" IN_LIST groups)
        list(APPEND groups "${instance}/${parameter}")
        add_one("${instance}/${parameter}" "${instance}/*/${parameter}")
      endif()
    elseif(suite_apart OR test IN_LIST APART)
      add_one("${test}" "${test}")
      list(APPEND alone "${test}")
    endif()
  endif()
endforeach()
add_suite()
foreach(name IN LISTS APART)  # a name that is no suite or test would go unnoticed
  if(NOT name IN_LIST listed)
    message(FATAL_ERROR "discover_tests: ${name} is not a suite or test of ${TEST_EXECUTABLE}")
  endif()
endforeach()
file(WRITE "${CTEST_FILE}" "${content}")
