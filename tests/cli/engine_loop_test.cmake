# The C API sample (samples/engine_loop) run as a user runs it: on a static surface fitted from
# a built-in mesh, and on a skinned character fitted from the shared glTF data (skipped with a
# message where ../shared/data is absent) with each deformer; then bad usage and a missing file.
# Invoked by ctest with -DDERMIS=<tool> -DSAMPLE=<engine_loop> -DWORK=<dir> -DDATA=<data dir>.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

function(run expect)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL ${expect})
    message(FATAL_ERROR "`${ARGN}` exited ${code}, expected ${expect}\n${out}\n${err}")
  endif()
  set(run_output "${out}${err}" PARENT_SCOPE)
endfunction()

run(0 ${DERMIS} tessellate --builtin torus -o ${WORK}/dense.obj --level 6 -q)
run(0 ${DERMIS} fit ${WORK}/dense.obj -o ${WORK}/torus.dsurf --control-vertices 60 -q)
run(0 ${SAMPLE} ${WORK}/torus.dsurf --frames 4)
if(NOT run_output MATCHES "0 joints.*engine_loop: ok")
  message(FATAL_ERROR "static surface: ${run_output}")
endif()

if(EXISTS ${DATA}/gltf/RiggedSimple.glb)
  run(0 ${DERMIS} fit ${DATA}/gltf/RiggedSimple.glb -o ${WORK}/rigged.dsurf -q)
  foreach(deformer lbs dqs sweep)
    run(0 ${SAMPLE} ${WORK}/rigged.dsurf --frames 12 --deformer ${deformer})
    if(NOT run_output MATCHES "2 joints.*bound: 160 vertices.*engine_loop: ok")
      message(FATAL_ERROR "RiggedSimple with ${deformer}: ${run_output}")
    endif()
  endforeach()
else()
  message(STATUS "SKIPPED the skinned character: ${DATA}/gltf/RiggedSimple.glb not found")
endif()

run(2 ${SAMPLE})
run(1 ${SAMPLE} ${WORK}/missing.dsurf)
if(NOT run_output MATCHES "missing.dsurf")
  message(FATAL_ERROR "a missing file is not named: ${run_output}")
endif()
file(WRITE ${WORK}/garbage.dsurf "this is not a surface")
run(1 ${SAMPLE} ${WORK}/garbage.dsurf)
if(NOT run_output MATCHES "garbage.dsurf")
  message(FATAL_ERROR "a damaged file is not named: ${run_output}")
endif()
