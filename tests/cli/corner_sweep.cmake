# `demo` at every corner of its accepted --vsm-res / --vsm-page / --size / --lights ranges
# ends with exit 0, or exit 1 and one refusal line naming the setting and the limit; never a signal
# (an abort on a device limit used to end 16384^2 maps at 256 lights with SIGABRT).
#   cmake -DEXE=path/to/manylights -DOUT=dir [-DSIZES=1x1;16384x16384] -P corner_sweep.cmake
# --frames 1, --no-stats; the size corner 16384x16384 is refused on lavapipe (cluster bounds past its
# 128 MiB storage buffer range) before the scene is bound; on a device that holds it, it renders one
# 268 M pixel frame (minutes on a CPU device; the default list keeps it, since the refusal is fast here).
if(NOT SIZES)
  set(SIZES "1x1;16384x16384")
endif()
file(MAKE_DIRECTORY ${OUT})
set(runs 0)
foreach(res 256 16384)
  foreach(page 32 128)
    foreach(size ${SIZES})
      foreach(lights 1 4096)
        set(args demo --vsm-res ${res} --vsm-page ${page} --size ${size} --lights ${lights} --frames 1
                 --no-stats --out ${OUT}/corner)
        string(TIMESTAMP t0 "%s")
        execute_process(COMMAND ${EXE} ${args} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
        string(TIMESTAMP t1 "%s")
        math(EXPR seconds "${t1} - ${t0}")
        string(STRIP "${err}" err)
        string(REGEX REPLACE "^.*\n" "" last "${err}")
        message(STATUS "vsm-res ${res} vsm-page ${page} size ${size} lights ${lights}: exit ${rc}, ${seconds} s: ${last}")
        if(rc STREQUAL "0")
        elseif(rc STREQUAL "1")
          if(NOT last MATCHES "^manylights demo: [^\n]+$")
            message(FATAL_ERROR "${args}: exit 1 without a one-line refusal: '${err}'")
          endif()
        else()
          message(FATAL_ERROR "${args}: exit '${rc}' (a signal or a failed run): '${err}'")
        endif()
        math(EXPR runs "${runs} + 1")
      endforeach()
    endforeach()
  endforeach()
endforeach()
message(STATUS "${runs} corners: each exit 0 or a one-line refusal")
