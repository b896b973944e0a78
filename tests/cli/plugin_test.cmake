# Issue 17: an engine plugin from the installed package. Installs the build into a scratch
# prefix, checks the shared C library (SONAME, exports nothing but dermis_*), then builds
# tests/consumer/plugin twice -- against the static runtime and against libdermis_runtime.so --
# with every offline package hidden from find_package, and runs each plugin through a host
# that dlopens it and evaluates frames of the fitted test character.
# Invoked by ctest with -DBUILD=<build dir> -DSOURCE=<repository root> -DWORK=<scratch dir>
# -DCHARACTER=<a skinned .dsurf> -DCC=<C compiler> -DCXX=<C++ compiler>.
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
file(GLOB_RECURSE so_files ${WORK}/prefix/*/libdermis_runtime.so.*.*.*)
if(NOT so_files)
  message(FATAL_ERROR "the install has no libdermis_runtime.so.MAJOR.MINOR.PATCH")
endif()
list(GET so_files 0 so)
run(objdump -p ${so})
if(NOT run_output MATCHES "SONAME +libdermis_runtime\\.so\\.[0-9]+\\.[0-9]+\n")
  message(FATAL_ERROR "libdermis_runtime.so has no SONAME libdermis_runtime.so.MAJOR.MINOR:\n"
                      "${run_output}")
endif()
run(nm -D --defined-only ${so})
string(REPLACE "\n" ";" symbols "${run_output}")
set(exports 0)
foreach(line ${symbols})
  if(line MATCHES " [TDBRVW] ([^ ]+)$")
    set(name ${CMAKE_MATCH_1})
    if(NOT name MATCHES "^dermis_")
      message(FATAL_ERROR "libdermis_runtime.so exports ${name}: only dermis_* may be exported")
    endif()
    math(EXPR exports "${exports} + 1")
  endif()
endforeach()
if(exports LESS 30)
  message(FATAL_ERROR "libdermis_runtime.so exports ${exports} functions, expected the C API")
endif()

# The offline packages hidden: the runtime component must not look for them.
set(hidden -DCMAKE_DISABLE_FIND_PACKAGE_Eigen3=ON -DCMAKE_DISABLE_FIND_PACKAGE_meshoptimizer=ON
           -DCMAKE_DISABLE_FIND_PACKAGE_TinyGLTF=ON -DCMAKE_DISABLE_FIND_PACKAGE_assimp=ON
           -DCMAKE_DISABLE_FIND_PACKAGE_Vulkan=ON -DCMAKE_DISABLE_FIND_PACKAGE_lemon=ON)
foreach(flavour static shared)
  set(dir ${WORK}/plugin_${flavour})
  run(${CMAKE_COMMAND} -S ${SOURCE}/tests/consumer/plugin -B ${dir} -DCMAKE_BUILD_TYPE=Release
      -DCMAKE_C_COMPILER=${CC} -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_PREFIX_PATH=${WORK}/prefix
      -DDERMIS_PLUGIN_RUNTIME=${flavour} ${hidden})
  run(${CMAKE_COMMAND} --build ${dir})
  run(ldd ${dir}/libengine_plugin.so)
  if(flavour STREQUAL "shared" AND NOT run_output MATCHES "libdermis_runtime\\.so")
    message(FATAL_ERROR "the shared-runtime plugin does not load libdermis_runtime.so")
  endif()
  if(flavour STREQUAL "static" AND run_output MATCHES "libdermis")
    message(FATAL_ERROR "the static-runtime plugin loads a Dermis library:\n${run_output}")
  endif()
  run(${dir}/plugin_host ${dir}/libengine_plugin.so ${CHARACTER} 4)
  if(NOT run_output MATCHES "plugin ok")
    message(FATAL_ERROR "the ${flavour}-runtime plugin did not report success: ${run_output}")
  endif()
  message(STATUS "${flavour} runtime: ${run_output}")
endforeach()
