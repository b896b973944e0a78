# Installs the build into a scratch prefix, then builds and runs tests/consumer against it with
# find_package(dermis CONFIG), and a runtime-only program with pkg-config's flags alone.
# Invoked by ctest with -DBUILD=<build dir> -DSOURCE=<repository root> -DWORK=<scratch dir>.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "`${ARGN}` exited ${code}\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix)
# Every expected file, with the library folder allowed to be multiarch (lib/x86_64-linux-gnu).
foreach(f include/dermis/surface/surface_evaluator.h include/dermis/plugins/gltf.h
          include/dermis/dermis.h include/dermis/runtime/runtime.h
          LIB/cmake/dermis/dermisConfig.cmake LIB/cmake/dermis/dermisConfigVersion.cmake
          LIB/pkgconfig/dermis-runtime.pc bin/dermis)
  string(REPLACE "LIB/" "lib/" plain ${f})
  string(REPLACE "LIB/" "lib/*/" multiarch ${f})
  file(GLOB found ${WORK}/prefix/${plain} ${WORK}/prefix/${multiarch})
  if(NOT found)
    message(FATAL_ERROR "the install has no ${plain}")
  endif()
endforeach()

run(${CMAKE_COMMAND} -S ${SOURCE}/tests/consumer -B ${WORK}/build -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_PREFIX_PATH=${WORK}/prefix)
run(${CMAKE_COMMAND} --build ${WORK}/build)
run(${WORK}/build/consumer)
if(NOT run_output MATCHES "consumer ok")
  message(FATAL_ERROR "the consumer did not report success: ${run_output}")
endif()
# dermis::gpu (-DGPU=ON): its headers, the shader as GLSL and SPIR-V, and a consumer of the
# exported target (Vulkan found through the package's config).
if(GPU)
  foreach(f include/dermis/gpu/gpu.h include/dermis/gpu/shader_interface.h
            include/dermis/dermis_gpu.h share/dermis/shaders/evaluate_plan.comp
            share/dermis/shaders/evaluate_plan.spv)
    if(NOT EXISTS ${WORK}/prefix/${f})
      message(FATAL_ERROR "the install has no ${f}")
    endif()
  endforeach()
  if(NOT EXISTS ${WORK}/build/gpu_consumer)
    message(FATAL_ERROR "find_package(dermis) did not provide dermis::gpu")
  endif()
  run(${WORK}/build/gpu_consumer)
  if(NOT run_output MATCHES "gpu consumer ok")
    message(FATAL_ERROR "the GPU consumer did not report success: ${run_output}")
  endif()
  message(STATUS "${run_output}")
endif()

# pkg-config: the runtime alone.
file(GLOB_RECURSE pc_files ${WORK}/prefix/*/dermis-runtime.pc)
list(GET pc_files 0 pc)
get_filename_component(pc_dir ${pc} DIRECTORY)
set(ENV{PKG_CONFIG_PATH} ${pc_dir})
run(pkg-config --cflags --libs dermis-runtime)
string(STRIP "${run_output}" flags)
separate_arguments(flags UNIX_COMMAND "${flags}")
run(${CXX} -std=c++17 ${SOURCE}/tests/consumer/runtime_only.cpp ${flags} -o ${WORK}/runtime_only)
run(${WORK}/runtime_only)
if(NOT run_output MATCHES "runtime-only ok")
  message(FATAL_ERROR "the runtime-only program did not report success: ${run_output}")
endif()

# pkg-config from C: the engine_loop sample (C API) built with the C compiler and nothing but
# pkg-config's flags, run on a surface the installed tool fits; it must need no shared library
# beyond the C and C++ runtimes.
run(${CC} -std=c11 ${SOURCE}/samples/engine_loop/engine_loop.c ${flags} -o ${WORK}/engine_loop)
run(${WORK}/prefix/bin/dermis tessellate --builtin torus -o ${WORK}/torus_dense.obj --level 6 -q)
run(${WORK}/prefix/bin/dermis fit ${WORK}/torus_dense.obj -o ${WORK}/torus.dsurf
    --control-vertices 60 -q)
run(${WORK}/engine_loop ${WORK}/torus.dsurf --frames 3)
if(NOT run_output MATCHES "engine_loop: ok")
  message(FATAL_ERROR "the C engine loop did not report success: ${run_output}")
endif()
run(ldd ${WORK}/engine_loop)
string(REPLACE "\n" ";" libs "${run_output}")
foreach(line ${libs})
  if(line MATCHES "=>" AND NOT line MATCHES "lib(stdc\\+\\+|m|gcc_s|c)\\.so")
    message(FATAL_ERROR "the runtime pulled in a shared library: ${line}")
  endif()
endforeach()
message(STATUS "installed package: find_package and pkg-config consumers (C++ and C) built and ran")
