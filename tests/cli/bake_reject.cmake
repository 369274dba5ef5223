# A bad command line must exit with status 2 (not crash, not 0) and print one line on stderr that starts
# with "manylights <command>: ".
#   cmake -DEXE=path/to/manylights -DARGS="bake|--res|0" -P bake_reject.cmake   ("|" separates arguments)
string(REPLACE "|" ";" args "${ARGS}")
list(GET args 0 command)
execute_process(COMMAND ${EXE} ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(STRIP "${err}" err)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "'${ARGS}' exited ${rc} (expected 2): ${err}")
endif()
if(NOT err MATCHES "^manylights ${command}: [^\n]+$")
  message(FATAL_ERROR "'${ARGS}': stderr is not one line naming the command: '${err}'")
endif()
