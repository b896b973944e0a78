# Progress on stderr (docs/cli.md, "Progress"): under a pseudo-terminal (util-linux `script`)
# the long commands draw a bar or stage line redrawn with "\r"; with -q, or when stderr is not
# a terminal (a pipe, as here without `script`), nothing of it is printed.
#   cmake -DDERMIS=<dermis> -DWORK=<dir> -DDATA=<../shared/data> -P progress_test.cmake
set(source ${DATA}/gltf/RiggedSimple.glb)
if(NOT EXISTS ${source})
  message(STATUS "skipped: ${source} is absent (../shared/data)")
  return()
endif()
find_program(SCRIPT script)
if(NOT SCRIPT)
  message(FATAL_ERROR "util-linux 'script' is needed to give the commands a terminal")
endif()
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${DERMIS} fit ${source} -o ${WORK}/rs.dsurf -q RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "dermis fit ${source} failed")
endif()

# command|what its progress line shows (the first)&what it must also show on a terminal (each
# stage of the fit as a fraction of the fit's work, with the time left; the stages of animate)
set(cases
  "export ${WORK}/rs.dsurf -o ${WORK}/bake.glb --bake-sweep --force|baking frames"
  "render ${WORK}/rs.dsurf -o ${WORK}/sheet.png --frames 3 --size 64x64 --force|posing frames"
  "tessellate --builtin cube --level 16 -o ${WORK}/cube.obj --force|evaluating samples&writing the OBJ"
  "animate ${WORK}/rs.dsurf -o ${WORK}/pose.obj --time 1 --force|posing steps&evaluating the rest surface&writing the OBJ"
  "fit ${source} -o ${WORK}/again.dsurf --refit --force|mesh 0 component 0: &% mesh 0 component 0: control mesh&% mesh 0 component 0: projection and optimisation&% mesh 0 component 0: displacement functions&% mesh 0 component 0: error metrics&s left")
foreach(case ${cases})
  string(REPLACE "|" ";" parts "${case}")
  list(GET parts 0 args)
  list(GET parts 1 shown_all)
  string(REPLACE "&" ";" shown_all "${shown_all}")
  list(GET shown_all 0 shown)
  # A terminal: the line is drawn (and erased with ESC [ K).
  execute_process(COMMAND ${SCRIPT} -qec "${DERMIS} ${args}" /dev/null
                  OUTPUT_VARIABLE tty ERROR_VARIABLE tty_err RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "dermis ${args} under a terminal failed (${rc}):\n${tty}${tty_err}")
  endif()
  foreach(part ${shown_all})
    string(FIND "${tty}" "${part}" at)
    if(at EQUAL -1)
      message(FATAL_ERROR "dermis ${args}: '${part}' is not on the terminal:\n${tty}")
    endif()
  endforeach()
  string(FIND "${tty}" "${shown}" at)
  string(FIND "${tty}" "\r" cr)
  if(at EQUAL -1 OR cr EQUAL -1)
    message(FATAL_ERROR "dermis ${args}: no progress ('${shown}' redrawn) on a terminal:\n${tty}")
  endif()
  # -q on a terminal: none.
  execute_process(COMMAND ${SCRIPT} -qec "${DERMIS} ${args} -q" /dev/null
                  OUTPUT_VARIABLE quiet RESULT_VARIABLE rc)
  string(FIND "${quiet}" "${shown}" at)
  if(NOT rc EQUAL 0 OR NOT at EQUAL -1)
    message(FATAL_ERROR "dermis ${args} -q printed progress or failed:\n${quiet}")
  endif()
  # Not a terminal: none.
  separate_arguments(argv UNIX_COMMAND "${args}")
  execute_process(COMMAND ${DERMIS} ${argv} ERROR_VARIABLE piped OUTPUT_QUIET RESULT_VARIABLE rc)
  string(FIND "${piped}" "${shown}" at)
  string(FIND "${piped}" "\r" cr)
  if(NOT rc EQUAL 0 OR NOT at EQUAL -1 OR NOT cr EQUAL -1)
    message(FATAL_ERROR "dermis ${args} printed progress into a pipe or failed:\n${piped}")
  endif()
endforeach()
message(STATUS "progress: drawn on a terminal, silent with -q and in pipes")
