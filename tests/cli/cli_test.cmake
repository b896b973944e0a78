# End-to-end checks of `dermis tessellate`, `fit`, `export`, `animate` and `inspect`: success, exit codes, messages, no partial output.
# Invoked by ctest with -DDERMIS=<path to dermis> -DWORK=<scratch dir>.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

function(expect_run expected_code expected_text)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL expected_code)
    message(FATAL_ERROR "`${ARGN}` exited ${code}, expected ${expected_code}\n${out}\n${err}")
  endif()
  if(NOT "${expected_text}" STREQUAL "")
    string(REGEX MATCH "${expected_text}" found "${out}${err}")
    if(found STREQUAL "")
      message(FATAL_ERROR "`${ARGN}` did not print '${expected_text}':\n${out}\n${err}")
    endif()
  endif()
endfunction()

# Success on a built-in mesh and on an OBJ file.
expect_run(0 "wrote" ${DERMIS} tessellate --builtin house -o ${WORK}/house.obj --level 4)
file(STRINGS ${WORK}/house.obj vn_lines REGEX "^vn ")
list(LENGTH vn_lines n)
if(n EQUAL 0)
  message(FATAL_ERROR "house.obj has no vn lines")
endif()
file(WRITE ${WORK}/quad.obj "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
expect_run(0 "" ${DERMIS} tessellate ${WORK}/quad.obj -o ${WORK}/sub/quad_out.obj --level 2 -q)
file(STRINGS ${WORK}/sub/quad_out.obj v_lines REGEX "^v ")
list(LENGTH v_lines n)
if(NOT n EQUAL 9)
  message(FATAL_ERROR "a single quad at level 2 must give 9 vertices, got ${n}")
endif()

# Bad inputs: exit 1, the file and line named, no output written.
set(header "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n")
file(WRITE ${WORK}/range.obj "${header}f 1 2 3 9\n")
file(WRITE ${WORK}/repeat.obj "${header}f 1 2 2 3\n")
file(WRITE ${WORK}/nan.obj "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
file(WRITE ${WORK}/inf.obj "v 0 0 0\nv 1 0 -inf\nv 0 1 0\nf 1 2 3\n")
file(WRITE ${WORK}/nonmanifold.obj
     "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n")
file(WRITE ${WORK}/empty.obj "")
foreach(case range:5 repeat:5 nan:1 inf:2 nonmanifold:8)
  string(REPLACE ":" ";" parts ${case})
  list(GET parts 0 name)
  list(GET parts 1 line)
  expect_run(1 "${name}\\.obj:(${line}:|.*line ${line}\\))" ${DERMIS} tessellate ${WORK}/${name}.obj -o ${WORK}/${name}_out.obj)
  if(EXISTS ${WORK}/${name}_out.obj)
    message(FATAL_ERROR "${name}: an output file was written for bad input")
  endif()
endforeach()
expect_run(1 "empty.obj: no vertices" ${DERMIS} tessellate ${WORK}/empty.obj -o ${WORK}/empty_out.obj)
expect_run(1 "missing.obj" ${DERMIS} tessellate ${WORK}/missing.obj -o ${WORK}/missing_out.obj)
expect_run(1 "directory" ${DERMIS} tessellate ${WORK} -o ${WORK}/dir_out.obj)
file(GLOB leftovers ${WORK}/*_out.obj ${WORK}/*.tmp.*)
if(leftovers)
  message(FATAL_ERROR "files left behind by failed runs: ${leftovers}")
endif()

# Existing outputs are never overwritten without --force (exit 2, the file untouched).
file(WRITE ${WORK}/existing.obj "old")
expect_run(2 "existing\\.obj exists; pass --force" ${DERMIS} tessellate --builtin cube
           -o ${WORK}/existing.obj)
file(READ ${WORK}/existing.obj kept)
if(NOT kept STREQUAL "old")
  message(FATAL_ERROR "tessellate overwrote a file without --force")
endif()
expect_run(0 "" ${DERMIS} tessellate --builtin cube -o ${WORK}/existing.obj --force -q)

# Usage errors: exit 2 with a hint.
expect_run(2 "\\-\\-help' for usage" ${DERMIS} tessellate ${WORK}/quad.obj)
expect_run(2 "\\-\\-help' for usage" ${DERMIS} tessellate ${WORK}/quad.obj -o ${WORK}/x.obj --level 0)
expect_run(2 "\\-\\-help' for usage" ${DERMIS} tessellate -o ${WORK}/x.obj)
expect_run(2 "" ${DERMIS} frobnicate)
expect_run(0 "dermis [0-9]" ${DERMIS} --version)
expect_run(0 "tessellate" ${DERMIS} tessellate --help)

# dermis fit: a dense mesh made by the tool itself, then its .dsurf tessellated back.
expect_run(0 "" ${DERMIS} tessellate --builtin torus -o ${WORK}/dense_torus.obj --level 6 -q)
expect_run(0 "wrote" ${DERMIS} fit ${WORK}/dense_torus.obj -o ${WORK}/fit/torus.dsurf
           --control-vertices 150 --threads 2 --report ${WORK}/fit/report.json)
file(READ ${WORK}/fit/report.json report)
foreach(key points points_dropped control_vertices control_faces coefficients mean rms max
        points_not_converged points_not_converged_placed boundary_points_beyond
        boundary_largest_excess boundary_vertices_moved no-cover-boundary
        unoptimized_mean holdout_mean holdout_max hausdorff_percent_diagonal control_mesh
        projection_optimization displacement total)
  string(FIND "${report}" "\"${key}\"" at)
  if(at LESS 0)
    message(FATAL_ERROR "report.json has no \"${key}\":\n${report}")
  endif()
endforeach()
# `dermis fit --help` states the defaults a fit without options runs with, for a surface and
# for a character alike: the report's "options" are the values the fit used (after the
# library's defaults for the input kind), the help reads them from the option structs.
execute_process(COMMAND ${DERMIS} fit --help OUTPUT_VARIABLE fit_help)
string(REGEX REPLACE "[ \t\r\n]+" " " fit_help "${fit_help}")
function(expect_help_defaults report_text kind)
  foreach(opt node-weight level-smoothing validation min-improvement residual-threshold
              coefficients-per-point consistency density smoothing control-fit)
    string(REGEX MATCH "\"${opt}\": ([-0-9.e+]+)" m "${report_text}")
    if(m STREQUAL "")
      message(FATAL_ERROR "the ${kind} report has no option ${opt}")
    endif()
    string(REGEX REPLACE "\\.0$" "" used "${CMAKE_MATCH_1}")
    string(FIND "${fit_help}" "--${opt} " at)
    if(at LESS 0)
      message(FATAL_ERROR "dermis fit --help has no --${opt}")
    endif()
    # The option's own help: up to the next option's line (" --name TYPE" or " --name " at
    # the start of an entry; an option named inside a help text is followed by other words).
    string(SUBSTRING "${fit_help}" ${at} -1 rest)
    string(SUBSTRING "${rest}" 2 -1 after)
    string(REGEX MATCH " -(-[a-z-]+ [A-Z]|h,|f,|q,)" next "${after}")
    if(NOT next STREQUAL "")
      string(FIND "${after}" "${next}" end)
      math(EXPR end "${end} + 2")
      string(SUBSTRING "${rest}" 0 ${end} rest)
    endif()
    string(REGEX MATCH "default ([^ ,;)]+)( for a surface, ([^ ,;)]+) for a character)?" m
           "${rest}")
    if(m STREQUAL "")
      message(FATAL_ERROR "dermis fit --help states no default for --${opt}: ${rest}")
    endif()
    set(stated "${CMAKE_MATCH_1}")
    if(kind STREQUAL "character" AND NOT "${CMAKE_MATCH_3}" STREQUAL "")
      set(stated "${CMAKE_MATCH_3}")
    endif()
    if(NOT stated STREQUAL used)
      message(FATAL_ERROR "dermis fit --help says --${opt} defaults to '${stated}' for a "
                          "${kind}; a fit used ${used}")
    endif()
  endforeach()
endfunction()
expect_help_defaults("${report}" surface)
expect_run(0 "displacement levels 2 of" ${DERMIS} tessellate ${WORK}/fit/torus.dsurf
           -o ${WORK}/fit/torus_l2.obj --level 4 --displacement-levels 2)
expect_run(0 "" ${DERMIS} tessellate ${WORK}/fit/torus.dsurf -o ${WORK}/fit/torus.obj -q)
# A .dsurf carries its charts and blending: options that would set them are refused.
expect_run(2 "--chart, --blend-lb: .*torus\\.dsurf carries its own" ${DERMIS} tessellate
           ${WORK}/fit/torus.dsurf -o ${WORK}/fit/torus_chart.obj --chart complex --blend-lb 0.1)
# ... and a control mesh has no displacement levels.
expect_run(2 "--displacement-levels applies to a fitted surface" ${DERMIS} tessellate
           --builtin cube -o ${WORK}/fit/torus_chart.obj --displacement-levels 2)
if(EXISTS ${WORK}/fit/torus_chart.obj)
  message(FATAL_ERROR "a refused tessellate wrote torus_chart.obj")
endif()
# Bad fit inputs: exit 1, a message naming the file, nothing written.
# An option only the other kind of input takes is refused (usage, nothing written), not ignored.
expect_run(2 "--refit applies to a character.*dense_torus\\.obj is a surface" ${DERMIS} fit
           ${WORK}/dense_torus.obj -o ${WORK}/bad_refit.dsurf --refit)
if(EXISTS ${WORK}/bad_refit.dsurf)
  message(FATAL_ERROR "a refused fit wrote bad_refit.dsurf")
endif()
expect_run(2 "--input-quads applies to a character" ${DERMIS} fit ${WORK}/dense_torus.obj
           -o ${WORK}/bad_refit.dsurf --input-quads 1.5)
expect_run(2 "--input-quads: must be 0 or in \\[1, 1e6\\]" ${DERMIS} fit ${WORK}/dense_torus.obj
           -o ${WORK}/bad_refit.dsurf --input-quads 0.5)
expect_run(2 "--creases-closed applies to a character" ${DERMIS} fit ${WORK}/dense_torus.obj
           -o ${WORK}/bad_refit.dsurf --creases-closed)
expect_run(2 "--low-poly-crease-angle applies to a character" ${DERMIS} fit
           ${WORK}/dense_torus.obj -o ${WORK}/bad_refit.dsurf --low-poly-crease-angle 0.2)
expect_run(2 "--surface-gap applies to a character" ${DERMIS} fit ${WORK}/dense_torus.obj
           -o ${WORK}/bad_refit.dsurf --surface-gap 0.001)
expect_run(2 "--surface-gap: Value 1.5 not in range" ${DERMIS} fit ${WORK}/dense_torus.obj
           -o ${WORK}/bad_refit.dsurf --surface-gap 1.5)
expect_run(2 "--check-points applies to a character" ${DERMIS} fit ${WORK}/dense_torus.obj
           -o ${WORK}/bad_refit.dsurf --check-points 2)
expect_run(2 "--check-points: Value 65 not in range" ${DERMIS} fit ${WORK}/dense_torus.obj
           -o ${WORK}/bad_refit.dsurf --check-points 65)
expect_run(2 "--no-check-shading applies to a character" ${DERMIS} fit ${WORK}/dense_torus.obj
           -o ${WORK}/bad_refit.dsurf --no-check-shading)
expect_run(2 "--skin-smoothing applies to a character" ${DERMIS} fit ${WORK}/dense_torus.obj
           -o ${WORK}/bad_refit.dsurf --skin-smoothing 1)
expect_run(2 "--skin-smoothing: Value 65 not in range" ${DERMIS} fit ${WORK}/dense_torus.obj
           -o ${WORK}/bad_refit.dsurf --skin-smoothing 65)
# --shading-shape: 'auto' (the default) or a factor in [0, 1]; anything else is a usage error.
string(FIND "${fit_help}" "--shading-shape TEXT=auto " at)
if(at LESS 0)
  message(FATAL_ERROR "dermis fit --help does not give --shading-shape's default as auto")
endif()
foreach(bad 1.5 -0.5 round 0.5x)
  expect_run(2 "--shading-shape: 'auto' or a number in \\[0, 1\\], not '${bad}'" ${DERMIS} fit
             ${WORK}/dense_torus.obj -o ${WORK}/bad_refit.dsurf --shading-shape=${bad})
endforeach()
# --refit=false asks for nothing a surface lacks (the input is missing: exit 1, not 2).
expect_run(1 "missing\\.obj" ${DERMIS} fit ${WORK}/missing.obj -o ${WORK}/bad_refit.dsurf
           --refit=false)
# A given control mesh is used as is: the automatic mesh's options are refused with it.
expect_run(2 "--control-vertices and --control-fit apply to the automatic control mesh" ${DERMIS}
           fit ${WORK}/dense_torus.obj -o ${WORK}/bad_refit.dsurf --control-mesh ${WORK}/quad.obj
           --control-vertices 50 --control-fit 1)
expect_run(2 "--no-cover-boundary applies to the automatic control mesh" ${DERMIS} fit
           ${WORK}/dense_torus.obj -o ${WORK}/bad_refit.dsurf --control-mesh ${WORK}/quad.obj
           --no-cover-boundary)
# On a character (the refusal comes before the file is read, so a missing one will do).
expect_run(2 "--control-vertices and --holdout apply to a surface.*x\\.gltf is read as a character"
           ${DERMIS} fit ${WORK}/x.gltf -o ${WORK}/bad_refit.dsurf --control-vertices 50
           --holdout 0.2)
expect_run(2 "--control-mesh applies to a surface" ${DERMIS} fit ${WORK}/x.glb
           -o ${WORK}/bad_refit.dsurf --control-mesh ${WORK}/quad.obj)
if(EXISTS ${WORK}/bad_refit.dsurf)
  message(FATAL_ERROR "a refused fit wrote bad_refit.dsurf")
endif()
expect_run(1 "missing.obj" ${DERMIS} fit ${WORK}/missing.obj -o ${WORK}/bad1.dsurf)
file(WRITE ${WORK}/empty.obj "# nothing\n")
expect_run(1 "empty.obj" ${DERMIS} fit ${WORK}/empty.obj -o ${WORK}/bad2.dsurf)
file(WRITE ${WORK}/cloud.obj "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n")
expect_run(1 "control-mesh" ${DERMIS} fit ${WORK}/cloud.obj -o ${WORK}/bad3.dsurf)
expect_run(1 "control-vertices" ${DERMIS} fit ${WORK}/dense_torus.obj -o ${WORK}/bad4.dsurf
           --control-vertices 1000000)
file(WRITE ${WORK}/bad.dsurf "DSURF but not really")
expect_run(1 "bad.dsurf" ${DERMIS} tessellate ${WORK}/bad.dsurf -o ${WORK}/bad5.obj)
foreach(f bad1.dsurf bad2.dsurf bad3.dsurf bad4.dsurf bad5.obj)
  if(EXISTS ${WORK}/${f})
    message(FATAL_ERROR "a failed command left ${f} behind")
  endif()
endforeach()
expect_run(2 "" ${DERMIS} fit ${WORK}/dense_torus.obj)

# Characters: dermis fit / export / inspect on a shared Khronos asset (skipped without
# ../shared/data), the lossless round trip through --embed, and bad inputs.
file(WRITE ${WORK}/garbage.glb "glTF this is not")
file(WRITE ${WORK}/garbage.gltf "{ \"asset\": { \"version\": \"2.0\" }, \"meshes\": [ }")
expect_run(1 "garbage\\.glb" ${DERMIS} fit ${WORK}/garbage.glb -o ${WORK}/ch/garbage.dsurf)
expect_run(1 "garbage\\.gltf" ${DERMIS} fit ${WORK}/garbage.gltf -o ${WORK}/ch/garbage2.dsurf)
expect_run(1 "garbage\\.glb" ${DERMIS} inspect ${WORK}/garbage.glb)
expect_run(1 "missing\\.glb" ${DERMIS} inspect ${WORK}/missing.glb)
expect_run(1 "bad\\.dsurf" ${DERMIS} export ${WORK}/bad.dsurf -o ${WORK}/ch/bad.glb)
expect_run(2 "\\.glb or \\.gltf" ${DERMIS} export ${WORK}/bad.dsurf -o ${WORK}/ch/bad.obj)
expect_run(2 "" ${DERMIS} export ${WORK}/bad.dsurf -o ${WORK}/ch/bad.glb --mode sideways)
foreach(f garbage.dsurf garbage2.dsurf bad.glb bad.obj)
  if(EXISTS ${WORK}/ch/${f})
    message(FATAL_ERROR "a failed command left ch/${f} behind")
  endif()
endforeach()

# dermis render: PNG pictures of a surface (with an error map against its data) and of the
# character's clip as a contact sheet; no overwrite without --force; bad input exits 1.
function(expect_png path min_bytes)
  if(NOT EXISTS ${path})
    message(FATAL_ERROR "${path} was not written")
  endif()
  file(READ ${path} head LIMIT 8 HEX)
  if(NOT head STREQUAL "89504e470d0a1a0a")
    message(FATAL_ERROR "${path} is not a PNG (starts ${head})")
  endif()
  file(SIZE ${path} size)
  if(size LESS ${min_bytes})
    message(FATAL_ERROR "${path} is only ${size} bytes")
  endif()
endfunction()
expect_run(0 "1 view, 200x160" ${DERMIS} render ${WORK}/fit/torus.dsurf -o ${WORK}/pic/torus.png
           --size 200x160)
expect_png(${WORK}/pic/torus.png 2000)
expect_run(0 "error map 0\\.\\." ${DERMIS} render ${WORK}/fit/torus.dsurf -o ${WORK}/pic/err.png
           --size 200x160 --heatmap error --reference ${WORK}/dense_torus.obj)
expect_png(${WORK}/pic/err.png 2000)
expect_run(0 "displacement levels 0: distance to data mean" ${DERMIS} render
           ${WORK}/fit/torus.dsurf -o ${WORK}/pic/series.png --size 96x96 --series 0,1,-1
           --heatmap error --reference ${WORK}/dense_torus.obj)
expect_png(${WORK}/pic/series.png 2000)
expect_run(2 "--series" ${DERMIS} render ${WORK}/fit/torus.dsurf -o ${WORK}/pic/x.png
           --series 0,two)
# --series takes the levels --displacement-levels takes (-1..13).
expect_run(2 "levels -1\\.\\.13" ${DERMIS} render ${WORK}/fit/torus.dsurf -o ${WORK}/pic/x.png
           --series 0,14)
expect_run(0 "" ${DERMIS} render ${WORK}/fit/torus.dsurf -o ${WORK}/pic/turn.png
           --size 100x100 --turntable 4 --frame-files -q)
expect_png(${WORK}/pic/turn.png 2000)
expect_png(${WORK}/pic/turn_003.png 500)
file(SHA256 ${WORK}/pic/torus.png before)
expect_run(2 "exists; pass --force" ${DERMIS} render ${WORK}/fit/torus.dsurf -o ${WORK}/pic/torus.png)
file(SHA256 ${WORK}/pic/torus.png after)
if(NOT before STREQUAL after)
  message(FATAL_ERROR "render overwrote a file without --force")
endif()
expect_run(0 "" ${DERMIS} render ${WORK}/fit/torus.dsurf -o ${WORK}/pic/torus.png --force -q
           --size 64x64)
# --wireframe draws the control edges, `level` segments each: a closed all-quad mesh has twice
# as many edges as vertices (Euler: V - E + F = 0 with 4F = 2E), so the torus's count comes from
# the fit report's control vertices, independently of the drawing; the picture differs from the
# plain one of the same view.
string(JSON torus_cv GET "${report}" control_vertices)
math(EXPR torus_segments "2 * ${torus_cv} * 3")
execute_process(COMMAND ${DERMIS} render ${WORK}/fit/torus.dsurf -o ${WORK}/pic/wire.png
                --size 200x160 --level 3 --wireframe RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 0 OR NOT err MATCHES
   "wireframe: ${torus_segments} segments drawn, ${torus_segments} on the control edges")
  message(FATAL_ERROR "--wireframe on the torus (${torus_cv} control vertices) must draw "
                      "${torus_segments} segments (exit ${code}):\n${err}")
endif()
expect_png(${WORK}/pic/wire.png 2000)
expect_run(0 "" ${DERMIS} render ${WORK}/fit/torus.dsurf -o ${WORK}/pic/plain3.png
           --size 200x160 --level 3 -q)
file(SHA256 ${WORK}/pic/wire.png wire_sha)
file(SHA256 ${WORK}/pic/plain3.png plain_sha)
if(wire_sha STREQUAL plain_sha)
  message(FATAL_ERROR "--wireframe drew nothing over the torus")
endif()
expect_run(2 "--wireframe needs --level 2" ${DERMIS} render ${WORK}/fit/torus.dsurf
           -o ${WORK}/pic/x.png --level 1 --wireframe)
expect_run(2 "needs --reference" ${DERMIS} render ${WORK}/fit/torus.dsurf -o ${WORK}/pic/x.png
           --heatmap error)
expect_run(2 "\\.png" ${DERMIS} render ${WORK}/fit/torus.dsurf -o ${WORK}/pic/x.jpg)
expect_run(2 "WxH" ${DERMIS} render ${WORK}/fit/torus.dsurf -o ${WORK}/pic/x.png --size 12)
expect_run(2 "skeleton" ${DERMIS} render ${WORK}/fit/torus.dsurf -o ${WORK}/pic/x.png --frames 3)
expect_run(1 "missing\\.dsurf" ${DERMIS} render ${WORK}/missing.dsurf -o ${WORK}/pic/x.png)
expect_run(1 "bad\\.dsurf" ${DERMIS} render ${WORK}/bad.dsurf -o ${WORK}/pic/x.png)
expect_run(1 "dense_torus\\.obj: not a \\.dsurf" ${DERMIS} render ${WORK}/dense_torus.obj
           -o ${WORK}/pic/x.png)
if(EXISTS ${WORK}/pic/x.png OR EXISTS ${WORK}/pic/x.jpg)
  message(FATAL_ERROR "a failed render left a picture behind")
endif()

# dermis validate: .dsurf and glTF files; bad or missing files exit 1.
expect_run(0 "torus\\.dsurf: valid" ${DERMIS} validate ${WORK}/fit/torus.dsurf)
expect_run(0 "\"valid\": true" ${DERMIS} validate ${WORK}/fit/torus.dsurf --json)
expect_run(1 "bad\\.dsurf" ${DERMIS} validate ${WORK}/bad.dsurf)
file(WRITE ${WORK}/garbage_v.glb "glTF but not really")
expect_run(1 "INVALID" ${DERMIS} validate ${WORK}/garbage_v.glb)
expect_run(1 "missing\\.glb" ${DERMIS} validate ${WORK}/missing.glb)
expect_run(2 "" ${DERMIS} validate)

set(skin ${DATA}/gltf/SimpleSkin.gltf)
if(NOT EXISTS ${skin})
  message(STATUS "skipped the character part: ${skin} is absent (../shared/data)")
  return()
endif()
set(ch ${WORK}/ch)
expect_run(0 "wrote" ${DERMIS} fit ${skin} -o ${ch}/skin.dsurf --threads 2 --report ${ch}/skin.json)
file(READ ${ch}/skin.json report)
foreach(key parts_fitted parts_unfitted vertices_bound e1_mean e1_max unfitted)
  string(FIND "${report}" "\"${key}\"" at)
  if(at LESS 0)
    message(FATAL_ERROR "skin.json has no \"${key}\":\n${report}")
  endif()
endforeach()
expect_help_defaults("${report}" character)
# The shading surface: chosen per part by default, and the report says which.
foreach(key "\"shading-shape\": \"auto\"" "\"shading_shape\": " "\"shading_normal_deviation_deg\": "
            "\"flat_normal_deviation_deg\": " "\"low-poly-crease-angle\": 0.1" "\"crease_angle_deg\": "
            "\"check-points\": 1" "\"no-check-shading\": false" "\"skin-smoothing\": 2")
  string(FIND "${report}" "${key}" at)
  if(at LESS 0)
    message(FATAL_ERROR "skin.json has no ${key}:\n${report}")
  endif()
endforeach()
# A character's report leaves out the options a character fit does not take (refused on a
# character, above) and keeps the control-vertex fit's, which --control-fit can turn on.
foreach(key control-vertices holdout)
  string(FIND "${report}" "\"${key}\"" at)
  if(NOT at LESS 0)
    message(FATAL_ERROR "skin.json lists the surface option ${key}:\n${report}")
  endif()
endforeach()
string(FIND "${report}" "\"patch-agreement\"" at)
if(at LESS 0)
  message(FATAL_ERROR "skin.json does not list patch-agreement:\n${report}")
endif()
expect_run(0 "parts +1 fitted, 0 unfitted" ${DERMIS} inspect ${ch}/skin.dsurf)
expect_run(0 "\"character\"" ${DERMIS} inspect ${ch}/skin.dsurf --json)
expect_run(0 "bound mode" ${DERMIS} export ${ch}/skin.dsurf -o ${ch}/bound.glb --embed)
expect_run(0 "lod mode" ${DERMIS} export ${ch}/skin.dsurf -o ${ch}/lod.gltf --mode lod --level 3
           --displacement-levels 2)
expect_run(0 "" ${DERMIS} export ${ch}/skin.dsurf -o ${ch}/plain.glb -q)
expect_run(0 "DERMIS_displaced_surface" ${DERMIS} inspect ${ch}/bound.glb)
expect_run(0 "clips" ${DERMIS} inspect ${ch}/lod.gltf)
# Round trip: the embedded .dsurf comes back byte for byte; --refit fits the export again.
expect_run(0 "unchanged" ${DERMIS} fit ${ch}/bound.glb -o ${ch}/again.dsurf)
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${ch}/skin.dsurf ${ch}/again.dsurf
                RESULT_VARIABLE differ)
if(differ)
  message(FATAL_ERROR "fit of an --embed export did not give back the same .dsurf bytes")
endif()
expect_run(0 "" ${DERMIS} fit ${ch}/plain.glb -o ${ch}/refit.dsurf -q)
if(NOT EXISTS ${ch}/refit.dsurf)
  message(FATAL_ERROR "fit of a plain export wrote nothing")
endif()
expect_run(0 "wrote" ${DERMIS} fit ${ch}/bound.glb -o ${ch}/refit2.dsurf --refit)
# A truncated .glb: exit 1 naming it, nothing written.
file(READ ${ch}/bound.glb head LIMIT 300 HEX)
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "\\\\x\\1" head "${head}")
execute_process(COMMAND printf "${head}" OUTPUT_FILE ${ch}/truncated.glb)
expect_run(1 "truncated\\.glb" ${DERMIS} fit ${ch}/truncated.glb -o ${ch}/truncated.dsurf)
expect_run(1 "truncated\\.glb" ${DERMIS} inspect ${ch}/truncated.glb)
if(EXISTS ${ch}/truncated.dsurf)
  message(FATAL_ERROR "a failed fit left truncated.dsurf behind")
endif()
# An export over an existing file replaces it only when it succeeds.
file(WRITE ${ch}/keep.glb "old")
expect_run(1 "bad\\.dsurf" ${DERMIS} export ${WORK}/bad.dsurf -o ${ch}/keep.glb --force)
file(READ ${ch}/keep.glb kept)
if(NOT kept STREQUAL "old")
  message(FATAL_ERROR "a failed export touched an existing output")
endif()

# dermis animate (a pose in world space, OBJ or static glTF) and export --bake-sweep (every clip
# baked into morph targets). The sweep deformer may not be built yet: only then is it skipped.
function(expect_pose deformer expected_text)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(deformer STREQUAL "sweep" AND code EQUAL 1 AND "${err}" MATCHES "deformer is not available")
    message(STATUS "skipped (sweep deformer not available): ${ARGN}")
    set(pose_skipped TRUE PARENT_SCOPE)
    return()
  endif()
  set(pose_skipped FALSE PARENT_SCOPE)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "`${ARGN}` exited ${code}, expected 0\n${out}\n${err}")
  endif()
  string(REGEX MATCH "${expected_text}" found "${out}${err}")
  if(found STREQUAL "")
    message(FATAL_ERROR "`${ARGN}` did not print '${expected_text}':\n${out}\n${err}")
  endif()
endfunction()
foreach(deformer sweep lbs dqs)
  expect_pose(${deformer} "lbs deformer|dqs deformer|sweep deformer" ${DERMIS} animate
              ${ch}/skin.dsurf --time 0.5 --deformer ${deformer} -o ${ch}/posed_${deformer}.obj)
  if(NOT pose_skipped)
    file(STRINGS ${ch}/posed_${deformer}.obj v_lines REGEX "^v ")
    file(STRINGS ${ch}/posed_${deformer}.obj vn_lines REGEX "^vn ")
    list(LENGTH v_lines nv)
    list(LENGTH vn_lines nvn)
    if(NOT nv EQUAL 10 OR NOT nvn EQUAL 10)
      message(FATAL_ERROR "posed_${deformer}.obj: ${nv} v and ${nvn} vn lines, expected 10 each")
    endif()
  endif()
  expect_pose(${deformer} "wrote" ${DERMIS} animate ${ch}/skin.dsurf --clip 0 --time 1.25
              --deformer ${deformer} -o ${ch}/posed_${deformer}.glb)
  if(NOT pose_skipped)
    expect_run(0 "skins +0" ${DERMIS} inspect ${ch}/posed_${deformer}.glb)
  endif()
  expect_pose(${deformer} "morph targets" ${DERMIS} export ${ch}/skin.dsurf
              -o ${ch}/baked_${deformer}.glb --bake-sweep --deformer ${deformer} --fps 10)
  if(NOT pose_skipped)
    expect_run(0 "clips +1" ${DERMIS} inspect ${ch}/baked_${deformer}.glb)
    expect_run(0 "skins +0" ${DERMIS} inspect ${ch}/baked_${deformer}.glb)
  endif()
endforeach()
expect_pose(sweep "lod mode" ${DERMIS} animate ${ch}/skin.dsurf --mode lod --level 2
            --displacement-levels 1 -o ${ch}/posed_lod.gltf)
expect_run(0 "rest pose" ${DERMIS} animate ${ch}/skin.dsurf --clip rest --deformer lbs
           -o ${ch}/rest.obj)
expect_run(0 "" ${DERMIS} export ${ch}/skin.dsurf -o ${ch}/baked_lod.gltf --bake-sweep
           --deformer dqs --mode lod --level 2 --embed -q)
expect_run(0 "DERMIS_displaced_surface" ${DERMIS} inspect ${ch}/baked_lod.gltf)
# Bad requests: exit 1 naming the file, or 2 for usage; nothing written, nothing overwritten.
expect_run(1 "skin\\.dsurf: no clip 'walk'" ${DERMIS} animate ${ch}/skin.dsurf --clip walk
           -o ${ch}/bad_clip.obj)
expect_run(1 "skin\\.dsurf: no clip '7'" ${DERMIS} animate ${ch}/skin.dsurf --clip 7
           -o ${ch}/bad_clip.glb)
expect_run(1 "skin\\.dsurf: --time applies to a clip" ${DERMIS} animate ${ch}/skin.dsurf
           --clip rest --time 1 -o ${ch}/bad_time.obj)
expect_run(1 "missing\\.dsurf" ${DERMIS} animate ${ch}/missing.dsurf -o ${ch}/bad_missing.obj)
expect_run(1 "bad\\.dsurf" ${DERMIS} animate ${WORK}/bad.dsurf -o ${ch}/bad_input.obj)
expect_run(2 "\\.obj, \\.glb or \\.gltf" ${DERMIS} animate ${ch}/skin.dsurf -o ${ch}/bad.ply)
expect_run(2 "seconds >= 0" ${DERMIS} animate ${ch}/skin.dsurf --time -1 -o ${ch}/bad_neg.obj)
expect_run(2 "" ${DERMIS} animate ${ch}/skin.dsurf --deformer cage -o ${ch}/bad_deformer.obj)
expect_run(2 "" ${DERMIS} export ${ch}/skin.dsurf -o ${ch}/bad_fps.glb --bake-sweep --fps 0)
foreach(f bad_clip.obj bad_clip.glb bad_time.obj bad_missing.obj bad_input.obj bad.ply bad_neg.obj
          bad_deformer.obj bad_fps.glb)
  if(EXISTS ${ch}/${f})
    message(FATAL_ERROR "a failed command left ch/${f} behind")
  endif()
endforeach()
file(WRITE ${ch}/keep.obj "old")
expect_run(1 "no clip" ${DERMIS} animate ${ch}/skin.dsurf --clip walk -o ${ch}/keep.obj --force)
file(READ ${ch}/keep.obj kept)
if(NOT kept STREQUAL "old")
  message(FATAL_ERROR "a failed animate touched an existing output")
endif()

expect_run(0 "bound\\.glb: valid" ${DERMIS} validate ${ch}/bound.glb)

# dermis render on the character: a clip contact sheet with the error map and LBS below.
expect_run(0 "8 views" ${DERMIS} render ${ch}/skin.dsurf -o ${ch}/sheet.png --frames 4
           --size 120x120 --heatmap error --compare lbs)
expect_png(${ch}/sheet.png 2000)
# Three rows (sweep, DQS, LBS) of 3 frames, one column per frame; a bad name in the list is a
# usage error.
expect_run(0 "9 views, 192x192" ${DERMIS} render ${ch}/skin.dsurf -o ${ch}/three.png --frames 3
           --size 64x64 --compare dqs,lbs)
expect_png(${ch}/three.png 1000)
expect_run(2 "unknown deformer .cage." ${DERMIS} render ${ch}/skin.dsurf -o ${ch}/bad_three.png
           --frames 3 --compare dqs,cage)
if(EXISTS ${ch}/bad_three.png)
  message(FATAL_ERROR "a refused render wrote ch/bad_three.png")
endif()
expect_run(1 "no clip" ${DERMIS} render ${ch}/skin.dsurf -o ${ch}/x.png --clip walk)
# The character's control edges in lod mode: every part's, `level` segments each.
execute_process(COMMAND ${DERMIS} render ${ch}/skin.dsurf -o ${ch}/wire.png --size 96x96
                --mode lod --level 2 --wireframe RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 0 OR NOT err MATCHES "wireframe: ([0-9]+) segments drawn, ([0-9]+) on the")
  message(FATAL_ERROR "--wireframe on the character (exit ${code}):\n${err}")
endif()
set(wire_drawn "${CMAKE_MATCH_1}")
set(wire_expected "${CMAKE_MATCH_2}")
if(NOT wire_drawn EQUAL wire_expected OR wire_drawn EQUAL 0)
  message(FATAL_ERROR "--wireframe on the character drew ${wire_drawn} segments of "
                      "${wire_expected}:\n${err}")
endif()
expect_png(${ch}/wire.png 1000)
expect_run(2 "--wireframe on a character needs --mode lod" ${DERMIS} render ${ch}/skin.dsurf
           -o ${ch}/x.png --wireframe)
