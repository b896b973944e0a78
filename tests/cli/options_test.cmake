# One set of options (issue 20): every subcommand that has an option accepts exactly the
# values the others accept, and the defaults of --mode, --level and --displacement-levels are
# the same everywhere. A value is "rejected" when the command exits with the usage status 2;
# the input does not exist, so an accepted value ends in exit 1 (missing file) instead.
#   cmake -DDERMIS=<dermis> -DWORK=<dir> -P options_test.cmake
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

set(commands "tessellate;export;animate;render;fit;pack")
set(out_tessellate x.obj)
set(out_export x.glb)
set(out_animate x.glb)
set(out_render x.png)
set(out_fit x.dsurf)
set(out_pack x.dsurf)

# option -> values to try (both sides of every bound, and junk).
set(values_--level "0;1;6;128;129;x")
set(values_--displacement-levels "-2;-1;0;13;14;x")
set(values_--mode "bound;lod;x")
set(values_--threads "-1;0;1024;1025")
set(values_--fps "0;0.001;1000;1001")
set(values_--deformer "lbs;dqs;sweep;x")

foreach(cmd ${commands})
  execute_process(COMMAND ${DERMIS} ${cmd} --help OUTPUT_VARIABLE help_${cmd} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "dermis ${cmd} --help failed")
  endif()
endforeach()

set(failures "")
foreach(option --level --displacement-levels --mode --threads --fps --deformer)
  foreach(value ${values_${option}})
    set(verdicts "")
    foreach(cmd ${commands})
      string(FIND "${help_${cmd}}" "${option} " has)
      if(has EQUAL -1)
        continue()
      endif()
      execute_process(COMMAND ${DERMIS} ${cmd} ${WORK}/missing.dsurf -o ${WORK}/${out_${cmd}}
                              ${option} ${value}
                      RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
      if(rc EQUAL 2)
        list(APPEND verdicts "${cmd}:rejects")
      else()
        list(APPEND verdicts "${cmd}:accepts")
      endif()
    endforeach()
    string(FIND "${verdicts}" "rejects" r)
    string(FIND "${verdicts}" "accepts" a)
    if(NOT r EQUAL -1 AND NOT a EQUAL -1)
      string(APPEND failures "  ${option} ${value}: ${verdicts}\n")
    endif()
  endforeach()
endforeach()

# The same defaults, as --help shows them (CLI11 prints "=DEFAULT" after the type).
foreach(option "--mode TEXT:{bound,lod}=bound" "--level INT:INT in [1 - 128]=6"
               "--displacement-levels INT:INT in [-1 - 13]=-1")
  string(REGEX MATCH "^[^ ]+" name "${option}")
  foreach(cmd ${commands})
    string(FIND "${help_${cmd}}" "${name} " has)
    if(has EQUAL -1)
      continue()
    endif()
    string(FIND "${help_${cmd}}" "${option}" same)
    if(same EQUAL -1)
      string(APPEND failures "  dermis ${cmd}: ${name} is not '${option}'\n")
    endif()
  endforeach()
endforeach()

if(failures)
  message(FATAL_ERROR "options that disagree between commands:\n${failures}")
endif()
message(STATUS "every shared option accepts the same values with the same defaults")
