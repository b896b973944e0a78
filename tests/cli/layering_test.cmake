# Fails if runtime or core code includes offline headers, Eigen, or any plugin.
file(GLOB_RECURSE files
     ${ROOT}/sdk/include/dermis/core/*.h ${ROOT}/sdk/include/dermis/surface/*.h
     ${ROOT}/sdk/src/core/*.cpp ${ROOT}/sdk/src/surface/*.cpp)
foreach(f ${files})
  file(STRINGS ${f} includes REGEX "^#include")
  foreach(line ${includes})
    if(line MATCHES "dermis/offline|Eigen|plugins|tiny_gltf|assimp")
      message(FATAL_ERROR "${f}: runtime code must not use '${line}'")
    endif()
  endforeach()
endforeach()
list(LENGTH files n)
message(STATUS "checked ${n} runtime files")
