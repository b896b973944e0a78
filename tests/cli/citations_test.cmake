# Every citation in the repository points into the repository (CONTRIBUTING.md, "Citations"):
#   - a document `x.md` (by its path from the repository root, or beside the citing file) exists,
#     and none is cited outside the repository (`../shared/...` or any `../`);
#   - a test file `tests/.../x_test.cpp` exists;
#   - a test cited by name, test `NAME` or `NAME` test, is one ctest knows.
# Scanned: sources, headers, tests, tools, benchmarks, samples, scripts, CMake files, docs.
#
#   cmake -DROOT=<repository> -DBUILD=<build dir> -P citations_test.cmake
#   cmake -DSELF_TEST=ON -DWORK=<scratch dir> -P citations_test.cmake
# The second form builds a small tree with one citation of each bad kind and fails unless every
# one of them is reported and the good ones are not (so the check is known to be able to fail).
cmake_policy(SET CMP0057 NEW)

# check_citations(ROOT FILES TESTS OUT): appends one message per bad citation to OUT.
function(check_citations root files tests out)
  set(errors)
  foreach(f ${files})
    file(READ ${f} text)
    file(RELATIVE_PATH rel ${root} ${f})
    get_filename_component(dir ${f} DIRECTORY)
    # URLs are not citations of files.
    string(REGEX REPLACE "[a-z]+://[^ \t\n)\"'`>]*" "" text "${text}")
    # Documents.
    string(REGEX MATCHALL "[A-Za-z0-9_./\${}-]*[A-Za-z0-9_}-]+\\.md" docs "${text}")
    foreach(doc ${docs})
      if(doc MATCHES "\\$")  # a shell variable: an output path, not a citation
        continue()
      endif()
      string(REGEX REPLACE "^(\\./)+" "" doc "${doc}")
      if(doc MATCHES "^\\.\\./" OR doc MATCHES "/\\.\\./")
        list(APPEND errors "${rel}: cites '${doc}', a document outside the repository")
      elseif(NOT EXISTS ${root}/${doc} AND NOT EXISTS ${dir}/${doc})
        list(APPEND errors "${rel}: cites '${doc}', which does not exist (cite documents by their path from the repository root)")
      endif()
    endforeach()
    # Test files.
    string(REGEX MATCHALL "tests/[A-Za-z0-9_/.-]+\\.(cpp|h|cmake|js)[^A-Za-z0-9_]" test_files
           "${text}")
    foreach(t ${test_files})
      string(REGEX REPLACE ".$" "" t "${t}")
      if(t MATCHES "/node_modules/")  # installed by scripts/setup_js.sh, not part of the tree
        continue()
      endif()
      if(NOT EXISTS ${root}/${t})
        list(APPEND errors "${rel}: cites the test file '${t}', which does not exist")
      endif()
    endforeach()
    # Tests by name.
    string(REGEX MATCHALL "test `[^`\n]+`|tested: `[^`\n]+`|`[^`\n]+` tests?[^a-z_]" named
           "${text}")
    foreach(n ${named})
      string(REGEX REPLACE "^(test|tested:) `([^`]+)`$" "\\2" name "${n}")
      string(REGEX REPLACE "^`([^`]+)` tests?.$" "\\1" name "${name}")
      if(NOT name IN_LIST tests)
        list(APPEND errors "${rel}: cites the test '${name}', which ctest does not know")
      endif()
    endforeach()
  endforeach()
  set(${out} ${errors} PARENT_SCOPE)
endfunction()

