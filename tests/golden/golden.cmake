# Golden outputs: bakes of every static method and demo frames (static DAG-MH and CPVS, dynamic
# VSM) must stay byte-identical to tests/golden/checksums.txt, so refactors prove "behaviour
# unchanged". The bakes are CPU work (deterministic everywhere); the frames come from the Vulkan device
# (lavapipe: deterministic for one Mesa build and CPU; another CPU or driver may round differently,
# then rerun with -DUPDATE=ON after checking the images).
#   cmake -DEXE=build/manylights -DSOURCE=. -DWORK=build/golden [-DUPDATE=ON] -P tests/golden/golden.cmake
foreach(var EXE SOURCE WORK)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "golden.cmake: -D${var}=... is required")
  endif()
endforeach()
set(list_file ${SOURCE}/tests/golden/checksums.txt)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

function(run)
  execute_process(COMMAND ${ARGN} WORKING_DIRECTORY ${WORK} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "golden.cmake: '${ARGN}' failed (${rc}): ${err}")
  endif()
endfunction()

set(outputs)
foreach(method sm mh mmh dagmh cpvs)
  run(${EXE} bake --method ${method} --res 128 --lights 0-5 --scene-lights 64 --light-dir -0.25,-1,0
      --out ${method}.mlbk --quiet)
  list(APPEND outputs ${method}.mlbk)
  # The same lights without the directional one: spot and point records must stay byte-identical
  # whatever directional bakes change (these checksums predate fitted directional maps).
  run(${EXE} bake --method ${method} --res 128 --lights 0-5 --scene-lights 64 --out spot_${method}.mlbk --quiet)
  list(APPEND outputs spot_${method}.mlbk)
endforeach()
foreach(static dagmh cpvs)
  run(${EXE} demo --static ${static} --static-res 128 --lights 64 --frames 2 --size 320x180 --path drive
      --out demo_${static} --no-stats)
  list(APPEND outputs demo_${static}/frame_0000.png demo_${static}/frame_0001.png)
endforeach()
run(${EXE} demo --lights 64 --frames 2 --size 320x180 --path drive --out demo_plain --no-stats)
list(APPEND outputs demo_plain/frame_0000.png demo_plain/frame_0001.png)

set(text "")
foreach(out ${outputs})
  file(SHA256 ${WORK}/${out} hash)
  string(APPEND text "${hash}  ${out}\n")
endforeach()
if(UPDATE)
  file(WRITE ${list_file} "${text}")
  message(STATUS "golden.cmake: wrote ${list_file}")
  return()
endif()
file(READ ${list_file} expected)
if(NOT text STREQUAL expected)
  message(FATAL_ERROR "golden.cmake: outputs differ from ${list_file}\nexpected:\n${expected}\ngot:\n${text}")
endif()
list(LENGTH outputs n)
message(STATUS "golden.cmake: ${n} outputs byte-identical to ${list_file}")
