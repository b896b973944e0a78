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

# --gpu (builds with dermis::gpu): the same frames on a Vulkan device, checked against the CPU
# by the sample itself. Exit 77 without a device: a skip, except under DERMIS_GPU_REQUIRED=1.
if(GPU)
  set(gpu_runs "torus.dsurf --frames 3")
  if(EXISTS ${WORK}/rigged.dsurf)
    list(APPEND gpu_runs "rigged.dsurf --frames 6 --deformer sweep")
  endif()
  # Under AddressSanitizer, without leak detection: the sample destroys its Vulkan instance,
  # the loader unloads Mesa's driver, and LeakSanitizer reports the allocations the driver's
  # (then unmapped) globals held; a plain vkCreateInstance + vkDestroyInstance shows the same.
  set(env)
  if(SANITIZE)
    set(env ${CMAKE_COMMAND} -E env "ASAN_OPTIONS=$ENV{ASAN_OPTIONS}:detect_leaks=0")
  endif()
  foreach(args ${gpu_runs})
    separate_arguments(args UNIX_COMMAND "${args}")
    execute_process(COMMAND ${env} ${SAMPLE} ${WORK}/${args} --gpu RESULT_VARIABLE code
                    OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(code EQUAL 77 AND NOT "$ENV{DERMIS_GPU_REQUIRED}" STREQUAL "1")
      message(STATUS "SKIPPED the GPU mode: ${out}")
      break()
    endif()
    if(NOT code EQUAL 0 OR NOT out MATCHES "GPU: .*GPU against the CPU.*engine_loop: ok")
      message(FATAL_ERROR "--gpu ${args} exited ${code}\n${out}\n${err}")
    endif()
    string(REGEX MATCH "GPU against the CPU[^\n]*" line "${out}")
    string(REPLACE ";" " " shown "${args}")
    message(STATUS "--gpu ${shown}: ${line}")
  endforeach()
else()
  run(2 ${SAMPLE} ${WORK}/torus.dsurf --gpu)  # a build without the GPU says so
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
