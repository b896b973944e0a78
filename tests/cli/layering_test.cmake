cmake_policy(SET CMP0057 NEW)
# Fails if runtime or core code includes offline headers, Eigen, or any plugin, or uses
# exceptions. The surface, deform and core modules do not see the asset module either; the
# runtime module (loading characters, jobs, C API) does: it is core + GLM only too. The GPU
# module (dermis::gpu) follows the runtime's rules, with the Vulkan headers besides.
file(GLOB_RECURSE files
     ${ROOT}/sdk/include/dermis/core/*.h ${ROOT}/sdk/include/dermis/surface/*.h
     ${ROOT}/sdk/include/dermis/deform/*.h ${ROOT}/sdk/src/core/*.cpp
     ${ROOT}/sdk/src/surface/*.cpp ${ROOT}/sdk/src/deform/*.cpp ${ROOT}/sdk/src/deform/*.h
     ${ROOT}/sdk/src/core/*.h)
file(GLOB_RECURSE runtime_files ${ROOT}/sdk/include/dermis/runtime/*.h
     ${ROOT}/sdk/include/dermis/dermis.h ${ROOT}/sdk/src/runtime/*.cpp ${ROOT}/sdk/src/runtime/*.h
     ${ROOT}/sdk/include/dermis/dsurf/*.h ${ROOT}/sdk/src/dsurf/*.cpp ${ROOT}/sdk/src/dsurf/*.h
     ${ROOT}/sdk/include/dermis/gpu/*.h ${ROOT}/sdk/include/dermis/dermis_gpu.h
     ${ROOT}/sdk/src/gpu/*.cpp ${ROOT}/sdk/src/gpu/*.h)
foreach(f ${files} ${runtime_files})
  file(STRINGS ${f} includes REGEX "^#include")
  foreach(line ${includes})
    if(line MATCHES "dermis/offline|Eigen|plugins|tiny_gltf|assimp")
      message(FATAL_ERROR "${f}: runtime code must not use '${line}'")
    endif()
    if(line MATCHES "dermis/asset" AND NOT f IN_LIST runtime_files)
      message(FATAL_ERROR "${f}: only the runtime module may use the asset module: '${line}'")
    endif()
  endforeach()
  file(STRINGS ${f} exceptions REGEX "(^|[^a-z_])(throw|try|catch)[ ({]")
  if(exceptions)
    message(FATAL_ERROR "${f}: runtime code must not use exceptions: ${exceptions}")
  endif()
endforeach()
list(APPEND files ${runtime_files})
list(LENGTH files n)
message(STATUS "checked ${n} runtime files")

# The asset module sees core only; plugins see only the asset module and core.
file(GLOB_RECURSE asset_files ${ROOT}/sdk/include/dermis/asset/*.h ${ROOT}/sdk/src/asset/*.cpp)
file(GLOB_RECURSE plugin_files ${ROOT}/plugins/*.h ${ROOT}/plugins/*.cpp)
foreach(f ${asset_files} ${plugin_files})
  file(STRINGS ${f} includes REGEX "^#include \"dermis/")
  foreach(line ${includes})
    if(NOT line MATCHES "dermis/(core|asset|plugins)/")
      message(FATAL_ERROR "${f}: asset and plugin code may use only dermis/core and dermis/asset: '${line}'")
    endif()
    if(f MATCHES "/sdk/" AND line MATCHES "dermis/plugins/")
      message(FATAL_ERROR "${f}: the asset module must not use plugins: '${line}'")
    endif()
  endforeach()
endforeach()

# Tests include only what their binary links (tests/CMakeLists.txt): the tests of a runtime-side
# module see that module, what it is built on, and the offline stage that builds their fixtures,
# through the test support of that stage. A test that needs more must say so here and there.
set(test_rules
  "core|dermis/core/|support/(meshes|random|temp_files)\\.h"
  "deform|dermis/(core|deform)/"
  "asset|dermis/(core|asset)/"
  "surface|dermis/(core|surface)/|dermis/offline/(geometry|build|io)/|support/(domains|meshes|random|wavy_displacement)\\.h"
  "dsurf|dermis/(core|surface|dsurf|runtime|asset)/|support/(fixtures|temp_files)\\.h"
  "runtime|dermis/(core|surface|dsurf|runtime|deform|asset)/|dermis/dermis\\.h|support/(fixtures|random|runtime_frames|wavy_displacement)\\.h")
foreach(rule ${test_rules})
  string(FIND "${rule}" "|" bar)
  string(SUBSTRING "${rule}" 0 ${bar} folder)
  math(EXPR start "${bar} + 1")
  string(SUBSTRING "${rule}" ${start} -1 allowed)
  file(GLOB test_files ${ROOT}/tests/${folder}/*.cpp)
  foreach(f ${test_files})
    file(STRINGS ${f} includes REGEX "^#include \"")
    foreach(line ${includes})
      string(REGEX REPLACE "^#include \"([^\"]+)\".*" "\\1" header "${line}")
      if(NOT header MATCHES "^(${allowed})")
        message(FATAL_ERROR "${f}: the ${folder} tests may include only ${allowed}: '${header}'")
      endif()
    endforeach()
  endforeach()
endforeach()
message(STATUS "checked the includes of the runtime-side tests")
