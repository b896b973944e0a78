# The tool on the bad inputs of the first fuzzing campaign (issue 19), generated small by
# tests/fuzz/make_regressions.py: each ends in exit 1 with a message naming the file and the
# problem (or a correct result), never a crash, an abort or a half-written output.
# Invoked by ctest with -DDERMIS=<dermis> -DWORK=<scratch> -DSOURCE=<repo> -DDATA=<shared data>.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/out)
find_program(PYTHON3 python3 REQUIRED)
execute_process(COMMAND ${PYTHON3} ${SOURCE}/tests/fuzz/make_regressions.py ${WORK}/in
                RESULT_VARIABLE code)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "make_regressions.py failed")
endif()
set(IN ${WORK}/in)
set(OUT ${WORK}/out)

# expect_run(CODE REGEX CMD...): exit CODE, output matching REGEX, and nothing left in OUT
# after a failed run.
function(expect_run expected_code expected_text)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err
                  TIMEOUT 120)
  if(NOT code EQUAL expected_code)
    message(FATAL_ERROR "`${ARGN}` exited ${code}, expected ${expected_code}\n${out}\n${err}")
  endif()
  if(NOT "${expected_text}" STREQUAL "")
    string(REGEX MATCH "${expected_text}" found "${out}${err}")
    if(found STREQUAL "")
      message(FATAL_ERROR "`${ARGN}` did not print '${expected_text}':\n${out}\n${err}")
    endif()
  endif()
  if(NOT expected_code EQUAL 0)
    file(GLOB left ${OUT}/*)
    if(left)
      message(FATAL_ERROR "`${ARGN}` failed but left ${left}")
    endif()
  endif()
endfunction()

# 1 (with finding 10): validate runs the readers the other commands run. OBJ through our reader.
expect_run(1 "llong_min_index\\.obj:4: relative vertex index -9223372036854775808 points before"
           ${DERMIS} validate ${IN}/obj/llong_min_index.obj)
expect_run(1 "llong_min_index\\.obj:4: relative vertex index" ${DERMIS} tessellate
           ${IN}/obj/llong_min_index.obj -o ${OUT}/x.obj)
expect_run(1 "llong_max_index\\.obj:4: vertex index 9223372036854775807 is too large"
           ${DERMIS} fit ${IN}/obj/llong_max_index.obj -o ${OUT}/x.dsurf)
# 11: coordinates whose products overflow.
foreach(cmd validate tessellate fit)
  set(extra)
  if(cmd STREQUAL tessellate)
    set(extra -o ${OUT}/x.obj)
  elseif(cmd STREQUAL fit)
    set(extra -o ${OUT}/x.dsurf)
  endif()
  expect_run(1 "huge_coords\\.obj: vertex 0 \\(line 1\\) has a coordinate .*magnitude above 1e12" ${DERMIS} ${cmd}
             ${IN}/obj/huge_coords.obj ${extra})
endforeach()
# 7: a face of 20,000 vertices with a repeated corner: found (and in linear time).
expect_run(1 "big_face_repeat\\.obj:20001: the face uses vertex 1 more than once"
           ${DERMIS} tessellate ${IN}/obj/big_face_repeat.obj -o ${OUT}/x.obj)
# 2: deep JSON refused before tinygltf, for every command that reads glTF.
expect_run(1 "deep_extras\\.gltf: JSON nested deeper than 64 levels" ${DERMIS} validate
           ${IN}/gltf/deep_extras.gltf)
expect_run(1 "deep_extras\\.gltf: JSON nested deeper" ${DERMIS} inspect ${IN}/gltf/deep_extras.gltf)
expect_run(1 "deep_extras\\.gltf: JSON nested deeper" ${DERMIS} fit ${IN}/gltf/deep_extras.gltf
           -o ${OUT}/x.dsurf)
# 4: accessors without data: the decoded-bytes budget.
foreach(f unbacked_accessor shared_unbacked_40_primitives)
  expect_run(1 "${f}\\.gltf: /accessors/0: decoding [0-9]+ more values would pass the import budget"
             ${DERMIS} fit ${IN}/gltf/${f}.gltf -o ${OUT}/x.dsurf)
endforeach()
# 6: 4,000 nodes sharing a skinned mesh: valid, and quick.
expect_run(0 "valid" ${DERMIS} validate ${IN}/gltf/instanced_skinned_4k_nodes.gltf)
# 3: bytes that are not UTF-8 in a glTF: refused as invalid JSON, and the JSON report (which
# quotes the bytes) is still printed, with replacement characters, instead of aborting.
expect_run(1 "\"valid\": false" ${DERMIS} validate --json ${IN}/gltf/bad_utf8_name.gltf)
expect_run(1 "ill-formed UTF-8" ${DERMIS} validate --json ${IN}/gltf/bad_utf8_name.gltf)
expect_run(1 "bad_utf8_name\\.gltf: invalid JSON" ${DERMIS} inspect --json ${IN}/gltf/bad_utf8_name.gltf)
# 12: a mesh whose triangles all collapse is listed as not fitted.
expect_run(0 "not fitted: mesh 0 component 0 .*degenerate" ${DERMIS} fit
           ${IN}/gltf/degenerate_mesh.gltf -o ${WORK}/degenerate.dsurf)
# 9, 14: deep Collada and files of no known format are refused before Assimp.
file(READ ${IN}/assimp/deep_nodes.dae dae OFFSET 1)
file(WRITE ${WORK}/deep_nodes.dae "${dae}")
expect_run(1 "deep_nodes\\.dae: XML elements nested deeper than 256 levels" ${DERMIS} validate
           ${WORK}/deep_nodes.dae)
expect_run(1 "deep_nodes\\.dae: XML elements nested deeper" ${DERMIS} fit ${WORK}/deep_nodes.dae
           -o ${OUT}/x.dsurf)
file(WRITE ${WORK}/noise.bin "noise")
expect_run(1 "noise\\.bin: no importer reads '\\.bin' files" ${DERMIS} validate ${WORK}/noise.bin)
# 13: misleading inputs.
expect_run(1 "/dev/zero: is not a regular file" ${DERMIS} validate /dev/zero)
expect_run(1 "/dev/zero: is not a regular file" ${DERMIS} tessellate /dev/zero -o ${OUT}/x.obj)
file(MAKE_DIRECTORY ${WORK}/dir.glb)
expect_run(1 "dir\\.glb: is a directory" ${DERMIS} fit ${WORK}/dir.glb -o ${OUT}/x.dsurf)
expect_run(1 "dir\\.glb: is a directory" ${DERMIS} inspect ${WORK}/dir.glb)
file(WRITE ${WORK}/quad.ply "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
     "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
     "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n")
expect_run(0 "wrote" ${DERMIS} tessellate ${WORK}/quad.ply -o ${WORK}/quad_ply.obj --level 2)
expect_run(1 "tessellate reads a control mesh \\(\\.obj, \\.ply\\) or a \\.dsurf, not '\\.gltf'"
           ${DERMIS} tessellate ${IN}/gltf/bad_utf8_name.gltf -o ${OUT}/x.obj)
# 3: a tessellation larger than memory allows: exit 1 with a message, not an abort, also under
# an address-space limit (where std::bad_alloc used to abort the tool).
# The CLI takes --level 1..128 (one range in every command), so the large tessellation is a
# 64 x 64 grid of quads at level 128: about 9 GiB, above the fixed limit of 8 GiB.
set(grid "")
foreach(j RANGE 64)
  foreach(i RANGE 64)
    string(APPEND grid "v ${i} ${j} 0\n")
  endforeach()
endforeach()
foreach(j RANGE 63)
  foreach(i RANGE 63)
    math(EXPR a "${j} * 65 + ${i} + 1")
    math(EXPR b "${a} + 1")
    math(EXPR c "${a} + 66")
    math(EXPR d "${a} + 65")
    string(APPEND grid "f ${a} ${b} ${c} ${d}\n")
  endforeach()
endforeach()
file(WRITE ${WORK}/grid64.obj "${grid}")
expect_run(1 "tessellation at level 128 of 4096 faces needs about [0-9]+ MiB.*lower --level"
           ${DERMIS} tessellate ${WORK}/grid64.obj --level 128 -o ${OUT}/x.obj)
find_program(SH sh)
if(SH AND NOT SANITIZE)
  expect_run(1 "lower --level" ${SH} -c
             "ulimit -v 4000000 && exec '${DERMIS}' tessellate '${WORK}/grid64.obj' --level 64 -o '${OUT}/x.obj'")
endif()
# Issue 17: runtime archives, damaged (make_regressions.py ARCHIVE): refused by the reader,
# naming the file and what is wrong; an archive without its source cannot be exported or
# repacked with its source.
expect_run(0 "wrote" ${DERMIS} pack ${FIXTURES}/cylinders.dsurf -o ${WORK}/cyl.runtime.dsurf
           --quantize-displacements)
execute_process(COMMAND ${PYTHON3} ${SOURCE}/tests/fuzz/make_regressions.py ${WORK}/archive
                        ${WORK}/cyl.runtime.dsurf RESULT_VARIABLE code)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "make_regressions.py ARCHIVE failed")
endif()
set(A ${WORK}/archive/dsurf)
expect_run(1 "archive_truncated\\.dsurf: (part [0-9]+: )?truncated or corrupt file" ${DERMIS} validate
           ${A}/archive_truncated.dsurf)
expect_run(1 "archive_node_count\\.dsurf: truncated or corrupt file: nodes needs" ${DERMIS}
           inspect ${A}/archive_node_count.dsurf)
expect_run(1 "archive_parent_out_of_range\\.dsurf: node 0: parent 100000 out of range"
           ${DERMIS} validate ${A}/archive_parent_out_of_range.dsurf)
expect_run(1 "archive_joint_out_of_range\\.dsurf: skin 0: joint node 100000 out of range"
           ${DERMIS} pack ${A}/archive_joint_out_of_range.dsurf -o ${OUT}/x.dsurf)
expect_run(1 "cyl\\.runtime\\.dsurf: a runtime archive without its source asset" ${DERMIS}
           export ${WORK}/cyl.runtime.dsurf -o ${OUT}/x.glb)
expect_run(1 "--keep-source needs the fitted character" ${DERMIS} pack
           ${WORK}/cyl.runtime.dsurf -o ${OUT}/x.dsurf --keep-source)
expect_run(0 "version 4, .*runtime archive +16-bit displacements" ${DERMIS} inspect
           ${WORK}/cyl.runtime.dsurf)

# 3: a file name that is not UTF-8 (validate --json and fit --report print and write it).
set(rigged ${DATA}/gltf/RiggedSimple.glb)
if(EXISTS ${rigged})
  string(ASCII 255 ff)
  set(bad_name "${WORK}/bad${ff}.glb")
  file(COPY_FILE ${rigged} ${bad_name})
  expect_run(0 "\"valid\": true" ${DERMIS} validate --json ${bad_name})
  expect_run(0 "" ${DERMIS} fit ${bad_name} -o ${WORK}/bad_name.dsurf --report ${WORK}/bad_name.json -q)
  if(NOT EXISTS ${WORK}/bad_name.json)
    message(FATAL_ERROR "fit --report with a non-UTF-8 input name wrote no report")
  endif()
else()
  message(STATUS "SKIPPED the non-UTF-8 file name case: ${rigged} is absent")
endif()