if(SELF_TEST)
  file(REMOVE_RECURSE ${WORK})
  file(WRITE ${WORK}/docs/notes/real.md "# A note\n")
  file(WRITE ${WORK}/tests/core/real_test.cpp "// a test file\n")
  file(WRITE ${WORK}/sdk/src/cited.cpp
       "// Good: docs/notes/real.md section 2, tests/core/real_test.cpp, test `real test`,\n"
       "// `real test` test, https://example.org/elsewhere/README.md, \$out/made.md.\n"
       "// Bad: docs/notes/missing.md, ../shared/docs/manifold.md, manifold.md,\n"
       "// tests/runtime/evaluation_plan_test.cpp, tested: `no such test`.\n")
  check_citations(${WORK} "${WORK}/sdk/src/cited.cpp" "real test" errors)
  set(expected "'docs/notes/missing.md'" "'../shared/docs/manifold.md'" "'manifold.md'"
               "'tests/runtime/evaluation_plan_test.cpp'" "'no such test'")
  list(LENGTH errors n)
  foreach(e ${expected})
    string(FIND "${errors}" "${e}" at)
    if(at EQUAL -1)
      message(FATAL_ERROR "the check missed the bad citation ${e}; it reported:\n${errors}")
    endif()
  endforeach()
  if(NOT n EQUAL 5)
    message(FATAL_ERROR "expected 5 bad citations, got ${n}:\n${errors}")
  endif()
  message(STATUS "the check reports each of the 5 bad citations and none of the good ones")
  return()
endif()

# The tests ctest knows.
execute_process(COMMAND ${CMAKE_CTEST_COMMAND} -N --test-dir ${BUILD} OUTPUT_VARIABLE listing
                RESULT_VARIABLE code)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "ctest -N failed in ${BUILD}")
endif()
string(REGEX MATCHALL "Test +#[0-9]+: [^\n]+" lines "${listing}")
set(tests)
foreach(l ${lines})
  string(REGEX REPLACE "^Test +#[0-9]+: " "" name "${l}")
  list(APPEND tests "${name}")
endforeach()
# Tests this configuration leaves out (e.g. the install tests under the sanitizers), comma-separated.
if(ELSEWHERE)
  string(REPLACE "," ";" elsewhere "${ELSEWHERE}")
  list(APPEND tests ${elsewhere})
endif()

file(GLOB_RECURSE files
     ${ROOT}/sdk/*.h ${ROOT}/sdk/*.cpp ${ROOT}/plugins/*.h ${ROOT}/plugins/*.cpp
     ${ROOT}/tools/*.h ${ROOT}/tools/*.cpp ${ROOT}/bench/*.cpp ${ROOT}/samples/*.c
     ${ROOT}/samples/*.cpp ${ROOT}/samples/*.sh ${ROOT}/samples/*.md ${ROOT}/tests/*.h
     ${ROOT}/tests/*.cpp ${ROOT}/tests/*.cmake ${ROOT}/tests/*.md ${ROOT}/scripts/*.sh
     ${ROOT}/cmake/*.cmake ${ROOT}/cmake/*.in ${ROOT}/docs/*.md ${ROOT}/sdk/CMakeLists.txt
     ${ROOT}/plugins/CMakeLists.txt ${ROOT}/tools/CMakeLists.txt ${ROOT}/tests/CMakeLists.txt
     ${ROOT}/bench/CMakeLists.txt ${ROOT}/samples/CMakeLists.txt)
file(GLOB js_files ${ROOT}/tests/js/*.js)
list(APPEND files ${js_files} ${ROOT}/CMakeLists.txt ${ROOT}/README.md ${ROOT}/CONTRIBUTING.md
     ${ROOT}/.ci/run)
list(FILTER files EXCLUDE REGEX "/node_modules/|/tests/cli/citations_test.cmake$")
list(REMOVE_DUPLICATES files)
set(existing)
foreach(f ${files})
  if(EXISTS ${f})
    list(APPEND existing ${f})
  endif()
endforeach()
check_citations(${ROOT} "${existing}" "${tests}" errors)
list(LENGTH existing n)
if(errors)
  list(JOIN errors "\n" report)
  message(FATAL_ERROR "citations of files or tests that do not exist:\n${report}")
endif()
message(STATUS "checked the citations of ${n} files")
