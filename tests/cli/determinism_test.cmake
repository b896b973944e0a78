# Every command's output is the same bytes across runs and thread counts (issue 19, item 6):
# fit (surface and character), export (bound, lod, baked), tessellate and render. Commands with
# --threads run with --threads 1 and --threads 2; tessellate and render (which split work over
# all cores) run twice. Inputs are small: a built-in torus, and RiggedSimple.glb from
# ../shared/data when it is present (the character steps are skipped with a note otherwise).
# Invoked by ctest with -DDERMIS=<dermis> -DWORK=<scratch dir> -DDATA=<../shared/data>.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

function(run)
  execute_process(COMMAND ${DERMIS} ${ARGN} -q RESULT_VARIABLE code OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "`dermis ${ARGN}` exited ${code}\n${out}\n${err}")
  endif()
endfunction()

function(same what a b)
  file(SHA256 ${a} ha)
  file(SHA256 ${b} hb)
  if(NOT ha STREQUAL hb)
    message(FATAL_ERROR "${what}: ${a} and ${b} differ")
  endif()
  message(STATUS "same bytes: ${what}")
endfunction()

# A dense torus, twice.
run(tessellate --builtin torus --level 4 -o ${WORK}/dense1.obj)
run(tessellate --builtin torus --level 4 -o ${WORK}/dense2.obj)
same("tessellate --builtin" ${WORK}/dense1.obj ${WORK}/dense2.obj)
# Surface fit on one and two threads.
foreach(t 1 2)
  run(fit ${WORK}/dense1.obj -o ${WORK}/torus_t${t}.dsurf --control-vertices 60 --threads ${t})
endforeach()
same("fit (surface), --threads 1 vs 2" ${WORK}/torus_t1.dsurf ${WORK}/torus_t2.dsurf)
# Tessellation and a picture of the fitted surface, twice.
foreach(i 1 2)
  run(tessellate ${WORK}/torus_t1.dsurf --level 3 -o ${WORK}/torus_tess${i}.obj)
  run(render ${WORK}/torus_t1.dsurf --size 96x96 -o ${WORK}/torus${i}.png)
endforeach()
same("tessellate .dsurf" ${WORK}/torus_tess1.obj ${WORK}/torus_tess2.obj)
same("render" ${WORK}/torus1.png ${WORK}/torus2.png)

set(rigged ${DATA}/gltf/RiggedSimple.glb)
if(NOT EXISTS ${rigged})
  message(STATUS "SKIPPED the character steps: ${rigged} is absent")
  return()
endif()
foreach(t 1 2)
  run(fit ${rigged} -o ${WORK}/rigged_t${t}.dsurf --threads ${t})
endforeach()
same("fit (character), --threads 1 vs 2" ${WORK}/rigged_t1.dsurf ${WORK}/rigged_t2.dsurf)
set(ch ${WORK}/rigged_t1.dsurf)
foreach(i 1 2)
  run(export ${ch} -o ${WORK}/bound${i}.glb)
  run(export ${ch} -o ${WORK}/lod${i}.glb --mode lod --level 2)
  run(render ${ch} --size 96x96 -o ${WORK}/rigged${i}.png)
  run(export ${ch} -o ${WORK}/baked${i}.glb --bake-sweep --fps 10 --mode lod --level 1 --threads ${i})
endforeach()
same("export bound" ${WORK}/bound1.glb ${WORK}/bound2.glb)
same("export lod" ${WORK}/lod1.glb ${WORK}/lod2.glb)
same("render character" ${WORK}/rigged1.png ${WORK}/rigged2.png)
same("export --bake-sweep, --threads 1 vs 2" ${WORK}/baked1.glb ${WORK}/baked2.glb)
