# `-o -` and the JSON reports (docs/cli.md, "Conventions" and "Reports"):
# - tessellate and animate write OBJ / GLB to stdout byte for byte as to a file, and nothing
#   else (messages stay on stderr); commands whose output cannot stream refuse `-o -` (exit 2,
#   one line);
# - every JSON report (fit --report for a surface and a character, inspect --json, validate
#   --json) records dermis_version and its effective options, and a fit run again with the
#   options its report recorded writes the same .dsurf.
#   cmake -DDERMIS=<dermis> -DWORK=<dir> -DDATA=<../shared/data> -P stdout_reports_test.cmake
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

function(run_ok)
  execute_process(COMMAND ${DERMIS} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "dermis ${ARGN} failed (${rc}):\n${out}${err}")
  endif()
endfunction()

# The same bytes on stdout as in the file; stdout gets nothing else. ${stdout_args}: what the
# stdout run adds (animate's --format).
function(same_on_stdout file)
  run_ok(${ARGN} -o ${file} -q --force)
  execute_process(COMMAND ${DERMIS} ${ARGN} -o - ${stdout_args} OUTPUT_FILE ${file}.stdout ERROR_VARIABLE err
                  RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "dermis ${ARGN} -o - failed (${rc}):\n${err}")
  endif()
  file(SHA256 ${file} a)
  file(SHA256 ${file}.stdout b)
  file(SIZE ${file} size)
  if(NOT a STREQUAL b OR size EQUAL 0)
    message(FATAL_ERROR "dermis ${ARGN} -o - differs from -o ${file}")
  endif()
  string(FIND "${err}" "wrote <stdout>" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "dermis ${ARGN} -o -: no 'wrote <stdout>' on stderr:\n${err}")
  endif()
endfunction()

# Refused with exit 2 and a one-line message (plus the usage hint).
function(refused what)
  execute_process(COMMAND ${DERMIS} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  string(FIND "${err}" "${what}" at)
  if(NOT rc EQUAL 2 OR at EQUAL -1 OR NOT out STREQUAL "")
    message(FATAL_ERROR "dermis ${ARGN}: expected exit 2 with '${what}', got ${rc}:\n${out}${err}")
  endif()
endfunction()

# The report's version and options.
function(has_header json_file)
  file(READ ${json_file} json)
  string(JSON version GET "${json}" dermis_version)
  string(JSON type TYPE "${json}" options)
  if(version STREQUAL "" OR NOT type STREQUAL "OBJECT")
    message(FATAL_ERROR "${json_file}: no dermis_version or options")
  endif()
endfunction()

same_on_stdout(${WORK}/cube.obj tessellate --builtin cube --level 4)
refused("error: -: the output must be a .png file" render ${WORK}/cube.obj -o -)
refused("'-o -' (stdout) is not supported" fit ${WORK}/cube.obj -o -)
execute_process(COMMAND ${DERMIS} inspect ${WORK}/cube.obj --json OUTPUT_FILE ${WORK}/inspect.json
                RESULT_VARIABLE rc)
has_header(${WORK}/inspect.json)
execute_process(COMMAND ${DERMIS} validate ${WORK}/cube.obj --json
                OUTPUT_FILE ${WORK}/validate.json RESULT_VARIABLE rc)
has_header(${WORK}/validate.json)

set(scan ${DATA}/scans/bunny-npm-1839v.obj)
set(character ${DATA}/gltf/RiggedSimple.glb)
if(NOT EXISTS ${scan} OR NOT EXISTS ${character})
  message(STATUS "skipped the fits: ${scan} or ${character} is absent (../shared/data)")
  return()
endif()

# A surface fit with options off their defaults, then again with only what its report recorded.
run_ok(fit ${scan} -o ${WORK}/bunny.dsurf --report ${WORK}/bunny.json --levels 4
       --control-vertices 120 --smoothing 0.002 --holdout 0.2 -q)
has_header(${WORK}/bunny.json)
file(READ ${WORK}/bunny.json json)
string(JSON n LENGTH "${json}" options)
math(EXPR last "${n} - 1")
set(again)
foreach(i RANGE ${last})
  string(JSON key MEMBER "${json}" options ${i})
  string(JSON type TYPE "${json}" options ${key})
  string(JSON value GET "${json}" options ${key})
  if(type STREQUAL "BOOLEAN")
    if(value)
      list(APPEND again --${key})
    endif()
  else()
    list(APPEND again --${key} ${value})
  endif()
endforeach()
string(JSON levels GET "${json}" options levels)
if(NOT levels EQUAL 4)
  message(FATAL_ERROR "the report's options do not hold --levels 4: ${again}")
endif()
run_ok(fit ${scan} -o ${WORK}/bunny_again.dsurf ${again} -q)
file(SHA256 ${WORK}/bunny.dsurf a)
file(SHA256 ${WORK}/bunny_again.dsurf b)
if(NOT a STREQUAL b)
  message(FATAL_ERROR "fit with the recorded options (${again}) wrote a different .dsurf")
endif()

# A character: its report, and animate's OBJ and GLB on stdout.
run_ok(fit ${character} -o ${WORK}/rs.dsurf --report ${WORK}/rs.json -q)
has_header(${WORK}/rs.json)
same_on_stdout(${WORK}/pose.glb animate ${WORK}/rs.dsurf --time 0.5)
set(stdout_args --format obj)
same_on_stdout(${WORK}/pose.obj animate ${WORK}/rs.dsurf --time 0.5)
refused("--format applies to '-o -'" animate ${WORK}/rs.dsurf -o ${WORK}/x.obj --format obj)
message(STATUS "stdout: same bytes as the files; reports: version and options, fit repeated")
