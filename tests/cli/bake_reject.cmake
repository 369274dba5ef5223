# A bad command line or input file must exit with its documented status (README "Exit status": 1 a
# usage error, 2 a missing or malformed input file; RC, default 2), not crash, not 0, and print one line
# on stderr that starts with "manylights <command>: " (or "manylights: " for an unknown command).
#   cmake -DEXE=path/to/manylights -DARGS="bake|--res|0" [-DRC=1] -P bake_reject.cmake   ("|" separates arguments)
if(NOT DEFINED RC)
  set(RC 2)
endif()
string(REPLACE "|" ";" args "${ARGS}")
list(GET args 0 command)
execute_process(COMMAND ${EXE} ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(STRIP "${err}" err)
if(NOT rc EQUAL RC)
  message(FATAL_ERROR "'${ARGS}' exited ${rc} (expected ${RC}): ${err}")
endif()
# The last line (check vsm and bake print their memory estimate first; help its text).
string(REGEX REPLACE "^.*\n" "" last "${err}")
if(NOT last MATCHES "^manylights( [a-z]+)*: [^\n]+$")
  message(FATAL_ERROR "'${ARGS}': stderr does not end in one line naming the command: '${err}'")
endif()
if(NOT command STREQUAL "help" AND NOT command STREQUAL "nothing" AND NOT command STREQUAL "check" AND NOT last MATCHES "^manylights ${command}")
  message(FATAL_ERROR "'${ARGS}': the line does not name the command ${command}: '${last}'")
endif()
