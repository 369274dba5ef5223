# PublicAbiLayout: runs the two builds of tests/abi/abi_host.cpp (plain, and with the GLM configuration
# macros) and fails unless both succeed and print the same layout and results ("#" lines are the build's
# own notes and are not compared). The forced build must see glm's vec3 widened, or it tests nothing.
#   cmake -DPLAIN=<abi_host_plain> -DFORCED=<abi_host_glm_forced> -P abi_layout.cmake
foreach(variant PLAIN FORCED)
  execute_process(COMMAND ${${variant}} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${${variant}} failed (${rc}):\n${out}\n${err}")
  endif()
  set(full_${variant} "${out}")
  string(REGEX REPLACE "#[^\n]*\n" "" out "${out}")
  set(out_${variant} "${out}")
endforeach()
if(NOT full_FORCED MATCHES "# glm aligned: sizeof\\(glm::vec3\\) 16")
  message(FATAL_ERROR "the forced build's glm::vec3 is not 16 bytes: the GLM macros did not take effect\n${full_FORCED}")
endif()
if(NOT out_PLAIN STREQUAL out_FORCED)
  message(FATAL_ERROR "the public API differs with the host's GLM definitions:\n--- plain\n${out_PLAIN}\n--- forced\n${out_FORCED}")
endif()
message("${out_PLAIN}")
