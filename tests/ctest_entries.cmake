# Writes the ctest entries of the test binary (run after each link of it, from
# tests/CMakeLists.txt): one entry per test case for the suites named in PER_CASE_SUITES (the
# command-line tests of tests/cli/, each of which runs programs and takes seconds to minutes),
# and one entry per suite for all others (unit tests of a few milliseconds each, where starting
# the process, which loads the 265 shared libraries OpenImageIO brings, cost more than the test).
#   -D TEST_EXECUTABLE=…  -D CTEST_FILE=…  -D WORKING_DIRECTORY=…  -D PER_CASE_SUITES=A,B,…
#   -D TEST_TIMEOUT=seconds
# The list comes from the binary itself (--gtest_list_tests), so every case is in exactly one
# entry whatever the sources look like.
cmake_minimum_required(VERSION 3.25)  # a script has no project policies: IN_LIST
string(REPLACE "," ";" PER_CASE_SUITES "${PER_CASE_SUITES}")
execute_process(COMMAND "${TEST_EXECUTABLE}" --gtest_list_tests
                OUTPUT_VARIABLE listing RESULT_VARIABLE status TIMEOUT 60)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${TEST_EXECUTABLE} --gtest_list_tests failed (${status}):\n${listing}")
endif()

set(entries "")
set(suite "")
set(per_case FALSE)
string(REPLACE "\n" ";" lines "${listing}")
foreach(line IN LISTS lines)
  # "Suite." or "Prefix/Suite." starts a suite; "  Case" or "  Case/0  # GetParam() = …" is a case.
  string(REGEX REPLACE "[ ]*#.*$" "" line "${line}")
  if(line MATCHES "^([^ ]+)\\.$")
    set(suite "${CMAKE_MATCH_1}")
    string(REGEX REPLACE "^.*/" "" bare_suite "${suite}")
    if(bare_suite IN_LIST PER_CASE_SUITES)
      set(per_case TRUE)
    else()
      set(per_case FALSE)
      list(APPEND entries "${suite}")
    endif()
  elseif(line MATCHES "^  ([^ ]+)$" AND per_case)
    list(APPEND entries "${suite}.${CMAKE_MATCH_1}")
  endif()
endforeach()

set(script "")
foreach(entry IN LISTS entries)
  if(entry MATCHES "\\.")
    set(filter "${entry}")
    # A skipped case (GTEST_SKIP: its benchmark data is absent) shows as skipped. A suite entry
    # has no such expression: one skipped case must not hide its neighbours' results.
    set(skip "SKIP_REGULAR_EXPRESSION [==[\\[  SKIPPED \\]]==]")
  else()
    set(filter "${entry}.*")
    set(skip "")
  endif()
  string(APPEND script
    "add_test([==[${entry}]==] [==[${TEST_EXECUTABLE}]==] [==[--gtest_filter=${filter}]==])\n"
    "set_tests_properties([==[${entry}]==] PROPERTIES WORKING_DIRECTORY [==[${WORKING_DIRECTORY}]==] "
    "TIMEOUT ${TEST_TIMEOUT} ${skip})\n")
endforeach()
file(WRITE "${CTEST_FILE}" "${script}")
