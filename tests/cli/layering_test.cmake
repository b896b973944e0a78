# Fails if runtime or core code includes offline headers, Eigen, or any plugin.
file(GLOB_RECURSE files
     ${ROOT}/sdk/include/dermis/core/*.h ${ROOT}/sdk/include/dermis/surface/*.h
     ${ROOT}/sdk/include/dermis/deform/*.h ${ROOT}/sdk/src/core/*.cpp
     ${ROOT}/sdk/src/surface/*.cpp ${ROOT}/sdk/src/deform/*.cpp ${ROOT}/sdk/src/deform/*.h)
foreach(f ${files})
  file(STRINGS ${f} includes REGEX "^#include")
  foreach(line ${includes})
    if(line MATCHES "dermis/offline|dermis/asset|Eigen|plugins|tiny_gltf|assimp")
      message(FATAL_ERROR "${f}: runtime code must not use '${line}'")
    endif()
  endforeach()
endforeach()
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
